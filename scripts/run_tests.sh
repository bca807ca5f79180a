#!/usr/bin/env bash
# Set-up, build, then every test: native (GoogleTest, EGL surfaceless) and Blender (blender -b),
# then the native tests again under AddressSanitizer and UndefinedBehaviorSanitizer, then each
# libFuzzer target for a bounded time from its seed corpus.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
(cd build && ctest --output-on-failure --timeout 1200)

# Sanitized native tests (docs/RELIABILITY.md): a Debug build of the library and its tests in
# build-asan/; any ASan or UBSan report, or a leak not of the GL driver's, fails the run.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DSUBSPLAT_SANITIZE=ON > /dev/null
cmake --build build-asan -j"$(nproc)" --target subsplat_tests
(cd build-asan &&
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 \
  LSAN_OPTIONS="suppressions=$PWD/../tests/sanitizers/lsan.supp:print_suppressions=0" \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest -R '^native$' --output-on-failure --timeout 1800)

# Fuzzing (docs/RELIABILITY.md): clang, ASan + UBSan, each target FUZZ_SECONDS (default 60) from
# its seeds in native/fuzz/corpus/ (replayed first: the regression cases), new inputs in a
# scratch corpus. A crash fails the run and leaves its input in build-fuzz/ for the corpus.
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSUBSPLAT_SANITIZE=ON \
  -DSUBSPLAT_FUZZ=ON -DSUBSPLAT_BUILD_TESTS=OFF > /dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_subedit_file fuzz_scene_input
for target in subedit_file:subedit scene_input:scene; do
  name=${target%%:*} seeds=native/fuzz/corpus/${target##*:}
  scratch=build-fuzz/corpus_$name
  mkdir -p "$scratch"
  echo "Fuzzing $name for ${FUZZ_SECONDS:-60} s from $seeds"
  log=build-fuzz/fuzz_$name.log status=0
  LSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0" \
    build-fuzz/native/fuzz_$name -max_total_time="${FUZZ_SECONDS:-60}" -timeout=30 -rss_limit_mb=4096 \
    -artifact_prefix=build-fuzz/crash_"$name"_ -print_final_stats=1 "$scratch" "$seeds" > "$log" 2>&1 || status=$?
  grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|Done)" "$log" || true
  if [ "$status" -ne 0 ]; then
    tail -n 80 "$log"
    echo "fuzz_$name failed (status $status); its input is in build-fuzz/crash_${name}_*"
    exit "$status"
  fi
done
