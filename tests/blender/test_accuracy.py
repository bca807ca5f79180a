"""Accuracy against REFERENCE, the ruler (docs/ACCURACY.md).

- BRUTE on the example scenes (CI: two of the three, EXAMPLES): relative RMSE of radiance and of
  exitance under bounds, so that a regression of BRUTE shows up here; FULL (the paper's method)
  within 1.5x BRUTE. Strips (BRUTE | REFERENCE | error x10) are written to the test output for a
  person to look at.
- REFERENCE against Cycles' random walk on slabs of Marble and Skin1: loose ranges that
  catch unit and radiometry mistakes (factors), not model differences (percents).
"""
import os
import unittest

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat_testing import accuracy  # noqa: E402

# Measured on this project's machine (llvmpipe), 25 % of 800 x 600, REFERENCE at 200 000 samples
# (docs/ACCURACY.md has the figures at 50 %). CI renders REFERENCE at 50 000 (against a converged
# one it is off by 0.0004 in radiance and 0.007 in exitance, docs/ACCURACY.md, against bounds of
# 0.02 and 0.12; REFERENCE is 85 % of this test's time; the slow tier, SUBSPLAT_SLOW=1, at 200 000).
# Radiance is bounded without its worst 0.1 % of pixels: those are direct specular highlights where
# the shadow map and REFERENCE's shadow ray disagree (crevices such as Suzanne's eye sockets; one
# such pixel of the jade is 2000x its reference and alone makes wax_jade's full radiance RMSE 0.16).
# They are counted apart (OUTLIER_SHARE). Exitance (the part the splatting computes) is bounded in
# full; silhouettes, where grazing Fresnel then hides it, dominate it. The bounds leave about 2x for
# driver and rasterisation differences; REFERENCE itself is converged to a few tenths of a percent.
REFERENCE_SAMPLES = 200000 if helpers.SLOW else 50000
# CI: skin_suzanne and the wide-range wax_jade, where FULL picks several levels (at this size it picks
# one on the other two, so FULL is BRUTE there); marble_pieces too in the slow tier.
EXAMPLES = accuracy.EXAMPLES if helpers.SLOW else ("skin_suzanne", "wax_jade")
BRUTE_BOUND = {"robust_relative_rmse": 0.02, "exitance_relative_rmse": 0.12}
OUTLIER_SHARE = 0.002  # pixels off by more than 3x the mean radiance, of the translucent pixels

# The paper's method must stay "visually indistinguishable from the ground truth": at default
# settings FULL's relative RMSE is at most 1.5 x BRUTE's, of radiance and of exitance.
FULL_OVER_BRUTE = 1.5

# REFERENCE / Cycles per channel (docs/ACCURACY.md): Marble 0.88 to 0.93, Skin1 0.53 to 0.67.
CYCLES_RANGE = {"MARBLE": (0.8, 1.1), "SKIN1": (0.45, 0.8)}


class MethodsAgainstReference(unittest.TestCase):
    def test_every_example(self):
        for name in EXAMPLES:
            scene = accuracy.open_example(name, 25)
            reference, reference_b, _ = accuracy.render_passes(scene, "REFERENCE", REFERENCE_SAMPLES)
            brute = self.check_brute(name, scene, reference, reference_b)
            image, image_b, _ = accuracy.render_passes(scene, "FULL")
            full = accuracy.compare(image, image_b, reference, reference_b)
            accuracy.write_strip(os.path.join(helpers.OUTPUT, f"accuracy_{name}_full.png"), image, reference,
                                 (image_b[..., 3] > 0.5) & (reference_b[..., 3] > 0.5))
            print(f"{name}: FULL against REFERENCE {full}")
            for key in ("relative_rmse", "exitance_relative_rmse"):
                with self.subTest(scene=name, method="FULL", figure=key):
                    self.assertLessEqual(full[key], FULL_OVER_BRUTE * brute[key],
                                         f"{name}: FULL {key} {full[key]:.4f}, BRUTE {brute[key]:.4f}")

    def check_brute(self, name, scene, reference, reference_b):
        """BRUTE under its bounds; returns its figures."""
        image, image_b, _ = accuracy.render_passes(scene, "BRUTE")
        figures = accuracy.compare(image, image_b, reference, reference_b)
        mask = (image_b[..., 3] > 0.5) & (reference_b[..., 3] > 0.5)
        strip = accuracy.write_strip(os.path.join(helpers.OUTPUT, f"accuracy_{name}_brute.png"),
                                     image, reference, mask)
        print(f"{name}: BRUTE against REFERENCE {figures} ({strip})")
        self.assertGreater(figures["pixels"], 1000, name)
        # Both renders see the same translucent pixels but for rasterisation at edges.
        self.assertLess(figures["mask_disagreement"], 0.01 * figures["pixels"], name)
        self.assertLess(figures["outlier_pixels"], OUTLIER_SHARE * figures["pixels"], f"{name} (strip {strip})")
        for key, bound in BRUTE_BOUND.items():
            with self.subTest(scene=name, figure=key):
                self.assertLess(figures[key], bound, f"{name}: {key} {figures[key]:.4f} (strip {strip})")
        return figures


class ReferenceAgainstCycles(unittest.TestCase):
    def test_marble_and_skin1_slabs(self):
        for preset, (lo, hi) in CYCLES_RANGE.items():
            ours, theirs, ratio = accuracy.reference_against_cycles(preset)
            print(f"{preset}: REFERENCE {ours}, Cycles {theirs}, ratio {ratio}")
            for c in range(3):
                with self.subTest(preset=preset, channel="RGB"[c]):
                    self.assertTrue(lo <= ratio[c] <= hi, f"{preset} {'RGB'[c]}: REFERENCE/Cycles {ratio[c]:.3f} "
                                                          f"outside [{lo}, {hi}]")


if __name__ == "__main__":
    helpers.run_tests()
