#!/usr/bin/env bash
# PRECOMPUTED on scenes none of its constants were chosen on (docs/PRECOMPUTED.md, "Held-out
# scenes"): the procedural test set of docs/AUTO.md (random shapes, sizes, media, lights and views;
# native testing::proceduralScene), each rendered by FULL and PRECOMPUTED (precomputed, then relit
# after the light turned: --warmup 1) and by REFERENCE, at 120 x 90. PRECOMPUTED's crease angle,
# small-object taps and memory rules were chosen on the examples; the test set was never looked at
# for them. Prints the table (bench/precomputed_heldout.py) and writes OUT/table.md, OUT/scenes.txt and
# each scene's OUT/test_<i>.json and .log.
#   bash bench/precomputed_heldout.sh [OUT (default bench/results/precomputed_heldout)] [SCENES (default 12)]
# SET=calibration runs the calibration set instead (where PRECOMPUTED's rules may be looked at and
# chosen; the test set is where they are checked).
# About 8 minutes on 2 cores for 12 scenes (2026-12-07; 15 at stop 48, before FULL got faster).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-bench/results/precomputed_heldout}
count=${2:-12}
python=${PYTHON:-python3}
mkdir -p "$out"
[ -d build ] || bash scripts/setup.sh
cmake --build build -j"$(nproc)" --target subsplat_auto_sets subsplat_replay > /dev/null
scenes=$(mktemp -d)
trap 'rm -rf "$scenes"' EXIT
build/native/subsplat_auto_sets --set "${SET:-test}" --count "$count" --size 120x90 --save "$scenes" > "$out/scenes.txt"
for scene in "$scenes"/*.ssscene; do
  name=$(basename "$scene" .ssscene)
  # One scene at a time: a scene that fails is recorded (its log), not the end of the run.
  build/native/subsplat_replay --methods FULL,PRECOMPUTED --runs 1 --warmup 1 --size 120x90 \
    --reference-samples 50000 --json "$out/$name.json" "$scene" > "$out/$name.log" 2>&1 ||
    echo "$name failed: $(grep -m1 -i 'error\|ssRender' "$out/$name.log")"
done
"$python" bench/precomputed_heldout.py "$out" | tee "$out/table.md"
