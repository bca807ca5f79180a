"""Chandrasekhar's H-function (tests/subsplat_testing/hfunction.py), the exact half-space radiance
the truth harness is checked against: its moments, tabulated values, and the albedo identity.
Plain Python with numpy (CTest: /usr/bin/python3, label unit)."""
import math
import unittest

import numpy as np

from subsplat_testing import hfunction

ALBEDOS = (0.05, 0.3, 0.5, 0.8, 0.9, 0.95, 0.99, 0.999, 0.9999, 1.0)


def gauss(n=400):
    """Gauss-Legendre on [0, 1] in t = sqrt(mu) (H has a mu log mu term at 0): nodes mu, weights."""
    x, w = np.polynomial.legendre.leggauss(n)
    t = 0.5 * (x + 1.0)
    return t * t, w * t


def fixed_point_in_mu(albedo, n=200, iterations=100000):
    """An independent solution: the plain iteration of 1/H on a grid in mu (the draft's method)."""
    x, w = np.polynomial.legendre.leggauss(n)
    mu, w = 0.5 * (x + 1.0), 0.5 * w
    root = math.sqrt(1.0 - albedo)
    h = np.ones(n)
    for _ in range(iterations):
        new = 1.0 / (root + (albedo / 2.0) * ((w * mu * h)[None, :] / (mu[:, None] + mu[None, :])).sum(axis=1))
        if np.max(np.abs(new - h)) < 1e-14:
            return lambda m: 1.0 / (root + (albedo / 2.0) * ((w * mu * new) / (np.asarray(m)[..., None] + mu)).sum(axis=-1))
        h = new
    raise RuntimeError("no convergence")


class HFunctionTest(unittest.TestCase):
    def test_zeroth_moment(self):
        """int_0^1 H dmu = (2 / a) (1 - sqrt(1 - a)), up to a = 1."""
        mu, w = gauss()
        for a in ALBEDOS:
            H = hfunction.h_function(a)
            self.assertAlmostEqual(float((w * H(mu)).sum()), 2.0 / a * (1.0 - math.sqrt(1.0 - a)), delta=1e-9,
                                   msg=f"a = {a}")

    def test_first_moment_conservative(self):
        """At a = 1, int_0^1 mu H dmu = 2 / sqrt(3)."""
        mu, w = gauss()
        self.assertAlmostEqual(float((w * mu * hfunction.h_function(1.0)(mu)).sum()), 2.0 / math.sqrt(3.0),
                               delta=1e-8)

    def test_tabulated(self):
        """Chandrasekhar's tables (Radiative Transfer, 1960; 4 decimals) for a = 1 and 0.9; H(0) = 1."""
        table = {1.0: {0.0: 1.0, 0.1: 1.2474, 0.5: 2.0128, 1.0: 2.9078},
                 0.9: {0.0: 1.0, 1.0: 1.8501}}
        for a, values in table.items():
            H = hfunction.h_function(a)
            for mu, expected in values.items():
                self.assertAlmostEqual(H(mu), expected, delta=1.5e-4, msg=f"a = {a}, mu = {mu}")

    def test_independent_solution(self):
        """Newton on the t = sqrt(mu) grid agrees with the plain iteration on a grid in mu."""
        m = np.linspace(0.0, 1.0, 21)
        for a in (0.3, 0.8, 0.99):
            np.testing.assert_allclose(hfunction.h_function(a)(m), fixed_point_in_mu(a)(m), rtol=2e-6,
                                       err_msg=f"a = {a}")

    def test_grid_converged(self):
        m = np.linspace(0.0, 1.0, 21)
        for a in (0.5, 0.99, 1.0):
            np.testing.assert_allclose(hfunction.HFunction(a, 48)(m), hfunction.HFunction(a, 160)(m), rtol=1e-12)

    def test_albedo_identity(self):
        """The half-space's albedo under a collimated beam: int L mu dOmega / E = 1 - sqrt(1 - a) H(mu0),
        integrating L_collimated over the outgoing hemisphere."""
        mu, w = gauss()
        for a in ALBEDOS:
            H = hfunction.h_function(a)
            for mu0 in (1.0, 0.8, 0.5, 0.2, 0.05):
                E = 3.0
                reflected = 2.0 * math.pi * float((w * mu * hfunction.L_collimated(a, E, mu0, mu)).sum())
                self.assertAlmostEqual(reflected / E, 1.0 - math.sqrt(1.0 - a) * H(mu0), delta=1e-9,
                                       msg=f"a = {a}, mu0 = {mu0}")

    def test_reciprocity_and_uniform(self):
        """L_collimated / E (the BRDF) is symmetric in (mu0, mu), and integrating it over
        every incident direction of a uniform sky gives L_uniform."""
        mu, w = gauss()
        for a in (0.5, 0.99, 1.0):
            for m0, m in ((1.0, 0.3), (0.7, 0.2)):
                self.assertAlmostEqual(hfunction.L_collimated(a, 1.0, m0, m), hfunction.L_collimated(a, 1.0, m, m0),
                                       delta=1e-12)
            for m in (1.0, 0.5, 0.1):
                # A sky of radiance 1: irradiance mu0 dOmega from each direction.
                sky = 2.0 * math.pi * float((w * hfunction.L_collimated(a, mu, mu, m)).sum())
                self.assertAlmostEqual(sky, hfunction.L_uniform(a, 1.0, m), delta=1e-9, msg=f"a = {a}, mu = {m}")

    def test_sun(self):
        """A sun of strength S (irradiance facing it) at mu0 gives irradiance S mu0 on the surface."""
        self.assertAlmostEqual(hfunction.sun_radiance(0.8, 2.0, 0.5, 1.0), hfunction.L_collimated(0.8, 1.0, 0.5, 1.0))

    def test_bad_albedo(self):
        for a in (0.0, -0.1, 1.01):
            with self.assertRaises(ValueError):
                hfunction.HFunction(a)


if __name__ == "__main__":
    unittest.main(verbosity=2)
