#!/usr/bin/env bash
# Installs, from Debian's/Ubuntu's packages, whatever tear needs to build that is missing, and
# usd-core (USD's Python bindings, from PyPI) in .venv/ for the test that reads tear's USD layers.
# Idempotent: when everything is present it does nothing (and does not touch the network).
# The CUDA toolkit is optional and not installed here: with nvcc on PATH (or at
# /usr/local/cuda/bin) the build adds the CUDA backend, without it the build is CPU-only and uses
# libthrust-dev.
set -euo pipefail
cd "$(dirname "$0")/.."
# assimp-testmodels: meshes written by other tools, read by the test suite.
# python3, python3-venv: the virtual environment usd-core goes in (Debian's Python refuses pip
# installs outside one).
packages=(cmake ninja-build g++ pkg-config libassimp-dev libtinyobjloader-dev libtinygltf-dev libeigen3-dev libcli11-dev
  nlohmann-json3-dev catch2 libthrust-dev assimp-testmodels python3 python3-venv)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all build dependencies are present"
else
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# usd-core, pinned, in a virtual environment of the repository (.venv/, ignored by git) made with
# the system's Python: no root needed, nothing installed outside the work tree. The USD layer test
# (tests/check_usd_layer.py) runs with .venv/bin/python. Where no wheel fits this machine the
# test is skipped with a message; CI (TEAR_REQUIRE_USD=1) fails instead.
usd_core="usd-core==26.11"
venv=.venv
if "$venv/bin/python" -c 'import pxr.Usd' >/dev/null 2>&1; then
  echo "install-deps: $usd_core is present in $venv"
  exit 0
fi
echo "install-deps: installing $usd_core in $venv"
if /usr/bin/python3 -m venv "$venv" && "$venv/bin/python" -m pip install -q --disable-pip-version-check "$usd_core" &&
  "$venv/bin/python" -c 'import pxr.Usd'; then
  echo "install-deps: $usd_core installed in $venv"
else
  echo "install-deps: could not install $usd_core in $venv: the USD layer test will be skipped" >&2
fi
