#!/usr/bin/env bash
# Installs, from Debian's/Ubuntu's packages, whatever tear needs to build that is missing, and, from
# PyPI in .venv/: usd-core (USD's Python bindings) for the test that reads tear's USD layers,
# nanobind for the Python module `tear` and NumPy for its arrays.
# Idempotent: when everything is present it does nothing (and does not touch the network).
# The CUDA toolkit is optional and not installed here: with nvcc on PATH (or at
# /usr/local/cuda/bin) the build adds the CUDA backend, without it the build is CPU-only and uses
# libthrust-dev.
set -euo pipefail
cd "$(dirname "$0")/.."
# assimp-testmodels: meshes written by other tools, read by the test suite.
# python3, python3-venv: the virtual environment usd-core and nanobind go in (Debian's Python
# refuses pip installs outside one); python3-dev: the headers the Python module is built against.
packages=(cmake ninja-build g++ pkg-config libassimp-dev libtinyobjloader-dev libtinygltf-dev libstb-dev libeigen3-dev libcli11-dev
  nlohmann-json3-dev catch2 libthrust-dev assimp-testmodels python3 python3-venv python3-dev)
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

# usd-core, nanobind and NumPy, pinned, in a virtual environment of the repository (.venv/, ignored
# by git) made with the system's Python: no root needed, nothing installed outside the work tree.
# The USD layer test (tests/check_usd_layer.py) runs with .venv/bin/python; CMake builds the Python
# module with .venv/bin/python's nanobind (python/CMakeLists.txt). Where no wheel fits this machine
# the tests that need them are skipped with a message; CI (TEAR_REQUIRE_USD=1,
# TEAR_REQUIRE_PYTHON=1) fails instead.
usd_core="usd-core==26.11"
python_packages=("nanobind==2.9.2" "numpy==2.4.6")
venv=.venv
if "$venv/bin/python" -c 'import pxr.Usd, nanobind, numpy' >/dev/null 2>&1; then
  echo "install-deps: $usd_core ${python_packages[*]} are present in $venv"
  exit 0
fi
[ -x "$venv/bin/python" ] || /usr/bin/python3 -m venv "$venv" || true
echo "install-deps: installing ${python_packages[*]} in $venv"
if "$venv/bin/python" -m pip install -q --disable-pip-version-check "${python_packages[@]}" &&
  "$venv/bin/python" -c 'import nanobind, numpy'; then
  echo "install-deps: ${python_packages[*]} installed in $venv"
else
  echo "install-deps: could not install ${python_packages[*]} in $venv: the Python module will not be built" >&2
fi
if "$venv/bin/python" -c 'import pxr.Usd' >/dev/null 2>&1; then
  echo "install-deps: $usd_core is present in $venv"
  exit 0
fi
echo "install-deps: installing $usd_core in $venv"
if "$venv/bin/python" -m pip install -q --disable-pip-version-check "$usd_core" &&
  "$venv/bin/python" -c 'import pxr.Usd'; then
  echo "install-deps: $usd_core installed in $venv"
else
  echo "install-deps: could not install $usd_core in $venv: the USD layer test will be skipped" >&2
fi
