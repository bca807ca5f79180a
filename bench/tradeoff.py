"""Speed against accuracy (issues 8 and 18): every real-time method over a sweep of its quality
settings, EEVEE's and Cycles' subsurface scattering at several sample counts, and the Cycles twin
(the physical answer) at several sample counts, on each example scene; a chart per scene and
docs/TRADEOFF.md.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        --python bench/tradeoff.py -- [--scenes skin_suzanne ...] [--percentage 25] \
        [--samples 200000] [--runs 3] [--eevee-samples 1 4 ...] \
        [--cycles-samples 4 16 ...] [--twin-samples 1 4 ...] [--render-truth] [--quick] [--output docs] \
        [--from-json docs/images/tradeoff/tradeoff.json]

One Blender run does everything for every scene:
- the examples the Cycles twin can convert (CONVERTIBLE: every translucent material a DIPOLE one) are
  rendered as subsplat_testing.physical.example_case(name, percentage, bounce=False): eta = 1 and
  specular 0 (a delta light reaches the twin's medium only through an index-matched boundary), open
  meshes closed, world black, opaque objects reflecting no light onto others (SubSplat has no
  interreflection). Their physical truth is the converged twin image committed in
  bench/results/truth/tradeoff_<scene>_<percentage>.exr (the mean of --truth-seeds renders) with
  its per-pixel standard error (..._stderr.exr); --render-truth renders a missing one, and without
  it a missing truth is an error (the test must fail, not skip). The SubEdit examples (candle_twist,
  heterogeneous) have no truth: the twin cannot convert a SubEdit file; they are rendered as before;
- REFERENCE is rendered in Blender (its combined image and exitance mask are the model's truth, and
  its translucent pixels are the ones measured);
- the scene is saved as the library receives it (a scene file) and `subsplat_replay` renders each
  SubSplat point `--runs` times in one native context: its time is the median frame, as in the
  viewport, where the context, meshes and materials stay from frame to frame;
- EEVEE and Cycles render the same scene, with each DIPOLE material given its Principled BSDF
  equivalent (tests/subsplat_testing/accuracy.py, principled_equivalent); their time is the wall time of
  a render after a first one (EEVEE compiles its shaders in the first).
- the twin renders at each --twin-samples count, one seed each (seeds 1000 + i, none of the truth's).
Errors, over REFERENCE's translucent pixels: relative RMSE of linear radiance against REFERENCE
("error": the image-space approximations of the model) and, where there is a truth, against it
("twin_error": the physical error) with the truth's own noise taken out: the truth's per-pixel
variance (its standard error squared, estimated from its seeds) is subtracted from the mean squared
difference and from the truth's mean square (twin_error_term).
"""
import argparse
import datetime
import json
import os
import subprocess
import sys
import tempfile
import time

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests"))  # subsplat_testing
from subsplat_testing import accuracy, helpers, physical, twin_truth  # noqa: E402
from subsplat_testing.accuracy import front_error_at, pareto  # noqa: E402

SCENES = ("skin_suzanne", "marble_pieces", "wax_jade", "finger_pose", "candle_twist", "heterogeneous")
CONVERTIBLE = ("skin_suzanne", "marble_pieces", "wax_jade", "finger_pose")  # every translucent material DIPOLE
TWIN_SEED = 1000  # the twin curve's seeds: TWIN_SEED + i, the truth's are 0 .. seeds - 1
DEFAULTS = {"irradiance": 512, "alpha": 15.0, "levels": 0, "epsilon": 0.001}  # manual quality's
AUTO_DEFAULT_TARGET = 0.01  # scene.subsplat.target_error's default
RUNGS = (128, 256, 512, 1024)


def sweep(kind):
    """(method, irradiance, alpha, levels, epsilon, target[, z0]) of every SubSplat point. irradiance 0 is
    the automatic quality (FULL, the resolution chosen for the target error, levels automatic)."""
    auto = [("AUTO", 0, 15.0, 0, 0.001, target) for target in (0.02, AUTO_DEFAULT_TARGET, 0.005)]
    if kind == "quick":
        return [("BRUTE", 128, 15.0, 0, 0.001, None), ("BRUTE", 512, 15.0, 0, 0.001, None),
                ("FULL", 512, 15.0, 0, 0.001, None), ("FULL", 256, 15.0, 3, 0.01, None),
                ("AUTO", 0, 15.0, 0, 0.001, AUTO_DEFAULT_TARGET)]
    if kind == "rungs":  # docs/AUTO.md's table: each rung's error and texels per R_P
        return [(m, r, 15.0, 0, 0.001, None) for r in RUNGS for m in ("BRUTE", "FULL")] + auto
    if kind == "auto":  # AUTO first; auto_sweep() chooses the rest from its resolution
        return [("AUTO", 0, 15.0, 0, 0.001, AUTO_DEFAULT_TARGET)]
    if kind == "defaults":
        return [("FULL", DEFAULTS["irradiance"], DEFAULTS["alpha"], DEFAULTS["levels"], DEFAULTS["epsilon"], None),
                ("AUTO", 0, 15.0, 0, 0.001, AUTO_DEFAULT_TARGET)]
    points = []
    for irradiance in RUNGS:
        points.append(("BRUTE", irradiance, 15.0, 0, 0.001, None))
    for irradiance in (256, 512):
        for levels in (0, 2, 3, 4):
            points.append(("MULTIRES", irradiance, 15.0, levels, 0.001, None))
    # (alpha and epsilon are swept at 512² and below; at 1024² only the levels, the costliest points)
    for irradiance in (512, 1024):
        for levels, alpha in ((0, 15.0), (3, 15.0), (3, 5.0), (3, 45.0))[:4 if irradiance < 1024 else 2]:
            points.append(("ADAPTIVE", irradiance, alpha, levels, 0.001, None))
    for irradiance in (256, 512, 1024):
        for levels, epsilon in ((0, 0.001), (3, 0.001), (3, 0.01), (3, 0.0001))[:4 if irradiance < 1024 else 2]:
            points.append(("FULL", irradiance, 15.0, levels, epsilon, None))
    points.append(("FULL", 512, 5.0, 3, 0.001, None))
    points.append(("FULL", 512, 45.0, 3, 0.001, None))
    for z0 in (0.003, 0.3):  # the depth threshold, as a factor of the bounding radius (default 0.03)
        points.append(("ADAPTIVE", 512, 15.0, 3, 0.001, None, z0))
        points.append(("FULL", 512, 15.0, 3, 0.001, None, z0))
    return points + auto


def auto_sweep(chosen):
    """What the AUTO test compares AUTO with, from the resolution it chose: FULL at that resolution
    and at every rung below it, BRUTE at the rungs below it (the points that can cost no more
    fragments than AUTO, FULL at its resolution, and so set the front at its cost), and BRUTE at
    twice it, up to 1024² (the finest point). A point at a finer resolution than AUTO's, or BRUTE at
    AUTO's, splats more than AUTO and cannot be on the front at its cost."""
    resolutions = sorted({r for r in RUNGS if r < chosen})
    points = [(m, r, 15.0, 0, 0.001, None) for r in resolutions for m in ("BRUTE", "FULL")]
    points.append(("FULL", chosen, 15.0, 0, 0.001, None))
    finest = min(2 * chosen, 1024)
    if finest not in resolutions:
        points.append(("BRUTE", finest, 15.0, 0, 0.001, None))
    return points


def label(method, irradiance, alpha, levels, epsilon, target=None, z0=None):
    if method == "AUTO":
        return f"AUTO {100 * target:g} %"
    return f"{method} {irradiance}² L{levels or 'auto'} α{alpha:g} ε{epsilon:g}" + (f" z0 {z0:g}" if z0 else "")


def is_default(method, irradiance, alpha, levels, epsilon, target=None, z0=None):
    if method == "AUTO":
        return target == AUTO_DEFAULT_TARGET
    return z0 is None and (irradiance, alpha, levels, epsilon) == tuple(DEFAULTS[k] for k in ("irradiance", "alpha", "levels", "epsilon"))


def arguments():
    parser = argparse.ArgumentParser(prog="bench/tradeoff.py")
    parser.add_argument("--scenes", nargs="+", default=list(SCENES))
    parser.add_argument("--percentage", type=int, default=25, help="resolution percentage of the 800x600 scenes")
    parser.add_argument("--samples", type=int, default=200000, help="REFERENCE surface samples")
    parser.add_argument("--runs", type=int, default=3, help="replay renders per SubSplat point (median)")
    parser.add_argument("--warmup", type=int, default=1,
                        help="replay renders before the timed ones (0: the first frame is timed, shader and "
                             "kernel-table set-up included; fragment counts are the same)")
    parser.add_argument("--eevee-samples", dest="eevee", type=int, nargs="+", default=[1, 4, 16, 64], help="EEVEE render samples")
    parser.add_argument("--cycles-samples", dest="cycles", type=int, nargs="+", default=[4, 16, 64, 256], help="Cycles samples")
    parser.add_argument("--twin-samples", dest="twin", type=int, nargs="*", default=[1, 4, 16, 64, 256],
                        help="the Cycles twin's samples (one seed each), on the scenes with a truth")
    parser.add_argument("--truth-samples", type=int, default=256, help="samples of each of the truth's renders")
    parser.add_argument("--truth-seeds", type=int, default=4, help="the truth's renders (their scatter is its noise)")
    parser.add_argument("--truth-dir", default=twin_truth.DIRECTORY, help="where the truth images are (and are written)")
    parser.add_argument("--render-truth", action="store_true",
                        help="render the truth of a scene that has none in --truth-dir (without it, that is an error)")
    parser.add_argument("--truth-only", action="store_true", help="only make sure each scene's truth exists")
    parser.add_argument("--as-is", action="store_true",
                        help="every example as it is (eta, specular, world, bounced light), against REFERENCE only "
                             "(the scenes docs/AUTO.md's bounds are stated for; no physical truth)")
    parser.add_argument("--quick", action="store_true", help="the reduced sweep (CI's chart test)")
    parser.add_argument("--sweep", choices=("full", "quick", "rungs", "auto", "defaults"), default=None,
                        help="which SubSplat points: every setting (default), the reduced one (--quick), BRUTE and "
                             "FULL at each irradiance rung with AUTO at three targets (docs/AUTO.md), AUTO and "
                             "the points around its choice (the AUTO test), or FULL at its manual defaults and "
                             "AUTO at its default target (the physical truth's test)")
    parser.add_argument("--no-foreign", dest="foreign", action="store_false", help="no EEVEE or Cycles points")
    parser.add_argument("--output", default=os.path.join(ROOT, "docs"), help="where TRADEOFF.md and images go")
    parser.add_argument("--replay", default=os.path.join(ROOT, "build", "native", "subsplat_replay"))
    parser.add_argument("--from-json", help="redraw the charts and the document from a tradeoff.json, measuring nothing")
    parser.add_argument("--note", default="", help="a paragraph for the document, on how its figures were taken")
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = parser.parse_args(argv)
    args.sweep = args.sweep or ("quick" if args.quick else "full")
    return args


def read_pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            raise ValueError(f"{path}: not a colour PFM")
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(height, width, 3)


def mean_ratio(image, truth, mask):
    return float(image[mask][:, :3].mean() / max(truth[mask][:, :3].mean(), 1e-30))


def relative_rmse(image, truth, mask):
    ours, theirs = image[mask][:, :3].astype(np.float64), truth[mask][:, :3].astype(np.float64)
    return float(np.sqrt(((ours - theirs) ** 2).mean()) / max(np.sqrt((theirs ** 2).mean()), 1e-30))


def robust_rmse(image, truth, mask):
    """relative_rmse without the worst 0.1 % of pixels (fireflies, shadow-test disagreements under a
    highlight: accuracy.compare's robust figure)."""
    ours, theirs = image[mask][:, :3].astype(np.float64), truth[mask][:, :3].astype(np.float64)
    squared = np.sort(((ours - theirs) ** 2).sum(axis=1))
    kept = squared[:len(squared) - max(1, len(squared) // 1000)]
    return float(np.sqrt(kept.mean() / 3.0) / max(np.sqrt((theirs ** 2).mean()), 1e-30))


# --- the physical truth: the Cycles twin ------------------------------------------------------

def open_scene(name, percentage, as_is=False):
    """The example as the chart renders it: a CONVERTIBLE one as its physical variant (the module's
    docstring), unless as_is; the others as they are."""
    if name in CONVERTIBLE and not as_is:
        scene, notes = physical.example_case(name, percentage, bounce=False)
        print(f"{name}: " + "; ".join(notes), flush=True)
        return scene
    return accuracy.open_example(name, percentage)


def truth_stem(args, name):
    return f"tradeoff_{name}_{args.percentage}"


def physical_truth(args, name, scene, twin, warnings, directory):
    """((mean, standard error), record) of a CONVERTIBLE scene's truth (subsplat_testing.twin_truth):
    read from --truth-dir, or, with --render-truth, rendered there first."""
    stem = truth_stem(args, name)
    if not os.path.exists(twin_truth.paths(stem, args.truth_dir)[0]):
        if not args.render_truth:
            raise twin_truth.MissingTruth(f"{name}: no physical truth at {twin_truth.paths(stem, args.truth_dir)[0]}; "
                                          f"render it with bench/tradeoff.py -- --scenes {name} --percentage "
                                          f"{args.percentage} --render-truth")
        twin_truth.render(stem, scene, twin, args.truth_samples, args.truth_seeds, directory, {
            "scene": name, "percentage": args.percentage, "variant": "physical.example_case(bounce=False)",
            "twin_warnings": warnings,
            "command": ("BLENDER_USER_SCRIPTS=build/scripts nice -n 19 blender -b --factory-startup --addons "
                        f"subsplat --python bench/tradeoff.py -- --scenes {name} --percentage {args.percentage} "
                        f"--truth-samples {args.truth_samples} --truth-seeds {args.truth_seeds} --render-truth "
                        "--truth-only")}, args.truth_dir)
    truth, record = twin_truth.load(stem, directory=args.truth_dir)
    _error, _raw, noise, _ratio = twin_truth.error(truth[0], truth, truth[0][..., :3].max(axis=-1) > 0)
    print(f"{name}: truth {record['samples']} samples x {len(record['seeds'])} seeds ({record['seconds']:.0f} s), "
          f"relative noise {noise:.4f} over every lit pixel", flush=True)
    return truth, record


def physical_figures(image, truth, mask):
    """The point's figures against the physical truth (none without one)."""
    if truth is None:
        return {}
    error, uncorrected, _noise, ratio = twin_truth.error(image, truth, mask)
    return {"twin_error": error, "twin_error_uncorrected": uncorrected, "twin_mean_ratio": ratio}


def reference_point(args, reference, ms, truth, record, mask):
    """REFERENCE as a point of the physical chart: the dipole model itself against the truth, and the
    truth's record (its time and noise)."""
    noise = twin_truth.error(reference, truth, mask)[2]
    return {"engine": "REFERENCE", "method": "REFERENCE", "label": f"REFERENCE {args.samples} samples",
            "settings": {"samples": args.samples}, "default": False, "ms": ms, "error": None,
            "mean_ratio": None, "robust_error": None, **physical_figures(reference, truth, mask),
            "truth": {"samples": record["samples"], "seeds": len(record["seeds"]), "seconds": record["seconds"],
                      "noise": noise, "machine": record["machine"]}}


def twin_points(args, name, scene, twin, reference, mask, truth, directory):
    """The Cycles twin at each of --twin-samples, one seed each (TWIN_SEED + i)."""
    twin_truth.render_twin(scene, twin, 1, TWIN_SEED - 1, os.path.join(directory, f"{name}_twin_warmup.exr"))  # loads kernels
    results = []
    for index, samples in enumerate(args.twin):
        image, seconds = twin_truth.render_twin(scene, twin, samples, TWIN_SEED + index,
                                     os.path.join(directory, f"{name}_twin_{samples}.exr"))
        if samples == max(args.twin):
            strip(args, name, "twin_physical", image, truth[0], mask)
        results.append({"engine": "Cycles twin", "method": "TWIN", "label": f"Cycles twin {samples} samples",
                        "settings": {"samples": samples, "seed": TWIN_SEED + index}, "default": False,
                        "ms": 1e3 * seconds, "error": relative_rmse(image, reference, mask),
                        "mean_ratio": mean_ratio(image, reference, mask),
                        "robust_error": robust_rmse(image, reference, mask), **physical_figures(image, truth, mask)})
        print(f"{name} {results[-1]['label']}: {results[-1]['ms']:.0f} ms, against the truth "
              f"{results[-1]['twin_error']:.4f} (uncorrected {results[-1]['twin_error_uncorrected']:.4f})", flush=True)
    return results


def subsplat_points(args, name, scene, truth, mask, directory, physical_truth=None):
    """Saves the scene as the library receives it and replays it for every SubSplat point; returns
    point dicts. `truth` is REFERENCE's image; `physical_truth` the twin's (mean, standard error) or
    None."""
    scene.render.engine = "SUBSPLAT"
    scene.subsplat.method = "FULL"
    scene.subsplat.samples = 1  # the methods are compared at one sample per pixel
    scene.subsplat.scene_file = os.path.join(directory, f"{name}.ssscene")
    bpy.ops.render.render()
    import subsplat
    if subsplat.last_render_error():
        raise RuntimeError(f"{name}: {subsplat.last_render_error()}")
    results = replay(args, name, scene, truth, mask, directory, sweep(args.sweep), physical_truth)
    if args.sweep == "auto":
        results += replay(args, name, scene, truth, mask, directory, auto_sweep(results[0]["irradiance_used"]),
                          physical_truth)
    return results


def replay(args, name, scene, truth, mask, directory, sweep_points, physical_truth=None):
    """Replays the scene file saved by subsplat_points for each point; returns point dicts."""
    groups = {}
    for point in sweep_points:
        point = tuple(point) + (None,) * (7 - len(point))  # z0 None: the saved (default) one
        groups.setdefault((point[1], point[2], point[5], point[6]), []).append(point)
    results = []
    for (irradiance, alpha, target, z0), points in groups.items():
        entries = {f"{'FULL' if m == 'AUTO' else m}:{levels}@{epsilon:g}": (m, irradiance, alpha, levels, epsilon, target, z0)
                   for m, _i, _a, levels, epsilon, _t, _z in points}
        what = f"auto{target:g}" if irradiance == 0 else str(irradiance)
        images = os.path.join(directory, f"{name}_{what}_{alpha:g}")
        os.makedirs(images, exist_ok=True)
        report = os.path.join(images, "report.json")
        command = [args.replay, "--warmup", str(args.warmup), "--runs", str(args.runs), "--no-reference",
                   "--irradiance", "auto" if irradiance == 0 else str(irradiance),
                   "--alpha", str(alpha), "--methods", ",".join(entries), "--images", images, "--json", report,
                   scene.subsplat.scene_file]
        if target is not None:
            command[1:1] = ["--target-error", str(target)]
        if z0 is not None:
            command[1:1] = ["--z0", str(z0)]
        print(" ".join(command), flush=True)
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        with open(report) as f:
            (entry,) = json.load(f)["scenes"]
        for figures in entry["methods"]:
            point = entries[figures["method"]]
            image = read_pfm(os.path.join(images, f"{name}_{figures['method']}.pfm"))
            error = relative_rmse(image, truth, mask)
            if is_default(*point) and point[0] in ("FULL", "AUTO"):
                strip(args, name, f"{point[0].lower()}_default", image, truth, mask)
                if physical_truth is not None:
                    strip(args, name, f"{point[0].lower()}_default_physical", image, physical_truth[0], mask)
            results.append({"engine": "SubSplat", "method": point[0], "label": label(*point),
                            "settings": dict(zip(("irradiance", "alpha", "levels", "epsilon", "target", "z0"), point[1:])),
                            "default": is_default(*point), "ms": figures["median_frame_ms"], "error": error,
                            "mean_ratio": mean_ratio(image, truth, mask),
                            "robust_error": robust_rmse(image, truth, mask),
                            "levels_used": [figures["levels"], figures["splat_levels"]],
                            "irradiance_used": figures["irradiance_resolution"],
                            "texels_per_range": figures["texels_per_range"],
                            "fragments": figures["fragment_invocations"]["total"],
                            **physical_figures(image, physical_truth, mask)})
            print(f"{name} {results[-1]['label']}: {results[-1]['ms']:.0f} ms, error {error:.4f}, "
                  + (f"against the truth {results[-1]['twin_error']:.4f}, " if physical_truth is not None else "") +
                  f"{figures['irradiance_resolution']}², {figures['texels_per_range']:.2f} texels per R_P", flush=True)
    return results


def strip(args, name, what, image, truth, mask):
    """images/tradeoff/<scene>_<what>.png: the image | `truth` (REFERENCE, or the twin's for
    *_physical) | error x10 (accuracy.write_strip)."""
    rgba = np.dstack([image[..., :3], np.ones(image.shape[:2] + (1,), dtype=np.float32)])
    path = os.path.join(args.output, "images", "tradeoff", f"{name}_{what}.png")
    accuracy.write_strip(path, rgba, truth, mask)
    return path


def foreign_points(args, name, scene, truth, mask, physical_truth=None):
    """EEVEE and Cycles on the scene, each DIPOLE material as its Principled equivalent."""
    for material in bpy.data.materials:
        if material.subsplat.enabled and material.subsplat.source == "DIPOLE":
            accuracy.principled_equivalent(material)
    # SubSplat and REFERENCE light with the scene's lights only (the world is a background colour),
    # so EEVEE and Cycles render without the world's light; Cycles keeps its light bounced off other
    # surfaces (2 diffuse bounces, as in docs/ACCURACY.md's slabs), which the others do not have.
    if scene.world is not None:
        scene.world.color = (0.0, 0.0, 0.0)
        if scene.world.use_nodes and scene.world.node_tree is not None:
            for node in scene.world.node_tree.nodes:
                if node.type == "BACKGROUND":
                    node.inputs["Strength"].default_value = 0.0
    scene.render.engine = "BLENDER_EEVEE"
    scene.eevee.taa_render_samples = 1
    helpers.render(scene, f"tradeoff_{name}_eevee_warmup")  # shaders compile in the first render

    def eevee(samples):
        scene.eevee.taa_render_samples = samples

    def cycles(samples):
        accuracy.use_cycles(scene, samples)

    results = []
    for engine, counts, prepare in (("EEVEE", args.eevee, eevee), ("Cycles", args.cycles, cycles)):
        for samples in counts:
            prepare(samples)
            start = time.perf_counter()
            image = helpers.render(scene, f"tradeoff_{name}_{engine.lower()}_{samples}")
            ms = 1e3 * (time.perf_counter() - start)
            if samples == max(counts):
                strip(args, name, engine.lower(), image, truth, mask)
                if physical_truth is not None:
                    strip(args, name, f"{engine.lower()}_physical", image, physical_truth[0], mask)
            results.append({"engine": engine, "method": engine, "label": f"{engine} {samples} samples",
                            "settings": {"samples": samples}, "default": False, "ms": ms,
                            "error": relative_rmse(image, truth, mask), "mean_ratio": mean_ratio(image, truth, mask),
                            "robust_error": robust_rmse(image, truth, mask),
                            **physical_figures(image, physical_truth, mask)})
            print(f"{name} {results[-1]['label']}: {ms:.0f} ms, error {results[-1]['error']:.4f}, "
                  f"mean / REFERENCE {results[-1]['mean_ratio']:.3f}"
                  + (f", against the truth {results[-1]['twin_error']:.4f}" if physical_truth is not None else ""),
                  flush=True)
    return results


MODEL_ENGINES = ("SubSplat", "EEVEE", "Cycles")  # the points measured against REFERENCE, on its front


def model_points(points):
    """The points the REFERENCE measure is for: SubSplat's approximations of the model, and EEVEE and
    Cycles Principled as before (REFERENCE itself and the twin are not approximations of it)."""
    return [p for p in points if p["engine"] in MODEL_ENGINES]


def physical_front(points):
    """The Pareto front of time against the error against the physical truth."""
    shown = [dict(p, error=p["twin_error"], index=i) for i, p in enumerate(points) if p.get("twin_error") is not None]
    return [points[p["index"]] for p in pareto(shown)]


def summary(points, front):
    """Lines on where the defaults and the other engines stand against the front (against
    REFERENCE: the image-space approximations of the model)."""
    lines = ["On the front: " + "; ".join(f"{p['label']} ({p['ms']:.0f} ms, {p['error']:.4f})" for p in front) + "."]
    for p in points:
        if p["default"] and p["method"] == "FULL":
            at = front_error_at(front, p["ms"])
            lines.append(f"FULL at its defaults: {p['ms']:.0f} ms, error {p['error']:.4f}; the front at that time "
                         f"{at:.4f} (default / front = {p['error'] / at:.2f}).")
    finest = min(p["error"] for p in points if p["engine"] == "SubSplat")
    for p in points:
        if p["method"] == "AUTO":
            at = front_error_at(pareto([q for q in points if q is not p]), p["ms"])
            lines.append(f"{p['label']}: chose {p['irradiance_used']}² ({p['texels_per_range']:.2f} texels per R_P), "
                         f"{p['ms']:.0f} ms, error {p['error']:.4f}; the front of the other points at that time "
                         f"{at:.4f} (AUTO / front = {p['error'] / at:.2f}); over the finest point's {finest:.4f} "
                         f"it adds {p['error'] - finest:.4f} (target {p['settings']['target']:g}).")
    for engine in ("EEVEE", "Cycles"):
        mine = [p for p in points if p["engine"] == engine]
        if mine:
            best = min(mine, key=lambda p: p["error"])
            lines.append(f"{engine} at best: {best['label']}, {best['ms']:.0f} ms, error {best['error']:.4f} "
                         f"(mean {best['mean_ratio']:.2f} x REFERENCE's).")
    return lines


def physical_summary(points):
    """Lines on the points against the physical truth: the model's own error (REFERENCE), SubSplat's
    defaults, the other engines, and the twin's curve (how long the physics takes to be as close)."""
    (reference,) = [p for p in points if p["engine"] == "REFERENCE"]
    truth = reference["truth"]
    twin = sorted((p for p in points if p["engine"] == "Cycles twin"), key=lambda p: p["settings"]["samples"])
    front = physical_front(points)

    def figure(p):
        return f"{p['twin_error']:.3f} (mean {p['twin_mean_ratio']:.2f} x the truth's)"

    lines = [f"The truth: the Cycles twin, {truth['samples']} samples x {truth['seeds']} seeds, "
             f"{truth['seconds']:.0f} s of Cycles on {truth['machine']}; its own noise over these pixels "
             f"{truth['noise']:.4f} (relative RMS of its per-pixel standard error), taken out of every figure.",
             f"REFERENCE (the dipole model, computed exactly): {figure(reference)}. No method that renders "
             "the model can do better than the model.",
             "On the front: " + "; ".join(f"{p['label']} ({p['ms']:.0f} ms, {p['twin_error']:.3f})" for p in front) + "."]
    defaults = [p for p in points if p["default"] and p["method"] in ("FULL", "AUTO")]
    for p in defaults:
        lines.append(f"{p['label']}{' at its defaults' if p['method'] == 'FULL' else ''}: {p['ms']:.0f} ms, "
                     f"{figure(p)}.")
    for engine, name in (("EEVEE", "EEVEE"), ("Cycles", "Cycles Principled")):
        mine = [p for p in points if p["engine"] == engine]
        if mine:
            best = min(mine, key=lambda p: p["twin_error"])
            lines.append(f"{name} at best: {best['label']}, {best['ms']:.0f} ms, {figure(best)}.")
    if twin:
        lines.append("The twin converges: " + "; ".join(
            f"{p['settings']['samples']} samples {p['twin_error']:.3f} ({p['ms']:.0f} ms)" for p in twin) + ".")
        full = [p for p in defaults if p["method"] == "FULL"]
        if full:
            (full,) = full
            reached = [p for p in twin if p["twin_error"] <= full["twin_error"]]
            if reached:
                lines.append(f"The twin is as close to the truth as FULL at its defaults from {reached[0]['label']} "
                             f"({reached[0]['ms']:.0f} ms, {reached[0]['ms'] / full['ms']:.1f} x FULL's "
                             f"{full['ms']:.0f} ms).")
            else:
                lines.append(f"The twin stays further from the truth than FULL at its defaults up to {twin[-1]['label']}.")
    return lines


STYLES = {"BRUTE": ("tab:gray", "s"), "MULTIRES": ("tab:blue", "^"), "ADAPTIVE": ("tab:green", "v"),
          "FULL": ("tab:red", "o"), "AUTO": ("black", "X"), "EEVEE": ("tab:purple", "D"), "Cycles": ("tab:orange", "P"),
          "REFERENCE": ("tab:brown", "h"), "TWIN": ("tab:cyan", "*")}
LEGEND = {"Cycles": "Cycles Principled", "TWIN": "Cycles twin (physics)", "REFERENCE": "REFERENCE (the model)"}
FLOOR = 1e-4  # an error drawn on a log axis below this is drawn at it


def chart(path, name, points):
    """The chart: time against the error against the physical truth (left) and against REFERENCE
    (right) where the scene has a truth; against REFERENCE alone where not."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    panels = []
    if any(p.get("twin_error") is not None for p in points):
        shown = [p for p in points if p.get("twin_error") is not None]
        panels.append((shown, "twin_error", physical_front(shown), "relative RMSE against the Cycles twin (log)",
                       f"{name}: against physical truth"))
    shown = model_points(points)
    panels.append((shown, "error", pareto(shown), "relative RMSE against REFERENCE (log)",
                   f"{name}: against REFERENCE (the model)" if panels else f"{name}: speed against accuracy"))
    figure, axes_row = plt.subplots(1, len(panels), figsize=(7.5 * len(panels), 5.0), dpi=100, squeeze=False)
    for axes, (shown, key, front, ylabel, title) in zip(axes_row[0], panels):
        def error(p):
            return max(p[key], FLOOR)
        for method, (colour, marker) in STYLES.items():
            mine = sorted((p for p in shown if p["method"] == method), key=lambda p: p["ms"])
            if not mine:
                continue
            if method == "REFERENCE":  # hollow and on top: it sits among the SubSplat points it is the model of
                axes.scatter([p["ms"] for p in mine], [error(p) for p in mine], marker=marker, s=150,
                             facecolors="none", edgecolors=colour, linewidths=1.8, zorder=5,
                             label=LEGEND.get(method, method))
                continue
            axes.scatter([p["ms"] for p in mine], [error(p) for p in mine], c=colour, marker=marker,
                         s=90 if method == "TWIN" else 36, label=LEGEND.get(method, method), alpha=0.85,
                         edgecolors="none")
            if method == "TWIN":
                axes.plot([p["ms"] for p in mine], [error(p) for p in mine], color=colour, lw=1.0)
                for p in mine:
                    axes.annotate(f"{p['settings']['samples']}", (p["ms"], error(p)), textcoords="offset points",
                                  xytext=(4, 4), fontsize=7, color="tab:blue")
        defaults = [p for p in shown if p["default"]]
        axes.scatter([p["ms"] for p in defaults], [error(p) for p in defaults], s=220, marker="*",
                     facecolors="none", edgecolors="black", linewidths=1.2, label="default settings")
        axes.step([p["ms"] for p in front], [error(p) for p in front], where="post", color="black", lw=1.0,
                  ls="--", label="Pareto front")
        axes.set_xscale("log")
        axes.set_yscale("log")
        axes.set_xlabel("frame time (ms, log)")
        axes.set_ylabel(ylabel)
        axes.set_title(title)
        axes.grid(True, which="both", alpha=0.3)
        axes.legend(fontsize=8, loc="best")
    figure.tight_layout()
    figure.savefig(path)
    plt.close(figure)


def _figure(value, digits=4):
    return "–" if value is None else f"{value:.{digits}f}"


def write_document(args, results):
    command = ("BLENDER_USER_SCRIPTS=build/scripts nice -n 19 blender -b --factory-startup --addons subsplat "
               f"--python bench/tradeoff.py -- --scenes {' '.join(args.scenes)} --percentage {args.percentage} "
               f"--samples {args.samples} --runs {args.runs} --eevee-samples {' '.join(map(str, args.eevee))} "
               f"--cycles-samples {' '.join(map(str, args.cycles))} --twin-samples {' '.join(map(str, args.twin))}"
               + (f" --sweep {args.sweep}" if args.sweep != "full" else "") + ("" if args.foreign else " --no-foreign")
               + (" --as-is" if args.as_is else ""))
    physical_scenes = [n for n, points in results.items() if any(p["engine"] == "REFERENCE" for p in points)]
    other_scenes = [n for n in results if n not in physical_scenes]
    lines = ["# Speed against accuracy", "",
             "Generated by `bench/tradeoff.py`; do not edit by hand. Rerun with", "", f"    {command}", "",
             f"Taken {datetime.date.today().isoformat()} on {helpers.machine()}, Blender {bpy.app.version_string}, "
             "OpenGL: Mesa llvmpipe (the GPU is the CPU here: times are for comparing methods with each other "
             "in one run, not for a GPU).", "",
             f"Each scene at {args.percentage} % of 800 x 600. Two measures of error, each the relative RMSE of "
             "linear radiance over REFERENCE's translucent pixels:", "",
             "- **against the physical truth** (the chart's main axis, where there is one): the scene's Cycles "
             "twin (docs/PHYSICAL.md: every translucent material its medium as a volume, rendered by Cycles' "
             "volumetric path tracer), converged. This is how far a picture is from what light does in the "
             "medium. It includes the dipole model's own error, which REFERENCE shows alone;",
             f"- **against REFERENCE** ({args.samples} surface samples), the model computed exactly: how far a "
             "method's image-space approximations (irradiance buffer, splatting levels, sample selection) take "
             "it from its own model. It is the measure the method settings and AUTO are tuned and tested on "
             "(docs/AUTO.md).", "",
             "**The model.** Every material with coefficients renders the classical dipole (profile_model "
             "DIPOLE; `physical.example_case` pins it): the chart measures the paper's model and its "
             "image-space approximations. The default model since issue 19, TABULATED, against the same "
             "truths: docs/PHYSICAL.md, \"The model: before and after\".", "",
             "**Which scenes have a truth.** " + (", ".join(physical_scenes) if physical_scenes else
                                                  "None here (--as-is, or only SubEdit examples); where there "
                                                  "is one") + ": every translucent "
             "material is a DIPOLE one, so the twin converts it. These are rendered, by every engine, as their "
             "physical variant (`physical.example_case(name, percentage, bounce=False)`, "
             "tests/subsplat_testing/physical.py): each translucent material at eta = 1 and specular 0, "
             "because a delta light (the examples' suns, points and spots) cannot reach the twin's medium "
             "through a refracting boundary; open meshes closed (the medium needs an inside); the world "
             "black (SubSplat does not light with it yet); opaque objects seen and casting shadows but "
             "reflecting no light onto others (SubSplat has no interreflection, so this isolates the "
             "translucency). Their REFERENCE figures therefore differ from earlier versions of this page, which "
             "rendered the examples as they are. "
             + (", ".join(other_scenes) + " use SubEdit files, whose media have no coefficients the twin could "
                "use: they have **no physical truth**, are rendered as they are, and are charted against "
                "REFERENCE only." if other_scenes else ""), "",
             "**The truth and its noise.** Each truth is committed in bench/results/truth/ "
             f"(`tradeoff_<scene>_{args.percentage}.exr`, the mean of its seeds' renders, half float; "
             "`..._stderr.exr`, its per-pixel standard error, from the scatter of the seeds; `.json`, how it "
             "was made) and reused on reruns; a missing one is an error (`--render-truth` renders it). "
             "Its noise is taken out of every error against it: for a truth T with per-pixel variance s² "
             "about the converged T*, and an image I whose noise is independent of T's, "
             "E[(I - T)²] = (I - T*)² + s² and E[T²] = T*² + s², so the error is "
             "sqrt((mean (I - T)² - mean s²) / (mean T² - mean s²)), s² the squared standard error. The "
             "table also gives it without the correction.", "",
             f"**The twin's own curve.** The twin at {', '.join(map(str, args.twin))} samples, one render each "
             f"with seeds {TWIN_SEED} and up (the truth's are 0 and up, so their noises are independent): "
             "its error against the truth goes to zero as it converges; the time it takes is what "
             "SubSplat's speed is measured against.", "",
             "Time: SubSplat, the median of "
             f"{args.runs} frames replayed in one native context (what a viewport frame costs, export aside), "
             f"after {args.warmup} warm-up frame{'' if args.warmup == 1 else 's'}; EEVEE, Cycles Principled and the twin, the wall time of a Blender render "
             "after a first one; REFERENCE, the wall time of its render (both passes).",
             "Stars mark SubSplat's default settings: AUTO at its 1 % target (the default quality, docs/AUTO.md) "
             "and the manual quality's defaults (512² irradiance, automatic levels, alpha 15, epsilon 0.001); "
             "the dashed line is the Pareto front: against the truth over every point, against REFERENCE "
             "over SubSplat's, EEVEE's and Cycles Principled's.", ""]
    if args.note:
        lines += [args.note, ""]
    for name, points in results.items():
        has_truth = name in physical_scenes
        shown = model_points(points)
        front = pareto(shown)
        twin_front = physical_front(points) if has_truth else []
        lines += [f"## {name}", "", f"![{name}](images/tradeoff/{name}.png)", ""]
        if has_truth:
            lines += ["Against the physical truth (image | the twin's truth | error x10, blue 0 to red 10 % of the "
                      "mean): REFERENCE, FULL at its manual defaults, AUTO at its default target, "
                      f"EEVEE at {max(args.eevee)} samples, Cycles Principled at {max(args.cycles)} samples, the "
                      f"twin at {max(args.twin)} samples.", ""]
            lines += [f"![{what}](images/tradeoff/{name}_{what}_physical.png)" + "\n"
                      for what in ("reference", "full_default", "auto_default", "eevee", "cycles", "twin")
                      if os.path.exists(os.path.join(args.output, "images", "tradeoff", f"{name}_{what}_physical.png"))]
            lines += [*[f"- {line}" for line in physical_summary(points)], ""]
        lines += ["Against REFERENCE (image | REFERENCE | error x10): FULL at its manual defaults, "
                  f"EEVEE at {max(args.eevee)} samples, Cycles at {max(args.cycles)} samples.", "",
                  f"![FULL](images/tradeoff/{name}_full_default.png)", "",
                  *([f"AUTO at its default target: ![AUTO](images/tradeoff/{name}_auto_default.png)", ""]
                    if any(p["method"] == "AUTO" and p["default"] for p in points) else []),
                  f"![EEVEE](images/tradeoff/{name}_eevee.png)", "",
                  f"![Cycles](images/tradeoff/{name}_cycles.png)", "",
                  *[f"- {line}" for line in summary(shown, front)], ""]
        if has_truth:
            lines += ["| engine | point | ms | against the truth | (uncorrected) | mean / truth | against REFERENCE "
                      "| without the worst 0.1 % | mean / REFERENCE | front (truth) | front (REFERENCE) |",
                      "|---|---|---|---|---|---|---|---|---|---|---|"]
        else:
            lines += ["| engine | point | ms | against REFERENCE | without the worst 0.1 % | mean / REFERENCE "
                      "| front (REFERENCE) |", "|---|---|---|---|---|---|---|"]
        for p in sorted(points, key=lambda p: (p["method"], p["ms"])):
            row = [p["engine"], p["label"] + (" (default)" if p["default"] else ""), f"{p['ms']:.0f}"]
            if has_truth:
                row += [_figure(p.get("twin_error")), _figure(p.get("twin_error_uncorrected")),
                        _figure(p.get("twin_mean_ratio"), 3)]
            row += [_figure(p.get("error")), _figure(p.get("robust_error")), _figure(p.get("mean_ratio"))]
            if has_truth:
                row.append("yes" if p in twin_front else "")
            row.append("yes" if p in front else "")
            lines.append("| " + " | ".join(row) + " |")
        lines.append("")
    lines += ["## The same materials in EEVEE and Cycles", "",
              "Each DIPOLE material becomes a Principled BSDF (`principled_equivalent` in tests/subsplat_testing/accuracy.py): "
              "Random Walk subsurface, Subsurface Radius = 1 / sigma_t' per channel in scene units, Subsurface "
              "Color (and Base Color) = the surface albedo whose random walk has single-scattering albedo "
              "sigma_s' / sigma_t' (the inverse of Cycles 3.x's albedo mapping), Subsurface = 1, IOR = eta, "
              "our roughness and specular; EEVEE gets Subsurface Translucency. EEVEE's screen-space SSS "
              "uses the same inputs with its own (Christensen-Burley) profile. Heterogeneous (SubEdit) "
              "materials (candle_twist, heterogeneous) are not converted: EEVEE and Cycles render them with "
              "the material's own surface nodes, so their EEVEE and Cycles points say what a user gets "
              "without SubSplat, not the closest those engines can do, which is still to be written (EEVEE "
              "ignores a textured radius).", ""]
    path = os.path.join(args.output, "TRADEOFF.md")
    with open(path, "w") as f:
        f.write("\n".join(lines))
    with open(os.path.join(args.output, "images", "tradeoff", "tradeoff.json"), "w") as f:
        json.dump(results, f, indent=1)
    print(f"wrote {path}", flush=True)
    return path


def main():
    args = arguments()
    helpers.enable_addon()
    images = os.path.join(args.output, "images", "tradeoff")
    os.makedirs(images, exist_ok=True)
    if args.from_json:
        with open(args.from_json) as f:
            results = json.load(f)
        args.scenes = list(results)
        for name, points in results.items():
            chart(os.path.join(images, f"{name}.png"), name, points)
        write_document(args, results)
        return
    results = {}
    with tempfile.TemporaryDirectory() as directory:
        for name in args.scenes:
            scene = open_scene(name, args.percentage, args.as_is)
            twin = truth = None
            if name in CONVERTIBLE and not args.as_is:
                twin, warnings = twin_truth.make_twin(scene)
                truth, record = physical_truth(args, name, scene, twin, warnings, directory)
            if args.truth_only:
                continue
            start = time.perf_counter()
            reference, reference_b, _ = accuracy.render_passes(scene, "REFERENCE", args.samples)
            reference_ms = 1e3 * (time.perf_counter() - start)
            mask = reference_b[..., 3] > 0.5
            points = []
            if truth is not None:
                if truth[0].shape != reference.shape:
                    raise RuntimeError(f"{name}: the truth is {truth[0].shape[1]} x {truth[0].shape[0]}, the render "
                                       f"{reference.shape[1]} x {reference.shape[0]}")
                points.append(reference_point(args, reference, reference_ms, truth, record, mask))
                strip(args, name, "reference_physical", reference, truth[0], mask)
            points += subsplat_points(args, name, scene, reference, mask, directory, truth)
            if args.foreign:
                points += foreign_points(args, name, scene, reference, mask, truth)
            if twin is not None and args.twin:
                points += twin_points(args, name, scene, twin, reference, mask, truth, directory)
            results[name] = points
            chart(os.path.join(images, f"{name}.png"), name, points)
    if not args.truth_only:
        write_document(args, results)


if __name__ == "__main__":
    main()
