"""The error against a physical truth with the truth's noise taken out (tests/subsplat_testing/
twin_truth.py, error()), on synthetic images whose converged truth is known: the corrected error
finds the true one where the uncorrected one is biased up by the truth's noise, and an image that is
only noise about the truth (the twin at few samples) gets its own noise level. Plain Python with
numpy (CTest: /usr/bin/python3, label unit)."""
import unittest

import numpy as np

from subsplat_testing import twin_truth

SEEDS = 4


def truth_of(converged, noise, rng):
    """A truth made as the benchmarks make it: the mean and standard error of SEEDS noisy renders."""
    renders = converged[None] * (1.0 + noise * rng.standard_normal((SEEDS,) + converged.shape))
    return renders.mean(axis=0), np.sqrt(renders.var(axis=0, ddof=1) / SEEDS)


def relative_rmse(image, converged):
    return float(np.sqrt(((image - converged) ** 2).mean() / (converged ** 2).mean()))


class NoiseTakenOut(unittest.TestCase):
    def setUp(self):
        self.rng = np.random.default_rng(7)
        self.converged = self.rng.uniform(0.2, 1.0, (120, 160, 4))
        self.mask = np.ones(self.converged.shape[:2], dtype=bool)

    def test_a_biased_image_gets_its_true_error(self):
        image = self.converged * 0.9  # 10 % low everywhere: the true relative error is 0.1
        truth = truth_of(self.converged, 0.3, self.rng)  # 15 % noise per pixel in the mean
        corrected, uncorrected, noise, ratio = twin_truth.error(image, truth, self.mask)
        self.assertAlmostEqual(corrected, 0.1, delta=0.005)
        self.assertGreater(uncorrected, 0.15, "without the correction the truth's noise dominates")
        self.assertAlmostEqual(noise, 0.15, delta=0.01)
        self.assertAlmostEqual(ratio, 0.9, delta=0.01)

    def test_a_noisy_image_gets_its_own_noise(self):
        truth = truth_of(self.converged, 0.1, self.rng)
        image = self.converged * (1.0 + 0.2 * self.rng.standard_normal(self.converged.shape))
        corrected, _uncorrected, _noise, _ratio = twin_truth.error(image, truth, self.mask)
        self.assertAlmostEqual(corrected, relative_rmse(image[..., :3], self.converged[..., :3]), delta=0.005)

    def test_the_truth_against_itself_is_zero(self):
        truth = truth_of(self.converged, 0.2, self.rng)
        self.assertEqual(twin_truth.error(truth[0], truth, self.mask)[0], 0.0)


if __name__ == "__main__":
    unittest.main()
