"""Committed physical truths (issue 18, item 4): the converged Cycles twin of a scene (subsplat.twin,
docs/PHYSICAL.md), rendered once by a benchmark and kept in bench/results/truth/ as three files per
scene: <stem>.exr, the mean of the seeds' renders (half float); <stem>_stderr.exr, its per-pixel
standard error (the seeds' scatter / sqrt(seeds)); <stem>.json, how it was made. bench/tradeoff.py
and bench/stability.py measure against them; a missing truth is an error, never a skip.

The error against a truth takes the truth's own noise out (error(); plain numpy, so that
tests/unit/test_twin_truth.py checks it without Blender: bpy is imported where it is used).
"""
import datetime
import json
import os
import time

import numpy as np

SOURCE = os.environ.get("SUBSPLAT_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
DIRECTORY = os.path.join(SOURCE, "bench", "results", "truth")


class MissingTruth(FileNotFoundError):
    pass


def make_twin(scene):
    """The scene's Cycles twin (rendered on the CPU, fixed seeds) and its warnings; raises where a
    material cannot be converted (a SubEdit file: no truth)."""
    import bpy
    import subsplat
    bpy.context.window.scene = scene
    twin, reports = subsplat.twin.make_cycles_twin(scene)
    warnings = [text for level, text in reports if level == "WARNING"]
    missing = [text for text in warnings if "is not converted" in text]
    if missing:
        raise RuntimeError(f"{scene.name}: the twin cannot convert it: " + "; ".join(missing))
    twin.cycles.device = "CPU"
    twin.cycles.use_animated_seed = False
    return twin, warnings


def render_twin(scene, twin, samples, seed, path):
    """One Cycles render of the twin: its image and seconds (the window shows `scene` again after)."""
    import bpy
    from subsplat_testing import helpers
    twin.cycles.samples = samples
    twin.cycles.seed = seed
    window = bpy.context.window
    window.scene = twin
    try:
        start = time.perf_counter()
        image = helpers.render_to(twin, path)
        return image, time.perf_counter() - start
    finally:
        window.scene = scene


def read_exr(path):
    import bpy
    image = bpy.data.images.load(path, check_existing=False)
    width, height = image.size
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)


def write_exr(path, image):
    """A half-float EXR of an image (its alpha set to 1); bench/physical.py writes its truths with it too."""
    import bpy
    h, w = image.shape[:2]
    picture = bpy.data.images.new(os.path.basename(path), w, h, alpha=True, float_buffer=True)
    rgba = np.array(image, dtype=np.float32)
    rgba[..., 3] = 1.0
    picture.pixels.foreach_set(rgba.ravel())
    picture.filepath_raw = path
    picture.file_format = "OPEN_EXR"
    settings = bpy.context.scene.render.image_settings
    settings.file_format, settings.color_depth, settings.exr_codec = "OPEN_EXR", "16", "ZIP"
    picture.save_render(path, scene=bpy.context.scene)
    bpy.data.images.remove(picture)


def paths(stem, directory=DIRECTORY):
    base = os.path.join(directory, stem)
    return base + ".exr", base + "_stderr.exr", base + ".json"


def render(stem, scene, twin, samples, seeds, scratch, record, directory=DIRECTORY):
    """Renders the truth (`seeds` renders of `samples` each, seeds 0 .. seeds - 1) and writes its three
    files; `record` (the command, what the scene is) goes into the JSON with the time and machine."""
    import bpy
    from subsplat_testing import helpers
    image_path, stderr_path, record_path = paths(stem, directory)
    os.makedirs(directory, exist_ok=True)
    per_seed, seconds = [], 0.0
    for seed in range(seeds):
        image, taken = render_twin(scene, twin, samples, seed, os.path.join(scratch, f"{stem}_seed{seed}.exr"))
        per_seed.append(image.astype(np.float64))
        seconds += taken
        print(f"{stem}: truth, seed {seed}, {samples} samples: {taken:.1f} s", flush=True)
    stack = np.stack(per_seed)
    mean, stderr = stack.mean(axis=0), np.sqrt(stack.var(axis=0, ddof=1) / seeds)
    write_exr(image_path, mean)
    write_exr(stderr_path, stderr)
    written = read_exr(image_path)[..., :3]  # half floats: within 0.1 % of the mean
    drift = np.sqrt(((written - mean[..., :3]) ** 2).mean() / max((mean[..., :3] ** 2).mean(), 1e-30))
    if drift > 1e-3:
        raise RuntimeError(f"{image_path}: the written image differs from the mean by {drift:.2e}")
    record = {**record, "samples": samples, "seeds": list(range(seeds)), "seconds": round(seconds, 2),
              "size": [int(mean.shape[1]), int(mean.shape[0])], "blender": bpy.app.version_string,
              "machine": helpers.machine(), "date": datetime.date.today().isoformat()}
    with open(record_path, "w") as f:
        json.dump(record, f, indent=1)
        f.write("\n")


def load(stem, shape=None, directory=DIRECTORY):
    """((mean, standard error), record) of a committed truth; MissingTruth where there is none, an
    error where its size is not `shape` (height, width)."""
    image_path, stderr_path, record_path = paths(stem, directory)
    for path in (image_path, stderr_path, record_path):
        if not os.path.exists(path):
            raise MissingTruth(f"no physical truth at {path}")
    truth = read_exr(image_path), read_exr(stderr_path)
    if shape is not None and truth[0].shape[:2] != tuple(shape[:2]):
        raise RuntimeError(f"{image_path} is {truth[0].shape[1]} x {truth[0].shape[0]}, the render "
                           f"{shape[1]} x {shape[0]}")
    with open(record_path) as f:
        return truth, json.load(f)


def error(image, truth, mask):
    """Relative RMSE of `image` against the truth (mean, standard error) over `mask`, rgb, with the
    truth's noise taken out: for a truth T of per-pixel variance s^2 about the converged T*, and an
    image I whose noise is independent of T's, E[(I - T)^2] = (I - T*)^2 + s^2 and
    E[T^2] = T*^2 + s^2; so sqrt((mean (I - T)^2 - mean s^2) / (mean T^2 - mean s^2)), s the
    standard error. Returns (that, the same without the correction, the truth's own relative noise
    sqrt(mean s^2 / (mean T^2 - mean s^2)), mean of I / mean of T)."""
    mean, stderr = truth
    ours, theirs = image[mask][:, :3].astype(np.float64), mean[mask][:, :3].astype(np.float64)
    variance = float((stderr[mask][:, :3].astype(np.float64) ** 2).mean())
    square = float((theirs ** 2).mean())
    difference = float(((ours - theirs) ** 2).mean())
    signal = square - variance
    return (float(np.sqrt(max(difference - variance, 0.0) / signal)), float(np.sqrt(difference / square)),
            float(np.sqrt(variance / signal)), float(ours.mean() / max(theirs.mean(), 1e-30)))
