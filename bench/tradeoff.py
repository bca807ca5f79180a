"""Speed against accuracy (issue 8): every real-time method over a sweep of its quality settings,
EEVEE's and Cycles' subsurface scattering at several sample counts, and REFERENCE as the truth, on
each example scene; a chart per scene and docs/TRADEOFF.md.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        --python bench/tradeoff.py -- [--scenes skin_suzanne ...] [--percentage 25] \
        [--samples 200000] [--runs 3] [--eevee-samples 1 4 ...] \
        [--cycles-samples 4 16 ...] [--quick] [--output docs] [--from-json docs/images/tradeoff/tradeoff.json]

One Blender run does everything for every scene:
- REFERENCE is rendered in Blender (its combined image and exitance mask are the truth);
- the scene is saved as the library receives it (a scene file) and `subsplat_replay` renders each
  SubSplat point `--runs` times in one native context: its time is the median frame, as in the
  viewport, where the context, meshes and materials stay from frame to frame;
- EEVEE and Cycles render the same scene, with each DIPOLE material given its Principled BSDF
  equivalent (tests/subsplat_testing/accuracy.py, principled_equivalent); their time is the wall time of
  a render after a first one (EEVEE compiles its shaders in the first).
Error: relative RMSE of linear radiance against REFERENCE over REFERENCE's translucent pixels.
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
from subsplat_testing import accuracy, helpers  # noqa: E402
from subsplat_testing.accuracy import front_error_at, pareto  # noqa: E402

SCENES = ("skin_suzanne", "marble_pieces", "wax_jade", "finger_pose", "candle_twist", "heterogeneous")
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
    """What the AUTO test compares AUTO with, from the resolution it chose: BRUTE and FULL at that
    resolution and at every rung up to 1.5 times it (the points that can be as fast as AUTO, which
    set the front at its time), and BRUTE at twice it, up to 1024² (the finest point)."""
    resolutions = sorted({r for r in RUNGS if r <= 1.5 * chosen} | {chosen})
    points = [(m, r, 15.0, 0, 0.001, None) for r in resolutions for m in ("BRUTE", "FULL")]
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
    parser.add_argument("--eevee-samples", dest="eevee", type=int, nargs="+", default=[1, 4, 16, 64], help="EEVEE render samples")
    parser.add_argument("--cycles-samples", dest="cycles", type=int, nargs="+", default=[4, 16, 64, 256], help="Cycles samples")
    parser.add_argument("--quick", action="store_true", help="the reduced sweep (CI's chart test)")
    parser.add_argument("--sweep", choices=("full", "quick", "rungs", "auto"), default=None,
                        help="which SubSplat points: every setting (default), the reduced one (--quick), BRUTE and "
                             "FULL at each irradiance rung with AUTO at three targets (docs/AUTO.md), or AUTO and "
                             "the points around its choice (the AUTO test)")
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


def subsplat_points(args, name, scene, truth, mask, directory):
    """Saves the scene as the library receives it and replays it for every SubSplat point; returns
    point dicts."""
    scene.render.engine = "SUBSPLAT"
    scene.subsplat.method = "FULL"
    scene.subsplat.scene_file = os.path.join(directory, f"{name}.ssscene")
    bpy.ops.render.render()
    import subsplat
    if subsplat.last_render_error():
        raise RuntimeError(f"{name}: {subsplat.last_render_error()}")
    results = replay(args, name, scene, truth, mask, directory, sweep(args.sweep))
    if args.sweep == "auto":
        results += replay(args, name, scene, truth, mask, directory, auto_sweep(results[0]["irradiance_used"]))
    return results


def replay(args, name, scene, truth, mask, directory, sweep_points):
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
        command = [args.replay, "--warmup", "1", "--runs", str(args.runs), "--no-reference",
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
            results.append({"engine": "SubSplat", "method": point[0], "label": label(*point),
                            "settings": dict(zip(("irradiance", "alpha", "levels", "epsilon", "target", "z0"), point[1:])),
                            "default": is_default(*point), "ms": figures["median_frame_ms"], "error": error,
                            "mean_ratio": mean_ratio(image, truth, mask),
                            "robust_error": robust_rmse(image, truth, mask),
                            "levels_used": [figures["levels"], figures["splat_levels"]],
                            "irradiance_used": figures["irradiance_resolution"],
                            "texels_per_range": figures["texels_per_range"],
                            "fragments": figures["fragment_invocations"]["total"]})
            print(f"{name} {results[-1]['label']}: {results[-1]['ms']:.0f} ms, error {error:.4f}, "
                  f"{figures['irradiance_resolution']}², {figures['texels_per_range']:.2f} texels per R_P", flush=True)
    return results


def strip(args, name, what, image, truth, mask):
    """images/tradeoff/<scene>_<what>.png: the image | REFERENCE | error x10 (accuracy.write_strip)."""
    rgba = np.dstack([image[..., :3], np.ones(image.shape[:2] + (1,), dtype=np.float32)])
    path = os.path.join(args.output, "images", "tradeoff", f"{name}_{what}.png")
    accuracy.write_strip(path, rgba, truth, mask)
    return path


def foreign_points(args, name, scene, truth, mask):
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
            results.append({"engine": engine, "method": engine, "label": f"{engine} {samples} samples",
                            "settings": {"samples": samples}, "default": False, "ms": ms,
                            "error": relative_rmse(image, truth, mask), "mean_ratio": mean_ratio(image, truth, mask),
                            "robust_error": robust_rmse(image, truth, mask)})
            print(f"{name} {results[-1]['label']}: {ms:.0f} ms, error {results[-1]['error']:.4f}, "
                  f"mean / REFERENCE {results[-1]['mean_ratio']:.3f}", flush=True)
    return results


def summary(points, front):
    """Lines on where the defaults and the other engines stand against the front."""
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


def chart(path, name, points, front):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    styles = {"BRUTE": ("tab:gray", "s"), "MULTIRES": ("tab:blue", "^"), "ADAPTIVE": ("tab:green", "v"),
              "FULL": ("tab:red", "o"), "AUTO": ("black", "X"), "EEVEE": ("tab:purple", "D"), "Cycles": ("tab:orange", "P")}
    figure, axes = plt.subplots(figsize=(7.5, 5.0), dpi=100)
    for method, (colour, marker) in styles.items():
        mine = [p for p in points if p["method"] == method]
        if mine:
            axes.scatter([p["ms"] for p in mine], [p["error"] for p in mine], c=colour, marker=marker, s=36,
                         label=method, alpha=0.85, edgecolors="none")
    defaults = [p for p in points if p["default"]]
    axes.scatter([p["ms"] for p in defaults], [p["error"] for p in defaults], s=220, marker="*", facecolors="none",
                 edgecolors="black", linewidths=1.2, label="default settings")
    axes.step([p["ms"] for p in front], [p["error"] for p in front], where="post", color="black", lw=1.0,
              ls="--", label="Pareto front")
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("frame time (ms, log)")
    axes.set_ylabel("relative RMSE against REFERENCE (log)")
    axes.set_title(f"{name}: speed against accuracy")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8, loc="best")
    figure.tight_layout()
    figure.savefig(path)
    plt.close(figure)


def _figure(value):
    return "–" if value is None else f"{value:.4f}"


def write_document(args, results):
    command = ("BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat "
               f"--python bench/tradeoff.py -- --scenes {' '.join(args.scenes)} --percentage {args.percentage} "
               f"--samples {args.samples} --runs {args.runs} --eevee-samples {' '.join(map(str, args.eevee))} "
               f"--cycles-samples {' '.join(map(str, args.cycles))}" + (f" --sweep {args.sweep}" if args.sweep != "full" else "")
               + ("" if args.foreign else " --no-foreign"))
    lines = ["# Speed against accuracy", "",
             "Generated by `bench/tradeoff.py`; do not edit by hand. Rerun with", "", f"    {command}", "",
             f"Taken {datetime.date.today().isoformat()} on {helpers.machine()}, Blender {bpy.app.version_string}, "
             "OpenGL: Mesa llvmpipe (the GPU is the CPU here: times are for comparing methods with each other "
             "in one run, not for a GPU).", "",
             f"Each scene at {args.percentage} % of 800 x 600; REFERENCE with {args.samples} surface samples is the "
             "truth. Error: relative RMSE of linear radiance over REFERENCE's translucent pixels. Time: SubSplat, "
             f"the median of {args.runs} frames replayed in one native context (what a viewport frame costs, "
             "export aside); EEVEE and Cycles, the wall time of a Blender render after a first one.",
             "Stars mark SubSplat's default settings: AUTO at its 1 % target (the default quality, docs/AUTO.md) "
             "and the manual quality's defaults (512² irradiance, automatic levels, alpha 15, epsilon 0.001); "
             "the dashed line is the Pareto front over every engine. Each SubSplat point renders one warm-up "
             "frame first, which is not counted.", ""]
    if args.note:
        lines += [args.note, ""]
    for name, points in results.items():
        front = pareto(points)
        lines += [f"## {name}", "", f"![{name}](images/tradeoff/{name}.png)", "",
                  "Strips (image | REFERENCE | error x10, blue 0 to red 10 % of the mean): FULL at its manual defaults, "
                  f"EEVEE at {max(args.eevee)} samples, Cycles at {max(args.cycles)} samples.", "",
                  f"![FULL](images/tradeoff/{name}_full_default.png)", "",
                  *([f"AUTO at its default target: ![AUTO](images/tradeoff/{name}_auto_default.png)", ""]
                    if any(p["method"] == "AUTO" and p["default"] for p in points) else []),
                  f"![EEVEE](images/tradeoff/{name}_eevee.png)", "",
                  f"![Cycles](images/tradeoff/{name}_cycles.png)", "",
                  *[f"- {line}" for line in summary(points, front)], "",
                  "| engine | point | ms | relative RMSE | without the worst 0.1 % | mean / REFERENCE | on the front |",
                  "|---|---|---|---|---|---|---|"]
        for p in sorted(points, key=lambda p: (p["method"], p["ms"])):
            lines.append(f"| {p['engine']} | {p['label']}{' (default)' if p['default'] else ''} | {p['ms']:.0f} | "
                         f"{p['error']:.4f} | {_figure(p.get('robust_error'))} | {_figure(p.get('mean_ratio'))} | "
                         f"{'yes' if p in front else ''} |")
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
            chart(os.path.join(images, f"{name}.png"), name, points, pareto(points))
        write_document(args, results)
        return
    results = {}
    with tempfile.TemporaryDirectory() as directory:
        for name in args.scenes:
            scene = accuracy.open_example(name, args.percentage)
            truth, truth_b, _ = accuracy.render_passes(scene, "REFERENCE", args.samples)
            mask = truth_b[..., 3] > 0.5
            points = subsplat_points(args, name, scene, truth, mask, directory)
            if args.foreign:
                points += foreign_points(args, name, scene, truth, mask)
            results[name] = points
            chart(os.path.join(images, f"{name}.png"), name, points, pareto(points))
    write_document(args, results)


if __name__ == "__main__":
    main()
