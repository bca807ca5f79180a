#!/usr/bin/env bash
# One virtual environment per Blender release of scripts/bpy_versions.txt, build/bpy-<version>/,
# with that release's `bpy` module from PyPI (about 1 GB each, installed once; docs/VERSIONS.md).
# Idempotent: an environment whose bpy imports as the pinned version is left as it is.
# Debian's Python 3.11 (the wheels are cp311 only), its venv module (python3-venv: scripts/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${SUBSPLAT_BPY_PYTHON:-/usr/bin/python3}
# The NumPy every pinned release bundles with Blender itself (4.5 and 5.0's wheels require <2).
NUMPY=1.26.4
export PIP_DISABLE_PIP_VERSION_CHECK=1
for version in $(grep -v '^#' scripts/bpy_versions.txt); do
  venv="build/bpy-$version"
  if [ -x "$venv/bin/python" ] &&
     [ "$("$venv/bin/python" -c 'import bpy; print(bpy.app.version_string.split()[0])' 2>/dev/null)" = "$version" ]; then
    continue
  fi
  echo "Installing bpy $version into $venv"
  rm -rf "$venv"
  "$PYTHON" -m venv "$venv"
  nice -n 19 "$venv/bin/python" -m pip install -q "bpy==$version" "numpy==$NUMPY"
  "$venv/bin/python" -c 'import bpy; print("bpy", bpy.app.version_string)'
done
