"""The stability suite's hard cases (issue 8; tests/subsplat_testing/stability_cases.py): grazing light, a
depth discontinuity with the z0 threshold swept, a thin back-lit feature, a material discontinuity
with lambda_m swept, short and long ranges in one object, and one object at three scales. Every
real-time method against REFERENCE on each; a picture per set-up into docs/images/stability/ and
the table into docs/STABILITY.md (its "cases" section).

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        --python bench/stability.py -- [--size 64] [--samples 50000] [--cases grazing depth ...] \
        [--flicker] [--flicker-percentage 8] [--flicker-samples 10000] [--output docs]

The defaults are docs/STABILITY.md's (about 25 minutes on 2 cores with --flicker).
"""
import argparse
import datetime
import json
import os
import sys

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests"))  # subsplat_testing
sys.path.insert(0, HERE)
from subsplat_testing import helpers  # noqa: E402

subsplat = helpers.enable_addon()
import sections  # noqa: E402
from subsplat_testing import accuracy, stability_cases  # noqa: E402


def arguments():
    parser = argparse.ArgumentParser(prog="bench/stability.py")
    parser.add_argument("--size", type=int, default=64, help="image width and height in pixels")
    parser.add_argument("--samples", type=int, default=50000, help="REFERENCE surface samples")
    parser.add_argument("--cases", nargs="*", default=[c.name for c in stability_cases.CASES],
                        help="the cases to measure (none: only --flicker)")
    parser.add_argument("--output", default=os.path.join(ROOT, "docs"), help="where STABILITY.md and images go")
    parser.add_argument("--flicker", action="store_true",
                        help="also the flicker of every method under a moving light, on skin_suzanne and on the "
                             "coarse-sample sphere (60 frames each)")
    parser.add_argument("--flicker-percentage", type=int, default=8, help="skin_suzanne's resolution percentage")
    parser.add_argument("--flicker-samples", type=int, default=10000, help="REFERENCE samples of the flicker frames")
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return parser.parse_args(argv)


def table(case, setups):
    lines = [f"### {case.title}", "",
             "| set-up | variant | radiance rel. RMSE | without worst 0.1 % | exitance rel. RMSE | mean / REFERENCE "
             "| splats | texels from coarse samples |",
             "|---|---|---|---|---|---|---|---|"]
    for setup in setups:
        for row in setup["rows"]:
            lines.append(f"| {setup['label']} | {row['variant']} | {row['relative_rmse']:.4f} "
                         f"| {row['robust_relative_rmse']:.4f} | {row['exitance_relative_rmse']:.4f} "
                         f"| {row['mean_ratio']:.3f} | {row['splats']} | {100 * row['coarse_share']:.0f} % |")
    lines.append("")
    for setup in setups:
        lines.append(f"![{case.title}, {setup['label']}](images/stability/{setup['picture']})")
        lines.append("")
    return lines


def flicker(args, images):
    """The flicker section: every method's frame-to-frame change over 60 frames of a turning light."""
    methods = ("REFERENCE",) + stability_cases.METHODS
    scenes = [("skin_suzanne", f"skin Suzanne at {args.flicker_percentage} % of 800 x 600, 3 levels",
               lambda: _suzanne(args.flicker_percentage)),
              ("coarse_sphere", f"marble sphere with coarse samples, {args.size} x {args.size}, 512^2, 3 levels",
               lambda: stability_cases.coarse_sphere(args.size))]
    lines = [f"Measured by `bench/stability.py -- --flicker --size {args.size} --flicker-percentage "
             f"{args.flicker_percentage} --flicker-samples {args.flicker_samples}` on {helpers.machine()}, "
             f"Mesa llvmpipe, {datetime.date.today().isoformat()}: every light turns "
             f"{stability_cases.DEGREES_PER_FRAME} degrees a frame for {stability_cases.FRAMES} frames.", "",
             "| scene | method | flicker | excess over REFERENCE | texels from coarse samples (mean) |",
             "|---|---|---|---|---|"]
    pictures = []
    for name, title, build in scenes:
        frames, mask, stats = stability_cases.moving_light(build(), methods, args.flicker_samples)
        figures, excess, scale = stability_cases.flicker(frames, mask)
        for method in methods:
            coarse = np.mean([stability_cases.coarse_share(s) for s in stats[method]]) if method != "REFERENCE" else 0.0
            lines.append(f"| {name} | {method} | {figures[method]:.5f} | {excess[method]:+.5f} | {100 * coarse:.0f} % |")
            print(f"flicker | {name} | {method}: {figures[method]:.5f} (excess {excess[method]:+.5f}, "
                  f"coarse {coarse:.2f})", flush=True)
        plot = f"flicker_{name}.png"
        stability_cases.plot_changes(os.path.join(images, plot), f"Frame-to-frame change, {title}", frames, mask, scale)
        strip = f"flicker_{name}_full.png"
        accuracy.write_strip(os.path.join(images, strip), frames["FULL"][-1], frames["REFERENCE"][-1], mask)
        pictures += [f"![frame-to-frame change, {name}](images/stability/{plot})", "",
                     f"FULL at the last frame, {name} (FULL | REFERENCE | error x10):", "",
                     f"![FULL, last frame, {name}](images/stability/{strip})", ""]
    return lines + [""] + pictures


def _suzanne(percentage):
    scene = accuracy.open_example("skin_suzanne", percentage)
    scene.render.engine = "SUBSPLAT"
    stability_cases.apply(scene, {"levels": 3})
    return scene


def main():
    args = arguments()
    images = os.path.join(args.output, "images", "stability")
    os.makedirs(images, exist_ok=True)
    lines = [f"Measured by `bench/stability.py -- --size {args.size} --samples {args.samples}` on "
             f"{helpers.machine()}, Mesa llvmpipe, Blender {bpy.app.version_string}, "
             f"{datetime.date.today().isoformat()}. Settings unless a variant says otherwise: "
             + ", ".join(f"{k} {v}" for k, v in stability_cases.BASE.items()) + ". The error picture is "
             "|I - REFERENCE| x10 over the mean (10 % is full red).", ""]
    results = {}
    for case in stability_cases.CASES:
        if case.name not in args.cases:
            continue
        setups = stability_cases.measure(case, args.size, args.samples)
        for index, setup in enumerate(setups):
            setup["picture"] = f"case_{case.name}_{index}.png"
            stability_cases.picture(os.path.join(images, setup["picture"]), case.title, setup)
            for row in setup["rows"]:
                print(f"{case.name} | {setup['label']} | {row['variant']}: {row['relative_rmse']:.4f} "
                      f"(robust {row['robust_relative_rmse']:.4f}, exitance {row['exitance_relative_rmse']:.4f}, "
                      f"mean {row['mean_ratio']:.3f}, splats {row['splats']}, coarse {row['coarse_share']:.2f}, "
                      f"{row['frame_ms']:.0f} ms)", flush=True)
        lines += table(case, setups)
        results[case.name] = [{k: v for k, v in row.items() if k != "image"} for s in setups for row in s["rows"]]
    if results:
        with open(os.path.join(images, "cases.json"), "w") as f:
            json.dump(results, f, indent=1)
        sections.replace(os.path.join(args.output, "STABILITY.md"), "cases", lines)
    if args.flicker:
        sections.replace(os.path.join(args.output, "STABILITY.md"), "flicker", flicker(args, images))


if __name__ == "__main__":
    main()
