#!/usr/bin/env bash
# Installs Blender as a Python module (bpy, pinned, from PyPI) in a virtual environment of the
# repository, .venv-blender/ (ignored by git), for the ctest that imports tear's frames and USD
# layer into Blender (tests/blender_import_check.py). Not needed to build or use tear, and not run by
# scripts/install-deps.sh: the wheel is about 375 MB. CI runs it (.ci/run).
#
# bpy 5.0.1 publishes wheels for CPython 3.11 only, so this needs a python3.11 on PATH (Debian 12's
# python3 is one). The module links to X11's and OpenGL's client libraries (it opens no display);
# those missing are installed from Debian's/Ubuntu's packages through apt-get, with sudo when not
# root. Idempotent: when .venv-blender/ imports bpy it does nothing (and does not touch the network).
#
# Then: TEAR_BLENDER_PYTHON=$PWD/.venv-blender/bin/python ctest --test-dir build -R blender
set -euo pipefail
cd "$(dirname "$0")/.."
bpy="bpy==5.0.1"
venv=.venv-blender
if "$venv/bin/python" -c 'import bpy' >/dev/null 2>&1; then
  echo "install-blender: $bpy is present in $venv"
  exit 0
fi

# The shared libraries bpy's module links to outside its wheel, and the venv module.
packages=(libx11-6 libxext6 libxrender1 libxfixes3 libxi6 libxkbcommon0 libsm6 libgl1 python3-venv)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-blender: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

python=""
for candidate in python3.11 python3; do
  if command -v "$candidate" >/dev/null &&
    "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
    python=$(command -v "$candidate")
    break
  fi
done
if [ -z "$python" ]; then
  echo "install-blender: $bpy has wheels for CPython 3.11 only, and there is no python3.11 on PATH" >&2
  exit 1
fi
# A venv of another Python (made before, by hand) is made again.
if [ -x "$venv/bin/python" ] && ! "$venv/bin/python" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))'; then
  rm -rf "$venv"
fi
[ -x "$venv/bin/python" ] || "$python" -m venv "$venv"
echo "install-blender: installing $bpy in $venv (with $python)"
"$venv/bin/python" -m pip install -q --disable-pip-version-check "$bpy"
"$venv/bin/python" -c 'import bpy; print("install-blender: Blender " + bpy.app.version_string + " imports in '"$venv"'")'
