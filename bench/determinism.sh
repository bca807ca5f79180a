#!/usr/bin/env bash
# Determinism across processes (docs/ANIMATION.md): the same frame rendered by many processes at
# once, counted by distinct images. Renders the candle's frame 33 as test_animation.py does (25 %,
# 32-bit EXR, irradiance 256, one sample), keeps what the library was given (the scene file), then
# replays it with FULL in 5 processes at a time, ROUNDS times (default 30), both cores busy as in
# CI. Prints "<count> <md5>" per distinct image; one line is the property. About 12 s a round on 2 cores.
#   bash bench/determinism.sh [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-30}
[ -x build/native/subsplat_replay ] || { echo "build first (README.md)" >&2; exit 2; }
out=build/determinism
rm -rf "$out" && mkdir -p "$out"
pin="import sys; sys.path.insert(0, 'tests'); from subsplat_testing import one_sample; one_sample.pin()"
small="import bpy; s = bpy.context.scene; s.render.resolution_percentage = 25; \
s.render.image_settings.file_format = 'OPEN_EXR'; s.render.image_settings.color_depth = '32'; \
s.subsplat.irradiance_resolution = 256; s.subsplat.scene_file = '$PWD/$out/candle_####.scene'"
BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat --python-expr "$pin" \
  example_blends/candle_twist.blend --python-expr "$small" -E SUBSPLAT -o "$PWD/$out/candle_" -f 33 \
  > "$out/blender.log" 2>&1 || { tail -20 "$out/blender.log" >&2; exit 1; }
scene="$out/candle_0033.scene"
[ -f "$scene" ] || { echo "no scene file written: $out/blender.log" >&2; exit 1; }
for round in $(seq 1 "$rounds"); do
  for i in 1 2 3 4 5; do
    mkdir -p "$out/$round-$i"
    build/native/subsplat_replay "$scene" --methods FULL --runs 1 --no-reference --images "$out/$round-$i" \
      > "$out/$round-$i.log" 2>&1 &
  done
  wait
done
md5sum "$out"/*/*FULL.pfm | awk '{print $1}' | sort | uniq -c
