#!/usr/bin/env bash
# One libFuzzer target for FUZZ_SECONDS (default 20) from its seeds (CTest's fuzz_* tests,
# native/CMakeLists.txt; docs/RELIABILITY.md):
#   bash tests/sanitizers/fuzz.sh FUZZER SEED_DIR WORK_DIR
# The seeds are replayed first (the regression cases); new inputs go to WORK_DIR/corpus. A crash,
# a sanitizer report or a leak fails it, with the log's end printed and the input kept as
# WORK_DIR/crash_*.
set -uo pipefail
fuzzer=$1 seeds=$2 work=$3
mkdir -p "$work/corpus"
log=$work/fuzz.log
echo "Fuzzing $(basename "$fuzzer") for ${FUZZ_SECONDS:-20} s from $seeds"
"$fuzzer" -max_total_time="${FUZZ_SECONDS:-20}" -timeout=30 -rss_limit_mb=4096 -artifact_prefix="$work/crash_" \
  -print_final_stats=1 "$work/corpus" "$seeds" > "$log" 2>&1
status=$?
grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|Done)" "$log"
if [ "$status" -ne 0 ]; then
  tail -n 80 "$log"
  echo "$(basename "$fuzzer") failed (status $status); its input is in $work/crash_*"
fi
exit "$status"
