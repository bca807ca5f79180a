"""The truth harness's own check (docs/PHYSICAL.md, "Checking the truth"): the committed Cycles
radiance of an index-matched isotropic half-space (bench/results/truth_halfspace.json, written by
bench/truth_halfspace.py) is within 1 % of Chandrasekhar's H-function, recomputed here; and a live,
cheap Cycles render of one case agrees with the committed figure within its noise, so the figure stays
tied to the code that made it (tests/subsplat_testing/truth.py, addon/subsplat/twin.py)."""
import json
import math
import os
import unittest

from subsplat_testing import helpers, truth

helpers.enable_addon()

RESULT = os.path.join(helpers.SOURCE, "bench", "results", "truth_halfspace.json")
TOLERANCE = 0.01         # the check: Cycles within 1 % of the H-function
MAX_STANDARD_ERROR = 0.003  # the committed run must resolve it: standard error <= 0.3 %


def committed():
    if not os.path.exists(RESULT):
        raise AssertionError(f"{RESULT} is missing: run bench/truth_halfspace.py (docs/PHYSICAL.md)")
    with open(RESULT) as f:
        return json.load(f)


class TruthHarness(unittest.TestCase):
    def test_committed_within_one_percent(self):
        result = committed()
        cases = {(c["via"], c["medium"], c["case"]): c for c in result["cases"]}
        expected_cases = {(via, medium, name) for via in ("twin", "direct") for name, medium, *_ in truth.CASES}
        self.assertEqual(set(cases), expected_cases,
                         "the committed run covers every case of truth.CASES, through the twin and directly")
        for (via, medium, name), c in sorted(cases.items()):
            albedo = truth.MEDIA[medium]
            self.assertEqual(c["albedo"], albedo)
            exact = truth.exact(albedo, c["light"], c["mu0"], c["mu"])
            ratio = c["truth_radiance"] / exact
            print(f"truth {via} {medium} {name}: cycles {c['truth_radiance']:.6f} +- "
                  f"{100 * c['relative_standard_error']:.3f} %  H-function {exact:.6f}  ratio {ratio:.5f}")
            self.assertLessEqual(c["relative_standard_error"], MAX_STANDARD_ERROR, f"{via} {medium} {name}")
            self.assertAlmostEqual(ratio, 1.0, delta=TOLERANCE, msg=f"{via} {medium} {name}: Cycles / H-function")

    def test_live_render_agrees_with_committed(self):
        """Through the Cycles twin, a = 0.99 (the case that needs the most bounces), sun at 60
        degrees, seen from above: 512 samples x 4 seeds x 64 pixels, seeds unlike the committed run's."""
        c = next(c for c in committed()["cases"]
                 if (c["via"], c["medium"], c["case"]) == ("twin", "a0.99", "sun60_view0"))
        mean, error, per_seed, seconds = truth.measure(
            c["medium"], c["light"], c["mu0"], c["mu"], size_px=8, samples=512, seeds=4,
            path_prefix=os.path.join(helpers.OUTPUT, "truth_live"), first_seed=1000, via="twin")
        bound = 4.0 * math.hypot(error, c["standard_error"])
        print(f"live: {mean:.6f} +- {100 * error / mean:.3f} % ({seconds:.1f} s); committed "
              f"{c['truth_radiance']:.6f}; bound (4 sigma) {100 * bound / mean:.2f} %")
        self.assertLess(bound / mean, 0.03, "the live check must be able to see a 3 % change")
        self.assertAlmostEqual(mean, c["truth_radiance"], delta=bound)


if __name__ == "__main__":
    helpers.run_tests()
