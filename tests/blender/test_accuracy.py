"""Accuracy against REFERENCE, the ruler (docs/ACCURACY.md).

- BRUTE on every example scene: relative RMSE of radiance and of exitance under bounds,
  so that a regression of BRUTE shows up here; FULL (the paper's method) within 1.5x BRUTE. Strips (BRUTE | REFERENCE | error x10) are
  written to the test output for a person to look at.
- REFERENCE against Cycles' random walk on slabs of Marble and Skin1: loose ranges that
  catch unit and radiometry mistakes (factors), not model differences (percents).
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import helpers  # noqa: E402

subsplat = helpers.enable_addon()
import accuracy  # noqa: E402

# Measured on this project's machine (llvmpipe), 25 % of 800 x 600, REFERENCE at 200 000
# samples (docs/ACCURACY.md): radiance 0.0088 (skin_suzanne) and 0.0046 (marble_pieces);
# exitance 0.023 and 0.063 (silhouettes, where grazing Fresnel then hides it). The bounds
# leave about 2x for driver and rasterisation differences; REFERENCE itself is converged
# to a few tenths of a percent at this sample count.
BRUTE_BOUND = {"relative_rmse": 0.02, "exitance_relative_rmse": 0.12}

# The paper's method must stay "visually indistinguishable from the ground truth": at default
# settings FULL's relative RMSE of radiance is at most 1.5 x BRUTE's (measured: 1.01 x on
# skin_suzanne, 1.02 x on marble_pieces at 25 %).
FULL_OVER_BRUTE = 1.5

# REFERENCE / Cycles per channel (docs/ACCURACY.md): Marble 0.88 to 0.93, Skin1 0.53 to 0.67.
CYCLES_RANGE = {"MARBLE": (0.8, 1.1), "SKIN1": (0.45, 0.8)}


class MethodsAgainstReference(unittest.TestCase):
    def test_every_example(self):
        for name in accuracy.EXAMPLES:
            scene = accuracy.open_example(name, 25)
            reference, reference_b, _ = accuracy.render_passes(scene, "REFERENCE", 200000)
            brute = self.check_brute(name, scene, reference, reference_b)
            image, image_b, _ = accuracy.render_passes(scene, "FULL")
            full = accuracy.compare(image, image_b, reference, reference_b)
            accuracy.write_strip(os.path.join(helpers.OUTPUT, f"accuracy_{name}_full.png"), image, reference,
                                 (image_b[..., 3] > 0.5) & (reference_b[..., 3] > 0.5))
            print(f"{name}: FULL against REFERENCE {full}")
            with self.subTest(scene=name, method="FULL"):
                self.assertLessEqual(full["relative_rmse"], FULL_OVER_BRUTE * brute["relative_rmse"],
                                     f"{name}: FULL {full['relative_rmse']:.4f}, BRUTE {brute['relative_rmse']:.4f}")

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
