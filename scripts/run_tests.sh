#!/usr/bin/env bash
# Set-up, build, then every test: native (GoogleTest, EGL surfaceless) and Blender (blender -b),
# then the native tests again under AddressSanitizer and UndefinedBehaviorSanitizer.
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
