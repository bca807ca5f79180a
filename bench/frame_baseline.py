"""Baseline figures of every example scene: frame time, GL time per stage and fragment-shader
invocations per stage, at 800x600 with a 512^2 irradiance buffer. Writes docs/BENCHMARKS.md.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        --python bench/frame_baseline.py -- [--repeats N]
"""
import datetime
import glob
import os
import platform
import statistics
import subprocess
import sys

import bpy

import subsplat

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
COMMAND = ("BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat "
           "--python bench/frame_baseline.py")


def machine():
    cpu = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{cpu}, {os.cpu_count()} cores"


def gl_renderer():
    import gpu
    try:
        return gpu.platform.renderer_get()
    except Exception:  # noqa: BLE001 - only informational
        return "unknown"


def measure(path, repeats):
    bpy.ops.wm.open_mainfile(filepath=path)
    scene = bpy.context.scene
    scene.render.engine = "SUBSPLAT"
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 800, 600, 100
    scene.subsplat.method = "BRUTE"
    scene.subsplat.irradiance_resolution = 512
    runs = []
    for _ in range(repeats):
        bpy.ops.render.render(write_still=False)
        runs.append(subsplat.last_render_stats())
    best = min(runs, key=lambda s: s["frame_ms"])
    best["median_frame_ms"] = statistics.median(s["frame_ms"] for s in runs)
    return best


def main():
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    repeats = int(args[args.index("--repeats") + 1]) if "--repeats" in args else 3
    rows = []
    for path in sorted(glob.glob(os.path.join(ROOT, "example_blends", "*.blend"))):
        stats = measure(path, repeats)
        name = os.path.splitext(os.path.basename(path))[0]
        rows.append((name, stats))
        print(name, stats, flush=True)
    revision = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                              text=True).stdout.strip()
    lines = [
        "# Benchmarks",
        "",
        "## BRUTE baseline (issue: end to end)",
        "",
        f"Taken {datetime.date.today()} at revision `{revision}` on {machine()}, "
        f"OpenGL renderer `{gl_renderer()}`, Blender {bpy.app.version_string}, by",
        "",
        f"    {COMMAND}",
        "",
        f"Each scene rendered {repeats} times at 800x600 with a 512^2 irradiance buffer per light view "
        "(six views per point light). Frame time is the wall time of `ssRender` (median over the runs); "
        "stage times are GL timer queries and fragment counts are `GL_FRAGMENT_SHADER_INVOCATIONS` "
        "of the fastest run. On llvmpipe the timings are noisy; the invocation counts are not.",
        "",
        "| scene | frame ms (median) | buffers ms | splatting ms | shading ms | read-back ms | splats | "
        "fragments: buffers | splatting | shading | total |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, s in rows:
        ms, fi = s["stage_ms"], s["fragment_invocations"]
        lines.append(f"| {name} | {s['median_frame_ms']:.0f} | {ms['buffers']:.0f} | {ms['splatting']:.0f} | "
                     f"{ms['shading']:.0f} | {ms['readback']:.1f} | {s['splat_count']:,} | {fi['buffers']:,} | "
                     f"{fi['splatting']:,} | {fi['shading']:,} | {fi['total']:,} |")
    lines += ["", "Splatting dominates: every lit irradiance texel draws a quad over its whole kernel. "
              "This is the baseline the multiresolution issue is measured against.", ""]
    os.makedirs(os.path.join(ROOT, "docs"), exist_ok=True)
    with open(os.path.join(ROOT, "docs", "BENCHMARKS.md"), "w") as f:
        f.write("\n".join(lines))
    print("wrote docs/BENCHMARKS.md")


main()
