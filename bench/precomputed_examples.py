"""PRECOMPUTED (Lensch et al. 2002) on the examples: what the precomputation costs, what a frame
costs once it is made, and how far it is from REFERENCE and from the physical truth, beside FULL
(docs/PRECOMPUTED.md, "The examples").

  BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
      --python bench/precomputed_examples.py -- [--scenes ...] [--models DIPOLE TABULATED] \
      [--percentage 10] [--runs 3] [--atlas UV_MAP|MADE] [--output bench/results/precomputed_examples]

Each example with a physical truth (bench/tradeoff.py's CONVERTIBLE ones, as their physical variant:
eta 1, specular 0, world black; the committed converged Cycles twin image
bench/results/truth/tradeoff_<scene>_<percentage>.exr) under each profile model, at the irradiance
resolution the automatic quality chooses for it (then fixed), one sample per pixel, as final renders
in this Blender session (PRECOMPUTED keeps its context from one to the next):
- FULL (`--runs` times; the median frame time) and REFERENCE, at the scene's own lights;
- PRECOMPUTED's first render (the precomputation: its time, bytes, texels and factors);
- a moving light: every light turned about the vertical through the scene's centre by 6 degrees a
  step, `--runs` steps; at each, PRECOMPUTED (relit: `transport_reused`) and FULL; the median frame
  times and PRECOMPUTED's error against FULL's image of the same step; the same steps' frame times
  again at the example's own size (100 %), where FULL's pixels cost more;
- a deforming object: where the example is animated (finger_pose), two more frames, each of which
  precomputes again (the cost a deforming mesh pays every frame).
Times are the library's frame times (SsStats.frame_ms, no export). Errors: relative RMSE over the
translucent pixels against REFERENCE, and against the truth with the truth's noise taken out
(subsplat_testing.twin_truth.error). Writes <output>/precomputed_examples.json, the table on
stdout, and docs/images/precomputed_examples.png: per example, FULL, PRECOMPUTED on a rigid object
under a moving light (the precomputation amortised over 1, 10 and 100 frames) and on a deforming
one (paid every frame), time per frame against the error against the truth.
"""
import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys

import bpy
import mathutils

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(ROOT, "tests"), os.path.join(ROOT, "bench")]

from subsplat_testing import accuracy, physical, twin_truth  # noqa: E402
from tradeoff import CONVERTIBLE, relative_rmse  # noqa: E402  (the examples with a physical truth)

AMORTISED = (1, 10, 100)
DEFORMING = {"finger_pose": (12, 23)}  # animated examples: the frames rendered after the first
STEP_DEGREES = 6.0


def arguments():
    parser = argparse.ArgumentParser(prog="precomputed_examples.py")
    parser.add_argument("--scenes", nargs="+", default=list(CONVERTIBLE), choices=CONVERTIBLE)
    parser.add_argument("--models", nargs="+", default=["DIPOLE", "TABULATED"], choices=("DIPOLE", "TABULATED"))
    parser.add_argument("--percentage", type=int, default=10)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--atlas", default="UV_MAP", choices=("UV_MAP", "MADE"),
                        help="PRECOMPUTED's atlas (scene.subsplat.precomputed_atlas)")
    parser.add_argument("--output", default=os.path.join(ROOT, "bench", "results", "precomputed_examples"))
    parser.add_argument("--chart", default=os.path.join(ROOT, "docs", "images", "precomputed_examples.png"))
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return parser.parse_args(argv)


def render(scene, method):
    import subsplat
    image, exitance, stats = accuracy.render_passes(scene, method)
    if subsplat.last_render_error():
        raise RuntimeError(f"{method}: {subsplat.last_render_error()}")
    return image, exitance, stats


def turn_lights(scene, degrees):
    """Every light turned about the vertical axis through the origin by `degrees`."""
    rotation = mathutils.Matrix.Rotation(math.radians(degrees), 4, "Z")
    for obj in scene.objects:
        if obj.type == "LIGHT":
            obj.matrix_world = rotation @ obj.matrix_world


def relit_steps(scene, name, runs):
    """PRECOMPUTED at `runs` steps of the lights' turn (each must relight), the lights turned back:
    the images and frame times."""
    images, times = [], []
    for _step in range(runs):
        turn_lights(scene, STEP_DEGREES)
        image, _exitance, stats = render(scene, "PRECOMPUTED")
        if not stats["transport_reused"]:
            raise RuntimeError(f"{name}: a light move precomputed again ({stats})")
        images.append(image)
        times.append(stats["frame_ms"])
    turn_lights(scene, -STEP_DEGREES * runs)
    return images, times


def measure(name, model, args):
    scene, notes = physical.example_case(name, args.percentage, bounce=False, profile_model=model)
    scene.subsplat.samples = 1
    scene.subsplat.quality = "AUTO"
    scene.subsplat.precomputed_atlas = args.atlas
    truth, _record = twin_truth.load(f"tradeoff_{name}_{args.percentage}")
    _image, _exitance, automatic = render(scene, "FULL")
    scene.subsplat.irradiance_resolution = automatic["irradiance_resolution"]  # makes the quality manual
    full_runs = [render(scene, "FULL") for _ in range(args.runs)]
    full, full_exitance, full_stats = full_runs[0]
    mask = full_exitance[..., 3] > 0.5
    reference, _exitance, reference_stats = render(scene, "REFERENCE")
    precomputed, _exitance, first = render(scene, "PRECOMPUTED")
    if first["transport_reused"]:
        raise RuntimeError(f"{name}: the first PRECOMPUTED render reused a transport")
    if truth[0].shape != full.shape:
        raise RuntimeError(f"{name}: the truth is {truth[0].shape}, the render {full.shape}")
    stem = os.path.join(args.output, "images", f"{name}_{model.lower()}")
    os.makedirs(os.path.dirname(stem), exist_ok=True)
    accuracy.write_strip(f"{stem}_precomputed_reference.png", precomputed, reference, mask)
    accuracy.write_strip(f"{stem}_precomputed_truth.png", precomputed, truth[0], mask)

    # A moving light: relit at each step (one after another: another method's render in between
    # releases the kept context), then FULL at the same steps.
    relit, relit_ms = relit_steps(scene, name, args.runs)
    # The same steps at the example's own size (100 %), relit, then FULL: where the frame's pixels
    # cost FULL more and the relighting (per atlas texel) no more.
    scene.render.resolution_percentage = 100
    own, own_relit_ms = relit_steps(scene, name, args.runs)
    own_size = [int(own[0].shape[1]), int(own[0].shape[0])]
    own_full_ms = []
    for step in range(args.runs):
        turn_lights(scene, STEP_DEGREES)
        own_full_ms.append(render(scene, "FULL")[2]["frame_ms"])
    turn_lights(scene, -STEP_DEGREES * args.runs)
    scene.render.resolution_percentage = args.percentage
    full_moved_ms, moved_errors = [], []
    for step in range(args.runs):
        turn_lights(scene, STEP_DEGREES)
        full_moved, full_moved_exitance, full_moved_stats = render(scene, "FULL")
        full_moved_ms.append(full_moved_stats["frame_ms"])
        moved_mask = full_moved_exitance[..., 3] > 0.5
        moved_errors.append(relative_rmse(relit[step], full_moved, moved_mask))
        if step == args.runs - 1:
            accuracy.write_strip(f"{stem}_moved_light_full.png", relit[step], full_moved, moved_mask)
    turn_lights(scene, -STEP_DEGREES * args.runs)

    # A deforming object: each frame precomputes.
    deforming = []
    for frame in DEFORMING.get(name, ()):
        scene.frame_set(frame)
        _image, _exitance, stats = render(scene, "PRECOMPUTED")
        if stats["transport_reused"]:
            raise RuntimeError(f"{name}: frame {frame} of a deforming mesh reused the transport")
        _image, _exitance, full_frame = render(scene, "FULL")
        deforming.append({"frame": frame, "frame_ms": stats["frame_ms"], "precompute_ms": stats["precompute_ms"],
                          "full_ms": full_frame["frame_ms"]})

    row = {
        "scene": name, "model": model, "size": [int(full.shape[1]), int(full.shape[0])], "notes": notes,
        "irradiance_resolution": full_stats["irradiance_resolution"],
        "full_ms": statistics.median(s["frame_ms"] for _i, _e, s in full_runs),
        "reference_ms": reference_stats["frame_ms"],
        "precompute_ms": first["precompute_ms"], "first_frame_ms": first["frame_ms"],
        "bytes": first["precomputed_bytes"], "texels": first["precomputed_texels"],
        "factors": first["precomputed_factors"],
        "relit_ms": statistics.median(relit_ms),
        "full_moved_ms": statistics.median(full_moved_ms), "moved_vs_full": max(moved_errors),
        "own_size": own_size, "own_relit_ms": statistics.median(own_relit_ms),
        "own_full_ms": statistics.median(own_full_ms),
        "precomputed_vs_reference": relative_rmse(precomputed, reference, mask),
        "full_vs_reference": relative_rmse(full, reference, mask),
        "precomputed_vs_truth": twin_truth.error(precomputed, truth, mask)[0],
        "full_vs_truth": twin_truth.error(full, truth, mask)[0],
        "deforming": deforming,
    }
    print(f"{name} {model}: FULL {row['full_ms']:.0f} ms; precompute {row['precompute_ms']:.0f} ms "
          f"({row['bytes'] / 2**20:.0f} MiB, {row['texels']} texels, {row['factors']} factors); relit "
          f"{row['relit_ms']:.0f} ms (FULL at the same light {row['full_moved_ms']:.0f} ms, "
          f"{row['full_moved_ms'] / row['relit_ms']:.1f}x; at {own_size[0]} x {own_size[1]}: "
          f"{row['own_relit_ms']:.0f} ms, FULL {row['own_full_ms']:.0f} ms, "
          f"{row['own_full_ms'] / row['own_relit_ms']:.1f}x); against REFERENCE: PRECOMPUTED "
          f"{100 * row['precomputed_vs_reference']:.2f} %, FULL {100 * row['full_vs_reference']:.2f} %; against the "
          f"truth: PRECOMPUTED {100 * row['precomputed_vs_truth']:.1f} %, FULL {100 * row['full_vs_truth']:.1f} %; "
          f"moved light against FULL {100 * row['moved_vs_full']:.2f} %; deforming {deforming}", flush=True)
    return row


def table(rows):
    lines = ["| example | model | FULL ms | precompute ms (FULL frames) | memory MiB (texels, factors) | relit ms "
             "(FULL at the same light) | at the example's own size: relit ms (FULL) | vs REFERENCE: PRECOMPUTED, "
             "FULL | vs truth: PRECOMPUTED, FULL | moved light vs FULL | deforming: ms a frame (FULL) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        deforming = ", ".join(f"{d['frame_ms']:.0f} ({d['full_ms']:.0f})" for d in r["deforming"]) or "-"
        lines.append(f"| {r['scene']} | {r['model']} | {r['full_ms']:.0f} | {r['precompute_ms']:.0f} "
                     f"({r['precompute_ms'] / r['full_ms']:.1f}) | {r['bytes'] / 2**20:.0f} ({r['texels']}, "
                     f"{r['factors']}) | {r['relit_ms']:.0f} ({r['full_moved_ms']:.0f}: "
                     f"{r['full_moved_ms'] / r['relit_ms']:.1f}x) | {r['own_relit_ms']:.0f} ({r['own_full_ms']:.0f}: "
                     f"{r['own_full_ms'] / r['own_relit_ms']:.1f}x; {r['own_size'][0]} x {r['own_size'][1]}) | "
                     f"{100 * r['precomputed_vs_reference']:.2f} %, "
                     f"{100 * r['full_vs_reference']:.2f} % | {100 * r['precomputed_vs_truth']:.1f} %, "
                     f"{100 * r['full_vs_truth']:.1f} % | {100 * r['moved_vs_full']:.2f} % | {deforming} |")
    return "\n".join(lines)


def chart(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    figure, axes = plt.subplots(1, len(scenes), figsize=(4 * len(scenes), 3.6), squeeze=False)
    for axis, name in zip(axes[0], scenes):
        for r in (r for r in rows if r["scene"] == name):
            marker = "o" if r["model"] == "DIPOLE" else "s"
            axis.scatter([r["full_ms"]], [100 * r["full_vs_truth"]], color="tab:red", marker=marker,
                         label=f"FULL ({r['model']})")
            error = 100 * r["precomputed_vs_truth"]
            times = [(r["precompute_ms"] + n * r["relit_ms"]) / n for n in AMORTISED]
            axis.plot(times, [error] * len(times), color="tab:blue", marker=marker,
                      label=f"Precomputed, rigid ({r['model']}): 1 / 10 / 100 frames")
            for n, t in zip(AMORTISED, times):
                axis.annotate(str(n), (t, error), textcoords="offset points", xytext=(0, 5), ha="center", fontsize=7)
            # A deforming object pays the precomputation every frame.
            deforming = statistics.median(d["frame_ms"] for d in r["deforming"]) if r["deforming"] else \
                r["first_frame_ms"]
            axis.scatter([deforming], [error], color="tab:orange", marker=marker,
                         label=f"Precomputed, deforming ({r['model']})")
        axis.set_xscale("log")
        axis.set_title(name, fontsize=9)
        axis.set_xlabel("ms per frame", fontsize=8)
        axis.set_ylabel("error against the physical truth, %", fontsize=8)
        axis.grid(True, which="both", alpha=0.3)
    axes[0][0].legend(fontsize=6, loc="best")
    figure.tight_layout()
    os.makedirs(os.path.dirname(path), exist_ok=True)
    figure.savefig(path, dpi=100)


def main():
    args = arguments()
    rows = [measure(name, model, args) for name in args.scenes for model in args.models]
    os.makedirs(args.output, exist_ok=True)
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    record = {"machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
              "cpu": next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
                          "unknown"),
              "blender": bpy.app.version_string, "commit": commit.stdout.strip() or None,
              "percentage": args.percentage, "runs": args.runs, "atlas": args.atlas, "rows": rows}
    with open(os.path.join(args.output, "precomputed_examples.json"), "w") as f:
        json.dump(record, f, indent=1)
    print(table(rows))
    chart(rows, args.chart)
    print(f"wrote {args.output}/precomputed_examples.json and {args.chart}")


if __name__ == "__main__":
    main()
