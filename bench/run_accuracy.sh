#!/usr/bin/env bash
# Set-up and build (as README), then measure every method against REFERENCE on every
# example scene and write docs/ACCURACY.md with its image strips. Arguments go to
# bench/accuracy.py (--percentage, --samples, --quick).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BLENDER_USER_SCRIPTS="$PWD/build/scripts" blender -b --factory-startup --addons subsplat \
  --python-exit-code 1 --python bench/accuracy.py -- "$@"
