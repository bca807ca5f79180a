"""The profile models against physical truth (issue 19, docs/PHYSICAL.md "The model: before and
after"): every case of subsplat_testing.physical that has a committed truth (bench/results/truth/
<case>.exr, made by bench/physical.py) rendered by REFERENCE and FULL under each profile model
(DIPOLE, the classical dipole; TABULATED, the transport tables), in one run, each compared with the
truth per channel and as relative RMSE (a sphere: also its profile across the terminator and each
half). FULL's frame time and fragment invocations per model, same run: the model's cost; FULL under
TABULATED also at the irradiance resolution the automatic quality chose for the dipole (the cost of
the model at the same buffers), and each FULL's error against its own model's REFERENCE. Writes
bench/results/model.json (tests/blender/test_physical.py checks it and ties it to the code) and the
pictures docs/images/model/<case>_<model>.png (FULL | truth | error x10).

    BLENDER_USER_SCRIPTS=build/scripts nice -n 19 blender -b --factory-startup --addons subsplat \
        --python bench/model.py -- [--cases slab thin sphere example] [--only NAME ...] \
        [--reference-samples 200000] [--output bench/results/model.json] [--images docs/images/model] \
        [--scene-files DIR]

The truths are not rendered again (bench/physical.py does, 1-2 hours); a case without one is an
error. Results are merged into the JSON by case name.
"""
import argparse
import json
import os
import sys

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests"))
from subsplat_testing import accuracy, helpers, physical, twin_truth  # noqa: E402

MODELS = ("DIPOLE", "TABULATED")
METHODS = ("REFERENCE", "FULL")


def truth_of(name, shape):
    path = os.path.join(twin_truth.DIRECTORY, f"{name}.exr")
    if not os.path.exists(path):
        raise twin_truth.MissingTruth(f"{name}: no committed truth at {path}: run bench/physical.py --only {name}")
    truth = twin_truth.read_exr(path)
    if truth.shape[:2] != shape[:2]:
        raise RuntimeError(f"{name}: the truth is {truth.shape[1]} x {truth.shape[0]}, the render "
                           f"{shape[1]} x {shape[0]}")
    return truth


def summary(kind, m):
    text = f"ratio {' '.join(f'{r:.3f}' for r in m['ratio'])}  rel RMSE {m['relative_rmse']:.3f}"
    if kind == "sphere":
        text += (f"  profile {m['profile_relative_rmse']:.3f} lit {' '.join(f'{r:.2f}' for r in m['lit_ratio'])}"
                 f" shadowed {' '.join(f'{r:.2f}' for r in m['shadowed_ratio'])}")
    return text


def run_case(args, name, kind, build, details, committed):
    scene, notes = build()
    bpy.context.window.scene = scene
    print(f"== {name}", flush=True)
    result = {"kind": kind, **details, "notes": notes, "models": {}}
    principled = [m.name for m in bpy.data.materials if m.subsplat.enabled and m.subsplat.source == "PRINCIPLED"]
    if principled:  # its coefficients come from the colour through the model's total: another medium
        result["principled_sources"] = principled
    truth = mask = None
    dipole_resolution = None
    for model in MODELS:
        fixed = physical.set_profile_model(model)
        if fixed:
            result["without_profile_model"] = fixed
        entry, reference = {}, None
        # FULL at its automatic quality and, under TABULATED, also at the irradiance resolution the
        # automatic quality gave the dipole (the same buffers: the model's own cost per splat).
        variants = [("REFERENCE", None), ("FULL", None)]
        if model != "DIPOLE":
            variants.append(("FULL_AT_DIPOLE_RESOLUTION", dipole_resolution))
        for label, resolution in variants:
            method = "REFERENCE" if label == "REFERENCE" else "FULL"
            if resolution is not None:
                quality = scene.subsplat.quality
                scene.subsplat.irradiance_resolution = resolution  # makes the quality manual
            if label == "FULL":  # the first FULL render pays for the context and shaders
                if args.scene_files:  # the case as the library receives it, for subsplat_replay
                    scene.subsplat.scene_file = os.path.join(args.scene_files, f"{name}_{model.lower()}.ssscene")
                accuracy.render_passes(scene, method, None)
                scene.subsplat.scene_file = ""
            image, exitance, stats = accuracy.render_passes(scene, method, args.reference_samples)
            if resolution is not None:
                scene.subsplat.quality = quality
            if truth is None:
                truth = truth_of(name, image.shape)
            if mask is None:
                mask = physical.mask_for(kind, exitance)
            m = physical.measure(kind, image, truth, mask)
            if method == "REFERENCE":
                reference = image
            else:
                m["frame_ms"] = stats.get("frame_ms")
                m["fragments"] = (stats.get("fragment_invocations") or {}).get("total")
                m["irradiance_resolution"] = stats.get("irradiance_resolution")
                # The image-space approximations' error: against REFERENCE of the same model.
                ours, theirs = image[mask][:, :3].astype(np.float64), reference[mask][:, :3].astype(np.float64)
                m["against_reference"] = float(np.sqrt(((ours - theirs) ** 2).mean() / (theirs ** 2).mean()))
            if label == "FULL":
                if model == "DIPOLE":
                    dipole_resolution = stats.get("irradiance_resolution")
                picture = os.path.join(args.images, f"{name}_{model.lower()}.png")
                m["picture"] = os.path.relpath(physical.write_picture(picture, image, truth, mask), ROOT)
            entry[label] = m
            print(f"{name} {model} {label}: {summary(kind, m)}" +
                  (f"  against REFERENCE {m['against_reference']:.4f}, {m['fragments']} fragments, "
                   f"{m['frame_ms']:.0f} ms at {m['irradiance_resolution']}²" if method == "FULL" else ""), flush=True)
        result["models"][model] = entry
    previous = committed.get(name, {})
    result["truth"] = {"image": os.path.relpath(os.path.join(twin_truth.DIRECTORY, f"{name}.exr"), ROOT),
                       **{k: v for k, v in previous.get("truth", {}).items()
                          if k in ("samples", "seeds", "channel_relative_standard_error", "image_relative_noise",
                                   "profile_relative_noise")}}
    result["size"] = list(truth.shape[:2])
    result["pixels"] = int(mask.sum())
    return result


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--cases", nargs="+", default=list(physical.KINDS))
    parser.add_argument("--only", nargs="*", default=None, help="case names (of the kinds asked for)")
    parser.add_argument("--reference-samples", type=int, default=200000)
    parser.add_argument("--output", default=os.path.join(HERE, "results", "model.json"))
    parser.add_argument("--images", default=os.path.join(ROOT, "docs", "images", "model"))
    parser.add_argument("--scene-files", default=None,
                        help="a folder: also save each case as FULL renders it, <case>_<model>.ssscene, for subsplat_replay")
    args = parser.parse_args(argv)
    helpers.enable_addon()
    os.makedirs(args.images, exist_ok=True)
    if args.scene_files:
        os.makedirs(args.scene_files, exist_ok=True)
    with open(os.path.join(HERE, "results", "physical.json")) as f:
        committed = json.load(f)["cases"]
    results = {}
    if os.path.exists(args.output):
        with open(args.output) as f:
            results = json.load(f)
    results.setdefault("cases", {})
    for name, kind, build, details in physical.cases(args.cases, committed_size(committed, "slab"),
                                                     committed_percentage(committed)):
        if args.only and name not in args.only:
            continue
        if "not_measured" in committed.get(name, {}):
            result = {"kind": kind, "not_measured": committed[name]["not_measured"]}
            print(f"{name}: not measured: {committed[name]['not_measured']}", flush=True)
        else:
            result = run_case(args, name, kind, build, details, committed)
        physical.save_case(results, name, result, "model.py", argv, args.output)
    print(f"wrote {args.output}")


def committed_size(committed, kind):
    """The built cases' size in pixels, as the truths were rendered."""
    sizes = {c["size"][1] for c in committed.values() if c.get("kind") == kind and "size" in c}
    if len(sizes) != 1:
        raise RuntimeError(f"bench/results/physical.json: {kind} cases of sizes {sorted(sizes)}")
    return sizes.pop()


def committed_percentage(committed):
    values = {c["percentage"] for c in committed.values() if c.get("kind") == "example" and "percentage" in c}
    if len(values) != 1:
        raise RuntimeError(f"bench/results/physical.json: examples at percentages {sorted(values)}")
    return values.pop()


if __name__ == "__main__":
    main()
