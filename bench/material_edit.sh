#!/bin/bash
# MATERIAL_EDIT against FULL on procedural scenes (docs/MATERIAL_EDIT.md), about 10 minutes on 2 cores:
# the calibration set (which chose the precomputation's constants) and the test set (never looked at
# while choosing them), at a fixed irradiance resolution of 256 (the transport's own error) and at the
# automatic one (where FULL of the edited material may choose another resolution), then the tables.
#   bash bench/material_edit.sh [build]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=bench/results/material_edit
mkdir -p "$out"
cmake --build "$build" -j"$(nproc)" --target subsplat_material_edit > /dev/null
tool="$build/native/subsplat_material_edit"
"$tool" --set calibration --count 8 --size 120x90 --resolution 256 > "$out/calibration_256.json"
"$tool" --set test --count 8 --size 120x90 --resolution 256 > "$out/test_256.json"
"$tool" --set test --count 8 --size 120x90 > "$out/test_auto.json"
python3 bench/material_edit_tables.py "$out"
