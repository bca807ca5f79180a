// Chandrasekhar's H-function of isotropic scattering and the exact radiance of an
// index-matched (eta = 1), isotropically scattering half-space (Chandrasekhar, Radiative
// Transfer, 1960, chapter V). The same solver as tests/subsplat_testing/hfunction.py, which the
// truth harness is checked with (docs/PHYSICAL.md, "Checking the truth"); docs/TRANSPORT.md.
//
// For single-scattering albedo a in (0, 1], H solves
//     1 / H(mu) = sqrt(1 - a) + (a / 2) int_0^1 mu' H(mu') / (mu + mu') dmu'.
// Lengths do not appear: a half-space's answers depend on the albedo and the cosines alone.
#pragma once

#include <vector>

namespace subsplat {

// Gauss-Legendre on [0, 1] in t = sqrt(mu) (H has a mu log mu term at mu = 0 that a grid in mu
// resolves slowly): nodes mu_i = t_i^2 and weights for dmu = 2 t dt, so that
// sum_i weight_i f(mu_i) ~ int_0^1 f(mu) dmu.
struct MuQuadrature {
  std::vector<double> mu, weight;
};
MuQuadrature gaussLegendreInSqrtMu(int nodes);

// Gauss-Legendre nodes x and weights w on [-1, 1] (Newton on P_n; exact for degree 2n - 1).
void gaussLegendre(int nodes, std::vector<double>& x, std::vector<double>& w);

class HFunction {
 public:
  // Solves on `nodes` points: 50 fixed-point steps (a start), then Newton's method to a residual
  // under 1e-15 (it converges at a = 1 too, where the iteration alone crawls). Throws Error
  // (SS_INVALID_ARGUMENT) for an albedo outside (0, 1].
  explicit HFunction(double albedo, int nodes = 96);

  // H(mu) for mu in [0, 1] (Nystrom: the right-hand side evaluated at mu). H(0) = 1.
  double operator()(double mu) const;

  double albedo() const { return albedo_; }

 private:
  double albedo_ = 1.0, root_ = 0.0;  // root_ = sqrt(1 - a)
  std::vector<double> mu_, weight_, h_;
};

// Exact half-space answers for eta = 1 (Chandrasekhar; docs/PHYSICAL.md "Checking the truth").
//
// Albedo under a collimated beam at cosine mu0: the fraction of the incident power reflected,
// R(mu0) = 1 - sqrt(1 - a) H(mu0).
double halfSpaceAlbedo(const HFunction& h, double mu0);
// Radiance reflected at cosine mu per unit irradiance E on the surface from a collimated beam at
// cosine mu0 (the BRDF times mu0): a H(mu0) H(mu) / (4 pi (mu0 + mu)), in 1/sr.
double halfSpaceReflectedRadiance(const HFunction& h, double mu0, double mu);
// Radiance reflected at cosine mu per unit radiance of a uniform sky: 1 - sqrt(1 - a) H(mu).
double halfSpaceUniformRadiance(const HFunction& h, double mu);
// The once-scattered part of R(mu0) (H = 1 in the radiance above): (a/2)(1 - mu0 ln(1 + 1/mu0)).
double halfSpaceSingleScatteringAlbedo(double albedo, double mu0);

}  // namespace subsplat
