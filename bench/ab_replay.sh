#!/usr/bin/env bash
# A change's effect on the replayed examples, before against after, on this machine:
#   bash bench/ab_replay.sh BASE_REVISION [OUT_DIR]
# builds BASE_REVISION's subsplat_replay in a git worktree (build/ab-base/), then replays every
# scene file of `bench/methods.py --export-only` (build/bench/*.ssscene) with it and with this
# tree's build/, one scene at a time, base then this tree, and prints per scene and method the
# frame and splatting times (medians), the fragment invocations, the samples splatted and how far
# the images are apart (bench/ab_report.py). Environment: METHODS (default FULL,BRUTE), RUNS
# (default 3, after one warm-up), SIZE (default 200x150), SCENES (default all), PYTHON (one with
# numpy; default python3).
set -euo pipefail
cd "$(dirname "$0")/.."
base=${1:?usage: bench/ab_replay.sh BASE_REVISION [OUT_DIR]}
base=$(git rev-parse --verify "$base^{commit}")  # here, not in the worktree (whose HEAD is its own)
out=${2:-build/ab}
methods=${METHODS:-FULL,BRUTE}
runs=${RUNS:-3}
size=${SIZE:-200x150}
tree=build/ab-base
if [ ! -d "$tree" ]; then git worktree add -f --detach "$tree" "$base" >/dev/null; fi
git -C "$tree" checkout -q --detach "$base"
cmake -S "$tree" -B "$tree/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSUBSPLAT_BUILD_TESTS=OFF >/dev/null
cmake --build "$tree/build" -j"$(nproc)" --target subsplat_replay >/dev/null
cmake --build build -j"$(nproc)" --target subsplat_replay >/dev/null
scenes=${SCENES:-$(cd build/bench && ls *.ssscene | sed 's/\.ssscene$//')}
rm -rf "$out"
for s in $scenes; do
  for side in base after; do
    bin=build/native/subsplat_replay
    [ "$side" = base ] && bin="$tree/build/native/subsplat_replay"
    mkdir -p "$out/$side"
    "$bin" --methods "$methods" --runs "$runs" --warmup 1 --size "$size" --no-reference \
      --images "$out/$side" --json "$out/$side/$s.json" "build/bench/$s.ssscene" >/dev/null
  done
done
echo "base $(git -C "$tree" rev-parse --short HEAD), after $(git rev-parse --short HEAD)$(git diff --quiet || echo ' + changes')"
"${PYTHON:-python3}" bench/ab_report.py "$out"
