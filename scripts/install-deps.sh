#!/usr/bin/env bash
# Installs, from Debian's/Ubuntu's packages, whatever tear needs to build that is missing.
# Idempotent: when everything is present it does nothing (and does not touch the network).
# The CUDA toolkit is optional and not installed here: with nvcc on PATH (or at
# /usr/local/cuda/bin) the build adds the CUDA backend, without it the build is CPU-only and uses
# libthrust-dev.
set -euo pipefail
# assimp-testmodels: meshes written by other tools, read by the test suite.
packages=(cmake ninja-build g++ pkg-config libassimp-dev libtinyobjloader-dev libtinygltf-dev libeigen3-dev libcli11-dev nlohmann-json3-dev catch2 libthrust-dev
  assimp-testmodels)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all build dependencies are present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
