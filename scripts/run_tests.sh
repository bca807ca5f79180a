#!/usr/bin/env bash
# Set-up, build, then every test but the slow tier (docs/CI.md), in two build folders:
#   build/      the native tests (in shards, CTest label native-shard; each test is also a CTest test of its
#               own, labels unit and native-gl), the tests inside `blender -b`
#               (blender) and in Blender's UI under Xvfb (ui), and the per-version
#               suite in the `bpy` module of Blender 4.2, 4.5 and 5.0 (bpy, docs/VERSIONS.md);
#   build-san/  clang with AddressSanitizer and UndefinedBehaviorSanitizer (docs/RELIABILITY.md):
#               the native tests again, and each libFuzzer target for FUZZ_SECONDS (default 20)
#               from its seeds (label fuzz); any ASan or UBSan report, or a leak not of the GL
#               driver's, fails the run.
# The slow tier (the 1000-render soak, the full trade-off and stability sweeps): bash bench/slow.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${SUBSPLAT_TEST_JOBS:-$(nproc)}
stage() { echo "[run_tests] $1: ${SECONDS} s since the start"; }
bash scripts/setup.sh
stage "set-up and build/ done"
# Every test of build/ in one CTest run, two at a time: the longest Blender tests first (their COST),
# the short native ones filling the gaps. A Blender test keeps 1.3 cores busy on average (start-up,
# Python and the kernel tables are single-threaded), so two at once took 651 s where one at a time
# took 926 s (docs/CI.md, 2026-12-03).
# The native tests run in the shards (label native-shard: a few processes, each running its share of
# the tests; native/CMakeLists.txt), not a process per test (labels unit and native-gl, for ctest -R).
# tests/unit's Python tests carry the label python.
(cd build && ctest -L '^(native-shard|python|blender|ui|bpy)$' -j"$jobs" --output-on-failure)
stage "build/ tests done"

# Under the sanitizers, the native tests but SUBSPLAT_SANITIZED_SKIP (native/CMakeLists.txt says
# which and why), in the shards, and the fuzzers. LeakSanitizer's tracer crashed (signal 11) at some
# tests' exit after they had passed: up to LLVM 16 its __tls_get_addr interceptor can misread a
# dynamic TLS block (the GL driver's) as an old glibc's, depending on where malloc put it;
# intercept_tls_get_addr=0 turns that off, and the tests run the leak check after their last test
# (native/src/testing/leak_check.cpp) (docs/CI.md).
CC=clang CXX=clang++ cmake -S . -B build-san -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSUBSPLAT_SANITIZE=ON \
  -DSUBSPLAT_FUZZ=ON > /dev/null
cmake --build build-san -j"$(nproc)" --target subsplat_tests fuzz_subedit_file fuzz_scene_input
stage "build-san/ built"
(cd build-san &&
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:intercept_tls_get_addr=0 \
  LSAN_OPTIONS="suppressions=$PWD/../tests/sanitizers/lsan.supp:print_suppressions=0" \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest -L '^(native-shard|fuzz)$' -j"$jobs" --output-on-failure)
for log in build-san/fuzz_*/fuzz.log; do
  echo "$log: $(grep -E '^stat::(number_of_executed_units|peak_rss_mb)' "$log" | tr '\n' ' ')"
done
stage "sanitized tests and fuzzers done"
