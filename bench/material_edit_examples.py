"""MATERIAL_EDIT on the examples, against FULL and against the physical truth (docs/MATERIAL_EDIT.md,
"The examples").

  BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
      --python bench/material_edit_examples.py -- [--scenes ...] [--models DIPOLE TABULATED] \
      [--percentage 10] [--runs 3] [--output bench/results/material_edit_examples]

Each example that has a physical truth (bench/tradeoff.py's CONVERTIBLE ones, as their physical
variant: eta 1, specular 0, world black, its committed converged Cycles twin image
bench/results/truth/tradeoff_<scene>_<percentage>.exr) is rendered under each profile model, at the
irradiance resolution the automatic quality chooses for the example's own materials
(fixed for all of its renders) and one sample per pixel, as final renders (F12) in this Blender session:
- FULL of the example's own materials (`--runs` times; the median frame time);
- the precomputation: MATERIAL_EDIT with every translucent material's absorption doubled;
- the edit: the materials set back to the example's own, MATERIAL_EDIT again (`--runs` times: each
  recombines the same transport, `transport_reused`), so the edit lands on the material the truth
  is of.
Times are the library's frame times (SsStats.frame_ms, no export), fragments its fragment-shader
invocations. Errors: relative RMSE over the translucent pixels of the edit against FULL, and of
each against the truth with the truth's noise taken out (subsplat_testing.twin_truth.error).
The chart puts MATERIAL_EDIT on the speed-accuracy plane beside FULL: time per frame with the
precomputation amortised over 1, 10 and 100 edits, against the error against the truth.
Writes <output>/material_edit_examples.json, the table on stdout, and
docs/images/material_edit_examples.png.
"""
import argparse
import json
import os
import platform
import statistics
import subprocess
import sys

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(ROOT, "tests"), os.path.join(ROOT, "bench")]

from subsplat_testing import accuracy, physical, twin_truth  # noqa: E402
from tradeoff import CONVERTIBLE, relative_rmse  # noqa: E402  (the examples with a physical truth)

AMORTISED = (1, 10, 100)


def arguments():
    parser = argparse.ArgumentParser(prog="material_edit_examples.py")
    parser.add_argument("--scenes", nargs="+", default=list(CONVERTIBLE), choices=CONVERTIBLE)
    parser.add_argument("--models", nargs="+", default=["DIPOLE", "TABULATED"], choices=("DIPOLE", "TABULATED"))
    parser.add_argument("--percentage", type=int, default=10)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--output", default=os.path.join(ROOT, "bench", "results", "material_edit_examples"))
    parser.add_argument("--chart", default=os.path.join(ROOT, "docs", "images", "material_edit_examples.png"))
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return parser.parse_args(argv)


def render(scene, method):
    import subsplat
    image, exitance, stats = accuracy.render_passes(scene, method)
    if subsplat.last_render_error():
        raise RuntimeError(f"{method}: {subsplat.last_render_error()}")
    return image, exitance, stats


def fragments(stats):
    return int(stats["fragment_invocations"]["total"])


def measure(name, model, args):
    scene, notes = physical.example_case(name, args.percentage, bounce=False, profile_model=model)
    scene.subsplat.samples = 1
    scene.subsplat.quality = "AUTO"
    truth, _record = twin_truth.load(f"tradeoff_{name}_{args.percentage}")
    translucent = [m for m in bpy.data.materials if m.subsplat.enabled and m.subsplat.source == "DIPOLE"]
    own = {m.name: tuple(m.subsplat.sigma_a) for m in translucent}

    # The irradiance resolution AUTO chooses for the example's own materials, then fixed for every
    # render: AUTO would choose another for the precomputation's doubled absorption (shorter ranges),
    # and an edit keeps the precomputation's, so the edit would differ from FULL by that step alone.
    _image, _exitance, automatic = render(scene, "FULL")
    scene.subsplat.irradiance_resolution = automatic["irradiance_resolution"]  # makes the quality manual
    full_runs = [render(scene, "FULL") for _ in range(args.runs)]
    full, full_exitance, full_stats = full_runs[0]
    mask = full_exitance[..., 3] > 0.5
    for m in translucent:
        m.subsplat.sigma_a = [2 * value for value in own[m.name]]
    _image, _exitance, precompute = render(scene, "MATERIAL_EDIT")
    if precompute["transport_reused"] or precompute["transport_full_pipeline"]:
        raise RuntimeError(f"{name}: the first MATERIAL_EDIT render did not precompute ({precompute})")
    for m in translucent:
        m.subsplat.sigma_a = own[m.name]
    edit_runs = [render(scene, "MATERIAL_EDIT") for _ in range(args.runs)]
    edit, _exitance, edit_stats = edit_runs[0]
    if not all(stats["transport_reused"] for _i, _e, stats in edit_runs):
        raise RuntimeError(f"{name}: an edit did not reuse the transport")
    if truth[0].shape != full.shape:
        raise RuntimeError(f"{name}: the truth is {truth[0].shape}, the render {full.shape}")
    # What to look at: the edit | FULL | error x10, and the edit | the truth | error x10.
    stem = os.path.join(args.output, "images", f"{name}_{model.lower()}")
    os.makedirs(os.path.dirname(stem), exist_ok=True)
    accuracy.write_strip(f"{stem}_edit_full.png", edit, full, mask)
    accuracy.write_strip(f"{stem}_edit_truth.png", edit, truth[0], mask)
    row = {
        "scene": name, "model": model, "size": [int(full.shape[1]), int(full.shape[0])], "notes": notes,
        "materials": len(translucent), "irradiance_resolution": full_stats["irradiance_resolution"],
        "precompute_irradiance_resolution": precompute["irradiance_resolution"],
        "full_ms": statistics.median(s["frame_ms"] for _i, _e, s in full_runs), "full_fragments": fragments(full_stats),
        "precompute_ms": precompute["precompute_ms"], "precompute_fragments": fragments(precompute),
        "edit_ms": statistics.median(s["frame_ms"] for _i, _e, s in edit_runs), "edit_fragments": fragments(edit_stats),
        "edit_vs_full": relative_rmse(edit, full, mask),
        "full_vs_truth": twin_truth.error(full, truth, mask)[0],
        "edit_vs_truth": twin_truth.error(edit, truth, mask)[0],
    }
    print(f"{name} {model}: FULL {row['full_ms']:.0f} ms ({row['full_fragments'] / 1e6:.1f} M fragments), "
          f"precompute {row['precompute_ms']:.0f} ms ({row['precompute_fragments'] / 1e6:.1f} M), edit "
          f"{row['edit_ms']:.1f} ms ({row['edit_fragments'] / 1e6:.2f} M); edit against FULL "
          f"{100 * row['edit_vs_full']:.2f} %, against the truth: FULL {100 * row['full_vs_truth']:.1f} %, edit "
          f"{100 * row['edit_vs_truth']:.1f} %", flush=True)
    return row


def table(rows):
    lines = ["| example | model | FULL ms | precompute ms (FULL frames) | edit ms | FULL / edit: time, fragments "
             "| edit vs FULL | FULL vs truth | edit vs truth |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['model']} | {r['full_ms']:.0f} | {r['precompute_ms']:.0f} "
                     f"({r['precompute_ms'] / r['full_ms']:.1f}) | {r['edit_ms']:.1f} | "
                     f"{r['full_ms'] / r['edit_ms']:.0f}x, {r['full_fragments'] / r['edit_fragments']:.0f}x | "
                     f"{100 * r['edit_vs_full']:.2f} % | {100 * r['full_vs_truth']:.1f} % | "
                     f"{100 * r['edit_vs_truth']:.1f} % |")
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
            times = [(r["precompute_ms"] + n * r["edit_ms"]) / n for n in AMORTISED]
            axis.plot(times, [100 * r["edit_vs_truth"]] * len(times), color="tab:blue", marker=marker,
                      label=f"Material Edit ({r['model']}), 1 / 10 / 100 edits")
            for n, t in zip(AMORTISED, times):
                axis.annotate(str(n), (t, 100 * r["edit_vs_truth"]), textcoords="offset points", xytext=(0, 5),
                              ha="center", fontsize=7)
        axis.set_xscale("log")
        axis.set_title(name, fontsize=9)
        axis.set_xlabel("ms per frame (precomputation amortised)", fontsize=8)
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
              "percentage": args.percentage, "runs": args.runs, "rows": rows}
    with open(os.path.join(args.output, "material_edit_examples.json"), "w") as f:
        json.dump(record, f, indent=1)
    print(table(rows))
    chart(rows, args.chart)
    print(f"wrote {args.output}/material_edit_examples.json and {args.chart}")


if __name__ == "__main__":
    main()
