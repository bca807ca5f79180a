"""Chandrasekhar's H-function of isotropic scattering, and the exact radiance of an index-matched,
isotropically scattering half-space (the truth harness's own check: docs/PHYSICAL.md, "Checking the
truth").

Plain Python with numpy (no Blender): the H-function solves, for single-scattering albedo a in (0, 1],

    1 / H(mu) = sqrt(1 - a) + (a / 2) int_0^1 mu' H(mu') / (mu + mu') dmu'

(Chandrasekhar, Radiative Transfer, 1960, chapter V). It is solved on a Gauss-Legendre grid in
t = sqrt(mu) (H has a mu log mu term at mu = 0 that a grid in mu resolves slowly) by a few steps of
the fixed-point iteration and then Newton's method, which converges at a = 1 as well, where the
iteration alone slows to a crawl. H at any mu is then the right-hand side evaluated at mu (Nystrom).

Radiance leaving the half-space at direction cosine mu (Chandrasekhar's, with pi F = E / mu0 the
flux across the beam):
- a collimated beam whose irradiance on the surface is E, arriving at cosine mu0:
      L = a E H(mu0) H(mu) / (4 pi (mu0 + mu));
  (a sun of strength S, the irradiance on a plane facing it, at mu0 gives E = S mu0);
- uniform radiance L_in from the whole upper hemisphere: L = L_in (1 - sqrt(1 - a) H(mu)).
"""
import numpy as np

_cache = {}


def _nodes(n):
    x, w = np.polynomial.legendre.leggauss(n)
    t = 0.5 * (x + 1.0)
    # mu = t^2, dmu = 2 t dt, t in [0, 1].
    return t * t, w * t  # w * 0.5 * 2 t


def _solve(albedo, n):
    if not 0.0 < albedo <= 1.0:
        raise ValueError(f"albedo {albedo} outside (0, 1]")
    mu, w = _nodes(n)
    root = np.sqrt(max(1.0 - albedo, 0.0))
    kernel = (albedo / 2.0) * (w * mu)[None, :] / (mu[:, None] + mu[None, :])
    h = np.ones(n)
    for _ in range(50):  # fixed point: a good start for Newton
        h = 1.0 / (root + kernel @ h)
    for _ in range(50):
        # F(h) = h * (root + K h) - 1 = 0;  J = diag(root + K h) + diag(h) K
        s = root + kernel @ h
        residual = h * s - 1.0
        if np.max(np.abs(residual)) < 1e-15:
            break
        jacobian = np.diag(s) + h[:, None] * kernel
        h = h - np.linalg.solve(jacobian, residual)
    else:
        raise RuntimeError(f"H-function: Newton did not converge for albedo {albedo}")
    return mu, w, h, root


class HFunction:
    """H(mu) for one albedo; call it with a float or an array of mu in [0, 1]."""

    def __init__(self, albedo, n=96):
        self.albedo = float(albedo)
        self.mu, self.w, self.h, self.root = _solve(self.albedo, n)

    def __call__(self, mu):
        m = np.asarray(mu, dtype=float)
        integral = (self.albedo / 2.0) * ((self.w * self.mu * self.h) / (m[..., None] + self.mu)).sum(axis=-1)
        value = 1.0 / (self.root + integral)
        return float(value) if value.ndim == 0 else value


def h_function(albedo, n=96):
    key = (float(albedo), n)
    if key not in _cache:
        _cache[key] = HFunction(albedo, n)
    return _cache[key]


def L_collimated(albedo, E, mu0, mu):
    """Radiance leaving the half-space at cosine mu under a collimated beam of irradiance E (on the
    surface) at cosine mu0."""
    H = h_function(albedo)
    return albedo * E * H(mu0) * H(mu) / (4.0 * np.pi * (mu0 + mu))


def L_uniform(albedo, L_in, mu):
    """Radiance leaving the half-space at cosine mu under uniform radiance L_in from above."""
    H = h_function(albedo)
    return L_in * (1.0 - np.sqrt(1.0 - albedo) * H(mu))


def sun_radiance(albedo, strength, mu0, mu):
    """A Blender sun of `strength` (irradiance on a plane facing it) at cosine mu0."""
    return L_collimated(albedo, strength * mu0, mu0, mu)
