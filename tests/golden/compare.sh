#!/usr/bin/env bash
# Compares every EXR of DIR_A with the one of the same name in DIR_B (idiff, openimageio-tools):
# fails when any pixel differs by more than TOLERANCE (default 1e-6) or a file is missing.
#   bash tests/golden/compare.sh DIR_A DIR_B [TOLERANCE]
set -uo pipefail
a=$1 b=$2 tolerance=${3:-1e-6}
status=0 count=0
for first in "$a"/*.exr; do
  name=$(basename "$first")
  second=$b/$name
  if [ ! -f "$second" ]; then echo "MISSING $name"; status=1; continue; fi
  count=$((count + 1))
  if ! out=$(idiff -q -fail "$tolerance" -failpercent 0 -warn "$tolerance" "$first" "$second" 2>&1); then
    echo "DIFFERS $name: $(idiff -fail "$tolerance" "$first" "$second" 2>&1 | grep -E 'Max error|Mean error|FAIL' | tr '\n' ' ')"
    status=1
  fi
done
echo "$count images compared, tolerance $tolerance: $([ $status -eq 0 ] && echo same || echo DIFFERENT)"
exit $status
