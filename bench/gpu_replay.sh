#!/usr/bin/env bash
# The examples on a GPU (docs/BENCHMARKS.md, "On a GPU"), from the bundle scripts/gpu_bundle.sh packs
# into .devbuild/, on a machine that has a GPU, its driver and nothing of ours. Run as root from
# the repository's root:
#   bash bench/gpu_replay.sh OUT_DIR [DEADLINE_S]
# Each part is one subsplat_replay run with its own JSON and log in OUT_DIR; a part that would
# start past DEADLINE_S (default 270) seconds is skipped and says so, so a slow device still
# returns what it measured. SIZE (default 1920x1080) and SMALL (800x600) override the frame sizes.
set -uo pipefail
out=${1:?OUT_DIR}
deadline=${2:-270}
size=${SIZE:-1920x1080}
small=${SMALL:-800x600}
mkdir -p "$out"
start=$SECONDS
for f in .devbuild/gl/*.deb; do dpkg -x "$f" /; done
ldconfig
mkdir -p /tmp/subsplat_gpu && tar -C /tmp/subsplat_gpu -xJf .devbuild/lib.tar.xz
export LD_LIBRARY_PATH=/tmp/subsplat_gpu/lib
nvidia_egl=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f "$nvidia_egl" ] && export __EGL_VENDOR_LIBRARY_FILENAMES=$nvidia_egl
{ cat .devbuild/revision; nvidia-smi --query-gpu=name,driver_version,clocks.max.sm,memory.total --format=csv 2>&1; nproc
  grep -m1 "model name" /proc/cpuinfo; } > "$out/machine.txt"
replay=.devbuild/subsplat_replay
scenes=.devbuild/scenes

part() {  # part NAME TIMEOUT_S ARGS...
  local name=$1 limit=$2; shift 2
  if (( SECONDS - start + 5 > deadline )); then echo "[gpu_replay] $name: skipped (deadline)" | tee -a "$out/parts.txt"; return; fi
  local t0=$SECONDS
  timeout "$limit" "$replay" --json "$out/$name.json" "$@" > "$out/$name.log" 2>&1
  local rc=$?
  echo "[gpu_replay] $name: rc $rc, $((SECONDS - t0)) s" | tee -a "$out/parts.txt"
  tail -n 40 "$out/$name.log"
}

# 1. Does it render the same picture as llvmpipe? FULL's images at 400x300 (compared here, on
#    llvmpipe, with the same command's; docs/BENCHMARKS.md).
mkdir -p "$out/images"
part images 60 --runs 1 --size 400x300 --no-reference --methods FULL --images "$out/images" \
  $scenes/skin_suzanne.ssscene $scenes/wax_jade.ssscene $scenes/heterogeneous.ssscene
tar -C "$out" -czf "$out/images.tar.gz" images && rm -r "$out/images"
# 2. Table 1 at the large size, scene by scene, cheapest first.
for s in marble_pieces skin_suzanne finger_pose candle_twist heterogeneous wax_jade; do
  part "hd_$s" 120 --runs 3 --warmup 1 --size "$size" --no-reference \
    --methods BRUTE,MULTIRES,ADAPTIVE,FULL,FULL:0 "$scenes/$s.ssscene"
done
# 3. Table 1 at llvmpipe's size, every scene in one run.
part small 90 --runs 3 --warmup 1 --size "$small" --no-reference --methods BRUTE,MULTIRES,ADAPTIVE,FULL,FULL:0 $scenes/*.ssscene
# 4. eq. 14's epsilon on the wide-range scene at the large size.
part hd_wax_jade_epsilon 90 --runs 3 --warmup 1 --size "$size" --no-reference \
  --methods FULL:3@0.001,FULL:3@0.003,FULL:3@0.01,FULL:0@0.003,FULL:0@0.01 $scenes/wax_jade.ssscene
echo "[gpu_replay] done in $((SECONDS - start)) s" | tee -a "$out/parts.txt"
