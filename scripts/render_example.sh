#!/usr/bin/env bash
# Set-up, build, then render the example scenes with `blender -b` into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
mkdir -p out
for scene in example_blends/*.blend; do
  name=$(basename "$scene" .blend)
  BLENDER_USER_SCRIPTS="$PWD/build/scripts" blender -b --factory-startup --addons subsplat "$scene" \
    -E SUBSPLAT -o "$PWD/out/${name}_" -F PNG -f 1
  echo "Rendered $PWD/out/${name}_0001.png"
done
