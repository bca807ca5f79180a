#!/usr/bin/env bash
# Installs what is missing (Debian 12 packages only) and builds subsplat into build/.
# Run as root (or with sudo available). Idempotent.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(blender cmake g++ pkg-config libglm-dev libepoxy-dev libegl-dev libgl-dev libopenimageio-dev
          openimageio-tools libembree-dev googletest libgtest-dev python3-numpy python3-matplotlib xvfb zip
          clang libclang-rt-14-dev python3-venv)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# Blender 4.2 LTS, 4.5 LTS and 5.x as the `bpy` module, one virtual environment each under build/
# (scripts/setup_bpy.sh; installed once, then kept). They download and unpack (at nice 19) while
# the library compiles: a fresh clone's set-up waited for them after the build before.
mkdir -p build
bash scripts/setup_bpy.sh &
bpy_setup=$!

cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j"$(nproc)"
wait "$bpy_setup"

# The example SubEdit materials (example_blends/make_materials.py), made where missing.
BLENDER_USER_SCRIPTS="$PWD/build/scripts" blender -b --factory-startup --addons subsplat \
  --python example_blends/make_materials.py -- --missing
