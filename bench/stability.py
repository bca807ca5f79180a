"""The stability suite's hard cases (issue 8; tests/subsplat_testing/stability_cases.py): grazing light, a
depth discontinuity with the z0 threshold swept, a thin back-lit feature, a material discontinuity
with lambda_m swept, short and long ranges in one object, and one object at three scales. Every
real-time method against REFERENCE on each; a picture per set-up into docs/images/stability/ and
the table into docs/STABILITY.md (its "cases" section). A case with a physical truth (the Cycles
twin of its eta = 1 variant, committed in bench/results/truth/stability_<truth>_<size>.*; see
stability_cases.py) is also measured against it, every variant rendered again at eta = 1; a missing
truth is an error unless --render-truth renders it (--truth-samples x --truth-seeds).

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        --python bench/stability.py -- [--size 64] [--samples 50000] [--cases grazing depth ...] \
        [--flicker] [--flicker-percentage 8] [--flicker-samples 10000] [--output docs] \
        [--no-physical] [--render-truth] [--truth-samples 64] [--truth-seeds 4]

The defaults are docs/STABILITY.md's (about 25 minutes on 2 cores with --flicker).
"""
import argparse
import datetime
import json
import os
import sys
import tempfile

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests"))  # subsplat_testing
sys.path.insert(0, HERE)
from subsplat_testing import helpers  # noqa: E402

subsplat = helpers.enable_addon()
import sections  # noqa: E402
from subsplat_testing import accuracy, physical, stability_cases  # noqa: E402


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
    parser.add_argument("--no-physical", dest="physical", action="store_false",
                        help="do not measure against the physical truths")
    parser.add_argument("--render-truth", action="store_true", help="render the truths that are missing")
    # 64: a marble slab at 64 x 64 and 1024 bounces took 147 s a seed at 256 samples on 2 shared cores
    parser.add_argument("--truth-samples", type=int, default=64, help="samples of each of a truth's renders")
    parser.add_argument("--truth-seeds", type=int, default=4, help="a truth's renders (their scatter is its noise)")
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return parser.parse_args(argv)


def table(case, setups, size):
    lines = [f"### {case.title}", "",
             "| set-up | variant | radiance rel. RMSE | against the physical truth (eta 1) | mean / truth "
             "| without worst 0.1 % | exitance rel. RMSE | mean / REFERENCE | splats | texels from coarse samples |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for setup in setups:
        for row in setup["rows"]:
            physical = (f"{row['twin_error']:.4f} | {row['twin_mean_ratio']:.3f}" if "twin_error" in row else "– | –")
            lines.append(f"| {setup['label']} | {row['variant']} | {row['relative_rmse']:.4f} | {physical} "
                         f"| {row['robust_relative_rmse']:.4f} | {row['exitance_relative_rmse']:.4f} "
                         f"| {row['mean_ratio']:.3f} | {row['splats']} | {100 * row['coarse_share']:.0f} % |")
    lines.append("")
    if not case.truth:
        lines += [f"No physical truth: {case.no_truth}.", ""]
    for setup in setups:
        figures = setup.get("physical")
        if figures:
            lines += [f"Physical truth of {setup['label']}: the Cycles twin of its eta = 1 variant "
                      f"(`{stability_cases.truth_stem(figures['truth'], size)}`), {figures['samples']} "
                      f"samples x {figures['seeds']} seeds, {figures['seconds']:.0f} s of Cycles; its noise "
                      f"{figures['noise']:.4f}, taken out of each figure. REFERENCE at eta 1 (the dipole model "
                      f"itself) against it: {figures['reference_twin_error']:.4f}, mean "
                      f"{figures['reference_twin_mean_ratio']:.3f} x the truth's.", ""]
    for setup in setups:
        lines.append(f"![{case.title}, {setup['label']}](images/stability/{setup['picture']})")
        lines.append("")
        if setup.get("physical_picture"):
            lines += [f"At eta = 1, REFERENCE | the physical truth | error x10, and {setup['physical_shown']} | the "
                      "truth | error x10:", "",
                      f"![{case.title}, {setup['label']}, against the physical truth]"
                      f"(images/stability/{setup['physical_picture']})", ""]
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
    physical.set_profile_model("DIPOLE")  # the stability suite's model (stability_cases.translucent)
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
    scratch = tempfile.mkdtemp(prefix="stability_truth_")
    for case in stability_cases.CASES:
        if case.name not in args.cases:
            continue
        if args.physical and args.render_truth and case.truth:
            stability_cases.render_truth(
                case, args.size, args.truth_samples, args.truth_seeds, scratch,
                "BLENDER_USER_SCRIPTS=build/scripts nice -n 19 blender -b --factory-startup --addons subsplat "
                f"--python bench/stability.py -- --size {args.size} --samples {args.samples} --cases {case.name} "
                f"--render-truth --truth-samples {args.truth_samples} --truth-seeds {args.truth_seeds}")
        setups = stability_cases.measure(case, args.size, args.samples, physical=args.physical)
        for index, setup in enumerate(setups):
            setup["picture"] = f"case_{case.name}_{index}.png"
            stability_cases.picture(os.path.join(images, setup["picture"]), case.title, setup)
            figures = setup.get("physical")
            if figures:
                setup["physical_picture"] = f"case_{case.name}_{index}_physical.png"
                strips = [np.concatenate([accuracy.srgb(image[..., :3]), accuracy.srgb(figures["truth_image"][..., :3]),
                                          accuracy.error_colours(image, figures["truth_image"], figures["mask"])], axis=1)
                          for image in (figures["reference_image"], figures["shown"][1])]
                setup["physical_shown"] = figures["shown"][0]
                grow = max(1, -(-128 // args.size))  # at least 128 pixels a tile, to be seen
                accuracy.write_png(os.path.join(images, setup["physical_picture"]),
                          np.repeat(np.repeat(np.concatenate(strips[::-1], axis=0), grow, axis=0), grow, axis=1))
                print(f"{case.name} | {setup['label']}: REFERENCE at eta 1 against the truth "
                      f"{figures['reference_twin_error']:.4f} (mean {figures['reference_twin_mean_ratio']:.3f}), "
                      f"truth noise {figures['noise']:.4f}", flush=True)
            for row in setup["rows"]:
                print(f"{case.name} | {setup['label']} | {row['variant']}: {row['relative_rmse']:.4f} "
                      f"(robust {row['robust_relative_rmse']:.4f}, exitance {row['exitance_relative_rmse']:.4f}, "
                      f"mean {row['mean_ratio']:.3f}, splats {row['splats']}, coarse {row['coarse_share']:.2f}, "
                      f"{row['frame_ms']:.0f} ms)" + (f"; against the truth (eta 1) {row['twin_error']:.4f}"
                                                      if "twin_error" in row else ""), flush=True)
        lines += table(case, setups, args.size)
        results[case.name] = [{k: v for k, v in row.items() if k != "image"} for s in setups for row in s["rows"]]
    if results:
        with open(os.path.join(images, "cases.json"), "w") as f:
            json.dump(results, f, indent=1)
        sections.replace(os.path.join(args.output, "STABILITY.md"), "cases", lines)
    if args.flicker:
        sections.replace(os.path.join(args.output, "STABILITY.md"), "flicker", flicker(args, images))


if __name__ == "__main__":
    main()
