#!/usr/bin/env bash
# The golden images (CTest golden_examples; tests/golden/README.md): every example rendered with
# FULL at 6 % (48 x 36 pixels, half-float EXR) and compared with tests/golden/images/ by idiff.
#   bash tests/golden/check.sh OUT        render into OUT/, compare; a differing image leaves
#                                         OUT/<name>_diff.png (|render - golden| x 10) to look at
#   bash tests/golden/check.sh --update   render into tests/golden/images/ (the committed images)
# Needs the build (build/scripts, or SUBSPLAT_BUILD_DIR) and the example materials (scripts/setup.sh).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$(dirname "$here")")
build=${SUBSPLAT_BUILD_DIR:-$root/build}
golden=$here/images

# A pixel channel fails when it is off by more than FAIL_ABS and by more than FAIL_RELATIVE of its
# value; an image fails when more than FAIL_PERCENT % of its pixels do, or any one is off by more
# than HARD_FAIL. Why these figures: tests/golden/README.md.
FAIL_ABS=${FAIL_ABS:-0.002} FAIL_RELATIVE=${FAIL_RELATIVE:-0.01} FAIL_PERCENT=${FAIL_PERCENT:-1} HARD_FAIL=${HARD_FAIL:-0.5}

render() {
  mkdir -p "$1"
  if ! BLENDER_USER_SCRIPTS=$build/scripts "${BLENDER:-blender}" -b --factory-startup --addons subsplat \
      --python-exit-code 1 --python "$here/render_examples.py" -- \
      --out "$1" --methods FULL --percentage 6 --depth 16 > "$1/render.log" 2>&1; then
    tail -n 40 "$1/render.log"
    echo "rendering the examples failed (log: $1/render.log)"
    exit 1
  fi
}

if [ "${1:-}" = "--update" ]; then
  rm -f "$golden"/*.exr
  render "$golden"
  rm -f "$golden/render.log"
  ls -l "$golden"
  exit 0
fi

out=${1:?usage: check.sh OUT | --update}
rm -rf "$out"
render "$out"
status=0 count=0
for expected in "$golden"/*.exr; do
  name=$(basename "$expected" .exr)
  rendered=$out/$name.exr
  if [ ! -f "$rendered" ]; then echo "MISSING $name"; status=1; continue; fi
  count=$((count + 1))
  report=$(idiff -fail "$FAIL_ABS" -failrelative "$FAIL_RELATIVE" -failpercent "$FAIL_PERCENT" \
    -hardfail "$HARD_FAIL" -warn "$FAIL_ABS" -warnrelative "$FAIL_RELATIVE" "$expected" "$rendered" 2>&1)
  result=$?
  if [ $result -eq 0 ] || [ $result -eq 1 ]; then  # 0: PASS, 1: WARNING (within FAIL_PERCENT)
    echo "same    $name $(echo "$report" | grep -E 'Max error' | tr -s ' ')"
  else
    oiiotool "$rendered" "$expected" --absdiff --mulc 10 --ch R,G,B -d uint8 -o "$out/${name}_diff.png"
    echo "DIFFERS $name (difference x 10: $out/${name}_diff.png):"
    echo "$report" | grep -E 'Mean error|RMS error|Max error|pixels|FAIL' | sed 's/^/    /'
    status=1
  fi
done
for rendered in "$out"/*.exr; do
  [ -f "$golden/$(basename "$rendered")" ] || { echo "NEW $(basename "$rendered"): no golden image"; status=1; }
done
echo "$count golden images compared: $([ $status -eq 0 ] && echo same || echo DIFFERENT)"
exit $status
