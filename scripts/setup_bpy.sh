#!/usr/bin/env bash
# One virtual environment per Blender release of scripts/bpy_versions.txt, build/bpy-<version>/,
# with that release's `bpy` module from PyPI (about 1 GB each, installed once; docs/VERSIONS.md).
# Idempotent: an environment whose bpy imports as the pinned version is left as it is. The missing
# ones are installed side by side (unpacking is most of the time).
# Debian's Python 3.11 (the wheels are cp311 only), its venv module (python3-venv: scripts/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${SUBSPLAT_BPY_PYTHON:-/usr/bin/python3}
# The NumPy every pinned release bundles with Blender itself (4.5 and 5.0's wheels require <2).
NUMPY=1.26.4
export PIP_DISABLE_PIP_VERSION_CHECK=1

install() {
  local version=$1 venv=build/bpy-$1
  rm -rf "$venv"
  "$PYTHON" -m venv "$venv"
  nice -n 19 "$venv/bin/python" -m pip install -q "bpy==$version" "numpy==$NUMPY" > "$venv.log" 2>&1 ||
    { cat "$venv.log"; return 1; }
  "$venv/bin/python" -c 'import bpy; print("bpy", bpy.app.version_string)' 2>/dev/null
}

pids=()
for version in $(grep -v '^#' scripts/bpy_versions.txt); do
  venv="build/bpy-$version"
  if [ -x "$venv/bin/python" ] &&
     [ "$("$venv/bin/python" -c 'import bpy; print(bpy.app.version_string.split()[0])' 2>/dev/null)" = \
       "$version" ]; then
    continue
  fi
  echo "Installing bpy $version into $venv"
  mkdir -p build
  install "$version" &
  pids+=($!)
done
status=0
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
exit $status
