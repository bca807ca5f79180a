#!/usr/bin/env bash
# What the TABULATED model's forward shift costs FULL on the examples, on this machine:
#   bash bench/forward_shift_cost.sh [OUT_DIR]
# exports the examples with every coefficient material under TABULATED into build/bench_tabulated/
# (once: `bench/methods.py --export-only --profile-model TABULATED`), then replays each scene with
# FULL, the shift off and on in turn (`subsplat_replay --forward-shift off|on`), two rounds, RUNS
# renders each after a warm-up, and prints per scene the medians' frame times, their ratio, the
# splatting stage's ratio and the fragment invocations (docs/BENCHMARKS.md, "The forward shift").
# Environment: SCENES (default: finger_pose skin_suzanne marble_pieces wax_jade), SIZE (default
# 400x300), RUNS (default 2). OUT_DIR (default build/forward_shift_cost) keeps each replay's JSON
# and summary.md.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/forward_shift_cost}
scenes=${SCENES:-finger_pose skin_suzanne marble_pieces wax_jade}
mkdir -p "$out"
if [ ! -f build/bench_tabulated/finger_pose.ssscene ]; then
  BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat --python bench/methods.py -- \
    --export-only --profile-model TABULATED --directory build/bench_tabulated >/dev/null
fi
for s in $scenes; do
  for round in 1 2; do
    for shift in off on; do
      build/native/subsplat_replay --methods FULL --runs "${RUNS:-2}" --warmup 1 --size "${SIZE:-400x300}" \
        --no-reference --forward-shift "$shift" --json "$out/${s}_${shift}_${round}.json" \
        "build/bench_tabulated/$s.ssscene" >/dev/null
    done
  done
done
python3 - "$out" $scenes <<'PY' | tee "$out/summary.md"
import json, statistics, sys
out, scenes = sys.argv[1], sys.argv[2:]
print("| scene | FULL, shift off (ms, two rounds) | FULL, shift on (ms) | frame time on / off | splatting on / off | fragments off | fragments on / off |")
print("|---|---|---|---|---|---|---|")
for s in scenes:
    runs = {}
    for shift in ("off", "on"):
        runs[shift] = [json.load(open(f"{out}/{s}_{shift}_{r}.json"))["scenes"][0]["methods"][0] for r in (1, 2)]
    frame = {k: [m["median_frame_ms"] for m in v] for k, v in runs.items()}
    splat = {k: [m["stage_ms"]["splatting"] for m in v] for k, v in runs.items()}
    frags = {k: v[0]["fragment_invocations"]["total"] for k, v in runs.items()}
    print(f"| {s} | {' / '.join(f'{x:.0f}' for x in frame['off'])} | {' / '.join(f'{x:.0f}' for x in frame['on'])} | "
          f"{statistics.median(frame['on']) / statistics.median(frame['off']):.2f} | "
          f"{statistics.median(splat['on']) / statistics.median(splat['off']):.2f} | {frags['off'] / 1e6:.1f} M | "
          f"{frags['on'] / frags['off']:.3f} |")
PY
