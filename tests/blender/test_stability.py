"""Stability (docs/STABILITY.md): where the methods stay put and where they do not.

- Flicker under a slowly moving light, the limitation the paper admits: a marble sphere whose range
  is long enough for FULL's adaptive selection to choose coarse samples for about 40 % of it
  (stability_cases.coarse_sphere), its light turning 0.5 degrees a frame about the vertical for 8
  frames in CI, 60 in the slow tier (SUBSPLAT_SLOW=1, bench/slow.sh). A method's flicker is its
  mean frame-to-frame change over the translucent pixels, relative to REFERENCE's mean radiance;
  its excess is that minus REFERENCE's own (the change the light's motion really makes). FULL's
  excess is bounded.
- Deformation: the candle bends and twists over frames 1-48; FULL's error against REFERENCE before,
  during and after stays within its error at rest (see DEFORMATION_PERCENTAGE's comment). CI
  measures frames 1, 24 and 48, the slow tier also 12 and 36.
- Physical truth: every case with a truth (stability_cases.Case.truth) has it committed in
  bench/results/truth/ at bench/stability.py's size (a missing one fails), every case without one
  says why; FULL on the thin back-lit ear at eta = 1 against its truth is the figure committed in
  docs/images/stability/cases.json (bench/stability.py's), within 0.01.
Figures are printed; a plot and strips go to $SUBSPLAT_TEST_OUTPUT/stability_*.png. The hard cases
(grazing light, z0, thin features, lambda_m, ranges, scale) are measured by bench/stability.py and
bounded in test_hard_cases.py.
"""
import dataclasses
import json
import os
import unittest

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat_testing import accuracy  # noqa: E402
import numpy as np  # noqa: E402
from subsplat_testing import stability_cases, twin_truth  # noqa: E402

# The flicker sphere at 40 x 40 with REFERENCE at 8000 samples a frame (CI time; bench/stability.py
# --flicker measures every method at finer settings). FULL must select coarse samples for a good
# share of the texels (43 % measured), or the case would not be the one the paper worries about.
FLICKER_SIZE, FLICKER_SAMPLES = 40, 8000
MIN_COARSE_SHARE = 0.3
# Frames of the turning light: FULL's excess measured 0.00005 over 60 frames (docs/STABILITY.md),
# far below the bound, so CI's 8 (7 frame pairs) still tell flicker of a percent from none.
FLICKER_FRAMES = 60 if helpers.SLOW else 8
# FULL's excess over REFERENCE: measured in docs/STABILITY.md; the bound leaves room for the noise of
# REFERENCE's few samples and catches flicker of a percent of the radiance.
FULL_EXCESS_FLICKER = 0.01
# Deformation: the candle at 20 %. Its error at rest (frame 1) is the static bound: at every frame
# FULL's exitance error stays within twice it (the bend shows more silhouette, where exitance
# errors sit), and its radiance error (without the worst 0.1 % of pixels, see test_accuracy.py)
# within 1.5 x test_accuracy.py's static bound on BRUTE.
DEFORMATION_PERCENTAGE, DEFORMATION_SAMPLES = 20, 50000
EXITANCE_OVER_REST = 2.0
ROBUST_BOUND = 1.5 * 0.02
DEFORMATION_FRAMES = (1, 12, 24, 36, 48) if helpers.SLOW else (1, 24, 48)  # rest, the bend, the twist


class MovingLight(unittest.TestCase):
    # FULL's excess is what is asserted. BRUTE (every finest texel of the 512² view splatted onto the
    # 40 x 40 frame: 62 M fragments, ten times REFERENCE's time here) is printed beside it in the slow
    # tier only; MULTIRES and ADAPTIVE: bench/stability.py --flicker.
    METHODS = ("REFERENCE", "BRUTE", "FULL") if helpers.SLOW else ("REFERENCE", "FULL")

    def test_full_with_coarse_samples_flickers_little_more_than_reference(self):
        scene = stability_cases.coarse_sphere(FLICKER_SIZE)
        frames, mask, stats = stability_cases.moving_light(scene, self.METHODS, FLICKER_SAMPLES, frames=FLICKER_FRAMES)
        figures, excess, scale = stability_cases.flicker(frames, mask)
        coarse = float(np.mean([stability_cases.coarse_share(s) for s in stats["FULL"]]))
        stability_cases.plot_changes(os.path.join(helpers.OUTPUT, "stability_flicker.png"),
                                     "Frame-to-frame change, light turning 0.5 degrees a frame", frames, mask, scale)
        for method in self.METHODS[1:]:
            accuracy.write_strip(os.path.join(helpers.OUTPUT, f"stability_flicker_{method.lower()}.png"),
                                 frames[method][-1], frames["REFERENCE"][-1], mask)
        print("flicker (mean frame-to-frame change / mean REFERENCE): "
              + ", ".join(f"{m} {figures[m]:.5f} (excess {excess[m]:+.5f})" for m in self.METHODS)
              + f"; FULL's texels from coarse samples {coarse:.2f}", flush=True)
        self.assertGreater(coarse, MIN_COARSE_SHARE, "FULL selects coarse samples over much of the sphere")
        self.assertGreater(figures["REFERENCE"], 0.0, "the light moves")
        self.assertLess(excess["FULL"], FULL_EXCESS_FLICKER)


class Deformation(unittest.TestCase):
    def test_error_through_the_bend_stays_within_the_static_bound(self):
        scene = accuracy.open_example("candle_twist", DEFORMATION_PERCENTAGE)
        errors = {}
        for frame in DEFORMATION_FRAMES:
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


class PhysicalTruth(unittest.TestCase):
    SIZE = 64  # bench/stability.py's --size: the truths are rendered at it

    def test_every_case_with_a_truth_has_it_committed(self):
        for case in stability_cases.CASES:
            with self.subTest(case=case.name):
                if not case.truth:
                    self.assertTrue(case.no_truth, f"{case.name} says why it has no physical truth")
                    continue
                for name in sorted(set(case.truth.values())):
                    truth, record = twin_truth.load(stability_cases.truth_stem(name, self.SIZE))  # missing: fails
                    self.assertEqual(truth[0].shape[:2], (self.SIZE, self.SIZE), name)
                    self.assertTrue(np.isfinite(truth[0]).all() and np.isfinite(truth[1]).all(), name)
                    self.assertGreater(float(truth[0][..., :3].mean()), 0.0, f"{name} is lit")

    def test_full_against_the_truth_is_the_committed_figure(self):
        (case,) = [c for c in stability_cases.CASES if c.name == "thin"]
        case = dataclasses.replace(case, variants=[v for v in case.variants if v.label == "FULL"])
        rows = [{}]
        # REFERENCE only gives the mask here (its translucent pixels), so few samples do
        figures = stability_cases.measure_physical(case, "ear", dict(case.setups)["ear"], self.SIZE, 5000, rows, False)
        with open(os.path.join(helpers.SOURCE, "docs", "images", "stability", "cases.json")) as f:
            (committed,) = [r for r in json.load(f)["thin"] if r["setup"] == "ear" and r["variant"] == "FULL"]
        print(f"thin ear at eta 1, FULL against the physical truth: {rows[0]['twin_error']:.4f} (committed "
              f"{committed['twin_error']:.4f}); REFERENCE at 5000 samples {figures['reference_twin_error']:.4f}; "
              f"the truth's noise {figures['noise']:.4f}", flush=True)
        self.assertAlmostEqual(rows[0]["twin_error"], committed["twin_error"], delta=0.01)


if __name__ == "__main__":
    helpers.run_tests()
