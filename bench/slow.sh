#!/usr/bin/env bash
# The slow tier (docs/CI.md): what CI runs reduced, at full size, and the full sweeps. About
# two and a half hours on 2 cores (bench/physical.py alone about 25 minutes, bench/auto_sets.sh 30):
#   - the automatic resolution on the calibration and held-out procedural scenes (CI: two test scenes);
#   - PRECOMPUTED against REFERENCE and FULL on 12 held-out procedural scenes
#     (bench/precomputed_heldout.sh, about 15 minutes; CI: the rod alone);
#   - the soak: 1000 renders in one Blender process (CI: 300);
#   - the AUTO test of the trade-off on every example (CI: two) and the full sweep of
#     bench/tradeoff.py at 10 % (docs/TRADEOFF.md's command);
#   - the stability test over 60 frames of the moving light and 5 of the deformation (CI: 20 and 3),
#     and the full sweep of bench/stability.py with the flicker (docs/STABILITY.md's command);
#   - every example end to end at its full size (CI: 25 %);
#   - the model against physical truth, every case (bench/physical.py; CI: tests/blender/
#     test_physical.py renders two cases and checks the committed figures), each profile model
#     against the committed truths (bench/model.py, about 35 minutes; CI: test_physical.py renders
#     two cases under TABULATED), and the truth harness's own check (bench/truth_halfspace.py; CI:
#     test_truth.py renders one case).
# Each is a CTest test labelled slow (tests/CMakeLists.txt), run one at a time so that their
# figures are not shared with other work. Results: the figures each prints, in build/slow.log;
# the documents and images of the sweeps (TRADEOFF.md, STABILITY.md, images/) in
# build/test_output/slow_tradeoff_sweep/ and build/test_output/slow_stability_sweep/, to copy into
# docs/ when they are to replace its figures.
#   bash bench/slow.sh [ctest options, e.g. -R soak]
set -euo pipefail
cd "$(dirname "$0")/.."
[ -d build ] || bash scripts/setup.sh
cmake --build build -j"$(nproc)"
cd build
ctest -L '^slow$' -V "$@" 2>&1 | tee slow.log
