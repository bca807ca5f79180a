#!/usr/bin/env bash
# Set-up, build, then every test: native (GoogleTest, EGL surfaceless) and Blender (blender -b).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cd build
ctest --output-on-failure --timeout 1200
