"""Stability (docs/STABILITY.md): where the methods stay put and where they do not.

- Flicker under a slowly moving light, the limitation the paper admits: the skin Suzanne's lights
  turn 0.5 degrees a frame about the vertical for 60 frames. A method's flicker is its mean
  frame-to-frame change over the translucent pixels, relative to REFERENCE's mean radiance; its
  excess is that minus REFERENCE's own (the change the light's motion really makes). FULL's excess
  is bounded.
- Deformation: the candle bends and twists over frames 1-48; FULL's error against REFERENCE before,
  during and after stays within its error at rest (see DEFORMATION_PERCENTAGE's comment).
Figures are printed; a plot and strips go to $SUBSPLAT_TEST_OUTPUT/stability_*.png.
"""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import helpers  # noqa: E402

subsplat = helpers.enable_addon()
import accuracy  # noqa: E402
import mathutils  # noqa: E402
import numpy as np  # noqa: E402

FRAMES = 60
DEGREES_PER_FRAME = 0.5
# The flicker scene at 10 % of 800 x 600 with the paper's 3 levels forced: at that size the
# automatic choice is one level, and FULL would be BRUTE. (Its adaptive selection still keeps
# every sample at the finest level here, docs/STABILITY.md.)
FLICKER_PERCENTAGE, FLICKER_LEVELS, FLICKER_SAMPLES = 10, 3, 10000
# FULL's excess was 0.001 at 16 % (docs/STABILITY.md); the bound leaves room for
# the noise of REFERENCE's fewer samples here, and catches flicker of a percent of the radiance.
FULL_EXCESS_FLICKER = 0.01
# Deformation: the candle at 20 %. Its error at rest (frame 1) is the static bound: at every frame
# FULL's exitance error stays within twice it (the bend shows more silhouette, where exitance
# errors sit), and its radiance error (without the worst 0.1 % of pixels, see test_accuracy.py)
# within 1.5 x test_accuracy.py's static bound on BRUTE.
DEFORMATION_PERCENTAGE, DEFORMATION_SAMPLES = 20, 50000
EXITANCE_OVER_REST = 2.0
ROBUST_BOUND = 1.5 * 0.02


def flicker(frames, mask):
    """Mean over frame pairs of the mean |I(t+1) - I(t)| over the mask."""
    return float(np.mean([np.abs(b[mask][:, :3] - a[mask][:, :3]).mean() for a, b in zip(frames, frames[1:])]))


def plot(path, changes, scale):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(7.5, 4.0), dpi=100)
    for method, values in changes.items():
        axes.plot(np.arange(1, len(values) + 1), np.asarray(values) / scale, label=method,
                  lw=2.0 if method == "REFERENCE" else 1.0, color="black" if method == "REFERENCE" else None)
    axes.set_xlabel("frame")
    axes.set_ylabel("mean |I(t) - I(t-1)| / mean REFERENCE")
    axes.set_title(f"Frame-to-frame change, light turning {DEGREES_PER_FRAME} degrees a frame")
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path)
    plt.close(figure)


class MovingLight(unittest.TestCase):
    METHODS = ("REFERENCE", "BRUTE", "FULL")  # MULTIRES and ADAPTIVE: docs/STABILITY.md

    def test_full_flickers_little_more_than_reference(self):
        scene = accuracy.open_example("skin_suzanne", FLICKER_PERCENTAGE)
        scene.subsplat.levels = FLICKER_LEVELS
        lights = [(o, o.matrix_world.copy()) for o in scene.objects if o.type == "LIGHT"]
        frames = {m: [] for m in self.METHODS}
        masks = []
        for t in range(FRAMES):
            turn = mathutils.Matrix.Rotation(math.radians(DEGREES_PER_FRAME * t), 4, "Z")
            for light, rest in lights:
                light.matrix_world = turn @ rest
            for method in self.METHODS:
                image, exitance, _ = accuracy.render_passes(scene, method, FLICKER_SAMPLES)
                frames[method].append(image)
                if method == "REFERENCE":
                    masks.append(exitance[..., 3] > 0.5)
        mask = np.logical_and.reduce(masks)
        scale = float(np.mean([f[mask][:, :3].mean() for f in frames["REFERENCE"]]))
        figures = {m: flicker(frames[m], mask) / scale for m in self.METHODS}
        excess = {m: figures[m] - figures["REFERENCE"] for m in self.METHODS}
        changes = {m: [np.abs(b[mask][:, :3] - a[mask][:, :3]).mean() for a, b in zip(frames[m], frames[m][1:])]
                   for m in self.METHODS}
        plot(os.path.join(helpers.OUTPUT, "stability_flicker.png"), changes, scale)
        for method in ("BRUTE", "FULL"):
            accuracy.write_strip(os.path.join(helpers.OUTPUT, f"stability_flicker_{method.lower()}.png"),
                                 frames[method][-1], frames["REFERENCE"][-1], mask)
        print("flicker (mean frame-to-frame change / mean REFERENCE): "
              + ", ".join(f"{m} {figures[m]:.5f} (excess {excess[m]:+.5f})" for m in self.METHODS), flush=True)
        self.assertGreater(figures["REFERENCE"], 0.0, "the light moves")
        self.assertLess(excess["FULL"], FULL_EXCESS_FLICKER)


class Deformation(unittest.TestCase):
    def test_error_through_the_bend_stays_within_the_static_bound(self):
        scene = accuracy.open_example("candle_twist", DEFORMATION_PERCENTAGE)
        errors = {}
        for frame in (1, 12, 24, 36, 48):
            scene.frame_set(frame)
            reference, reference_b, _ = accuracy.render_passes(scene, "REFERENCE", DEFORMATION_SAMPLES)
            image, image_b, _ = accuracy.render_passes(scene, "FULL")
            errors[frame] = accuracy.compare(image, image_b, reference, reference_b)
            accuracy.write_strip(os.path.join(helpers.OUTPUT, f"stability_deformation_{frame:02d}.png"), image,
                                 reference, (image_b[..., 3] > 0.5) & (reference_b[..., 3] > 0.5))
        print("deformation, FULL against REFERENCE (radiance relative RMSE, the same without the worst 0.1 %, "
              "exitance relative RMSE): "
              + ", ".join(f"frame {f}: {e['relative_rmse']:.4f} {e['robust_relative_rmse']:.4f} "
                          f"{e['exitance_relative_rmse']:.4f}" for f, e in errors.items()), flush=True)
        rest = errors[1]["exitance_relative_rmse"]
        for frame, e in errors.items():
            with self.subTest(frame=frame):
                self.assertLess(e["exitance_relative_rmse"], EXITANCE_OVER_REST * rest)
                self.assertLess(e["robust_relative_rmse"], ROBUST_BOUND)


if __name__ == "__main__":
    helpers.run_tests()
