#!/usr/bin/env bash
# The automatic resolution on procedural scenes (docs/AUTO.md, "Held-out scenes"): the calibration
# set at every rung (native subsplat_auto_sets --rungs), the rule's fit on it (bench/auto_fit.py),
# then the test set, disjoint from it, under AUTO. Each scene is 120 x 90; about 30 minutes on
# 2 cores (2026-12-04). The test set's images (MULTIRES at AUTO's resolution, at the reference's,
# and their difference) go to OUT/images/; `python3 bench/auto_tables.py OUT` prints the tables.
# CI runs the first two test scenes at 64 x 48 (native AutoQualityHeldOut.*).
#   bash bench/auto_sets.sh [OUT (default bench/results/auto_sets)] [SCENES per set (default 24)]
# Exit status 3 when a test scene misses the target the library said it could meet (today: 13 of 24).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-bench/results/auto_sets}
count=${2:-24}
mkdir -p "$out"
[ -d build ] || bash scripts/setup.sh
cmake --build build -j"$(nproc)" --target subsplat_auto_sets > /dev/null
tool=build/native/subsplat_auto_sets
"$tool" --set calibration --count "$count" --rungs --json "$out/calibration.json" | tee "$out/calibration.log"
python3 bench/auto_fit.py "$out/calibration.json" | tee "$out/fit.txt"
status=0
"$tool" --set test --count "$count" --json "$out/test.json" --images "$out/images" | tee "$out/test.log" || status=$?
exit "$status"
