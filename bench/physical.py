"""The model against physical truth (issue 18, docs/PHYSICAL.md "The model against the truth"): every
case of subsplat_testing.physical rendered by REFERENCE, FULL, EEVEE and Cycles (each DIPOLE material
as its Principled BSDF equivalent, Random Walk) and by its Cycles twin (subsplat.twin: the medium as a
volume, the physical answer), each compared with the twin per channel and as relative RMSE. Writes
bench/results/physical.json (tests/blender/test_physical.py checks it and ties it to the code) and the
pictures docs/images/physical/<case>_<method>.png (method | truth | error x10).

    BLENDER_USER_SCRIPTS=build/scripts nice -n 19 blender -b --factory-startup --addons subsplat \
        --python bench/physical.py -- [--cases slab thin sphere example] [--only NAME ...] \
        [--size 32] [--percentage 10] [--samples 256] [--seeds 4] [--reference-samples 200000] \
        [--output bench/results/physical.json] [--images docs/images/physical]

Results are merged into the JSON by case name, so a run of some cases keeps the others'.
"""
import argparse
import json
import os
import sys
import tempfile
import time

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests"))
from subsplat_testing import accuracy, helpers, physical, twin_truth  # noqa: E402

METHODS = ("REFERENCE", "FULL", "EEVEE", "CYCLES_PRINCIPLED")


def render_subsplat(scene, method, reference_samples):
    start = time.perf_counter()
    image, exitance, stats = accuracy.render_passes(scene, method, reference_samples)
    seconds = time.perf_counter() - start
    return image, exitance, seconds, stats


def render_foreign(scene, engine, samples, path):
    if engine == "EEVEE":
        scene.render.engine = "BLENDER_EEVEE"
        scene.eevee.taa_render_samples = 1
        helpers.render_to(scene, path + "_warmup.exr")  # shaders compile in the first render
        scene.eevee.taa_render_samples = samples
    else:
        accuracy.use_cycles(scene, samples)
    start = time.perf_counter()
    image = helpers.render_to(scene, path + ".exr")
    return image, time.perf_counter() - start


def render_twin(scene, twin, samples, seeds, path):
    """The twin's image (mean over seeds), its per-seed images and seconds."""
    twin.cycles.device = "CPU"
    twin.cycles.samples = samples
    twin.cycles.use_animated_seed = False
    window = bpy.context.window
    window.scene = twin
    per_seed, seconds = [], 0.0
    try:
        for seed in range(seeds):
            twin.cycles.seed = seed
            start = time.perf_counter()
            per_seed.append(helpers.render_to(twin, f"{path}_seed{seed}.exr"))
            seconds += time.perf_counter() - start
    finally:
        window.scene = scene
    return np.mean(per_seed, axis=0), per_seed, seconds


def write_truth_image(path, image):
    """The truth's mean image as a half-float EXR (small enough to commit), for the benchmarks that
    measure against it."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    twin_truth.write_exr(path, image)
    return path


def run_case(args, scratch, name, kind, build, details):
    import subsplat
    scene, notes = build()
    bpy.context.window.scene = scene
    print(f"== {name}", flush=True)
    twin, reports = subsplat.twin.make_cycles_twin(scene)
    warnings = [text for level, text in reports if level == "WARNING"]
    missing = [w for w in warnings if "is not converted" in w]
    if missing:  # no physical answer to measure against: said, not guessed
        print(f"{name}: not measured: " + "; ".join(missing), flush=True)
        return {"kind": kind, **details, "notes": notes, "twin_warnings": warnings,
                "not_measured": "; ".join(missing)}
    reference, exitance, ref_seconds, _ = render_subsplat(scene, "REFERENCE", args.reference_samples)
    mask = physical.mask_for(kind, exitance)
    images = {"REFERENCE": reference}
    seconds = {"REFERENCE": ref_seconds}
    images["FULL"], _, seconds["FULL"], full_stats = render_subsplat(scene, "FULL", None)
    # A second FULL render: the first pays for the context and shaders, as a viewport does once.
    images["FULL"], _, seconds["FULL"], full_stats = render_subsplat(scene, "FULL", None)
    images["EEVEE"], seconds["EEVEE"] = render_foreign(scene, "EEVEE", args.eevee_samples,
                                                       os.path.join(scratch, f"{name}_eevee"))
    images["CYCLES_PRINCIPLED"], seconds["CYCLES_PRINCIPLED"] = render_foreign(
        scene, "CYCLES", args.cycles_samples, os.path.join(scratch, f"{name}_cycles"))
    truth, per_seed, twin_seconds = render_twin(scene, twin, args.samples, args.seeds,
                                                os.path.join(scratch, f"{name}_twin"))
    truth_image = write_truth_image(os.path.join(args.truth_images, f"{name}.exr"), truth)
    noise = physical.truth_noise(kind, per_seed, mask)
    result = {"kind": kind, **details, "notes": notes, "twin_warnings": warnings,
              "size": list(truth.shape[:2]), "pixels": int(mask.sum()),
              "truth": {"samples": args.samples, "seeds": args.seeds, "seconds": round(twin_seconds, 2),
                        "image": os.path.relpath(truth_image, ROOT),
                        "mean": truth[mask][:, :3].mean(axis=0).tolist(), **noise},
              "methods": {}}
    picture_dir = args.images
    os.makedirs(picture_dir, exist_ok=True)
    for method in METHODS:
        m = physical.measure(kind, images[method], truth, mask)
        m["seconds"] = round(seconds[method], 3)
        if method == "FULL":
            m["frame_ms"] = full_stats.get("frame_ms")
            m["fragments"] = (full_stats.get("fragment_invocations") or {}).get("total")
        m["picture"] = os.path.relpath(physical.write_picture(
            os.path.join(picture_dir, f"{name}_{method.lower()}.png"), images[method], truth, mask), ROOT)
        result["methods"][method] = m
        print(f"{name} {method}: ratio {' '.join(f'{r:.3f}' for r in m['ratio'])}  rel RMSE "
              f"{m['relative_rmse']:.3f}" + (f"  profile {m['profile_relative_rmse']:.3f} lit "
                                             f"{' '.join(f'{r:.2f}' for r in m['lit_ratio'])} shadowed "
                                             f"{' '.join(f'{r:.2f}' for r in m['shadowed_ratio'])}"
                                             if kind == "sphere" else "") + f"  ({seconds[method]:.2f} s)",
              flush=True)
    print(f"{name} truth: {twin_seconds:.1f} s, channel s.e. "
          f"{' '.join(f'{100 * e:.2f}%' for e in noise['channel_relative_standard_error'])}, image noise "
          f"{100 * noise['image_relative_noise']:.1f} %" + ("; " + "; ".join(warnings) if warnings else ""),
          flush=True)
    return result


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--cases", nargs="+", default=["slab", "thin", "sphere", "example"])
    parser.add_argument("--only", nargs="*", default=None, help="case names (of the kinds asked for)")
    parser.add_argument("--size", type=int, default=32, help="pixels across the built cases")
    parser.add_argument("--percentage", type=int, default=10, help="examples' resolution percentage")
    parser.add_argument("--samples", type=int, default=256, help="the twin's samples per pixel per seed")
    parser.add_argument("--seeds", type=int, default=4, help="the twin's renders (their scatter is its noise)")
    parser.add_argument("--reference-samples", type=int, default=200000)
    parser.add_argument("--eevee-samples", type=int, default=64)
    parser.add_argument("--cycles-samples", type=int, default=256)
    parser.add_argument("--output", default=os.path.join(HERE, "results", "physical.json"))
    parser.add_argument("--images", default=os.path.join(ROOT, "docs", "images", "physical"))
    parser.add_argument("--truth-images", default=os.path.join(HERE, "results", "truth"),
                        help="where the truth's mean image of each case is written (half-float EXR)")
    args = parser.parse_args(argv)
    helpers.enable_addon()
    scratch = tempfile.mkdtemp(prefix="physical_")
    results = {}
    if os.path.exists(args.output):
        with open(args.output) as f:
            results = json.load(f)
    results.setdefault("cases", {})
    for name, kind, build, details in physical.cases(args.cases, args.size, args.percentage):
        if args.only and name not in args.only:
            continue
        physical.save_case(results, name, run_case(args, scratch, name, kind, build, details), "physical.py", argv,
                           args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
