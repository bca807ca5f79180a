// Adding-doubling (adding_doubling.h), a deterministic slab solution independent of the Monte
// Carlo: against the H-function's half-space, energy, single scattering, its own grid, and then
// the slab Monte Carlo against it at the thicknesses thin parts have (0.5 to 4 mean free paths).
#include "transport/adding_doubling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "transport/hfunction.h"
#include "transport/slab_monte_carlo.h"
#include "util/error.h"

namespace subsplat {
namespace {

TEST(AddingDoubling, ThickSlabIsTheHalfSpace) {
  // 64 mean free paths at a = 0.9 (35 diffusion lengths), 512 at a = 0.99 (89).
  for (auto [a, tau] : {std::pair{0.9, 64.0}, std::pair{0.99, 512.0}}) {
    HFunction h(a);
    for (double mu0 : {1.0, 0.5, 0.2}) {
      SlabSolution s = solveSlabByAddingDoubling(a, tau, mu0);
      std::string what = "a = " + std::to_string(a) + ", mu0 = " + std::to_string(mu0);
      EXPECT_NEAR(s.reflectance, halfSpaceAlbedo(h, mu0), 2e-7) << what;
      EXPECT_LT(s.scatteredTransmittance, 1e-12) << what;
      for (size_t i = 0; i < s.mu.size(); ++i)
        EXPECT_NEAR(s.reflectedRadiance[i], halfSpaceReflectedRadiance(h, mu0, s.mu[i]),
                    1e-6 * halfSpaceReflectedRadiance(h, mu0, s.mu[i])) << what << ", mu = " << s.mu[i];
    }
  }
}

TEST(AddingDoubling, ConservativeSlabsLoseNothingAndOthersLoseSome) {
  for (double tau : {0.01, 0.5, 2.0, 16.0}) {
    for (double mu0 : {1.0, 0.3}) {
      SlabSolution s = solveSlabByAddingDoubling(1.0, tau, mu0);
      EXPECT_NEAR(s.reflectance + s.scatteredTransmittance + s.unscatteredTransmittance, 1.0, 1e-9) << tau;
      SlabSolution lossy = solveSlabByAddingDoubling(0.95, tau, mu0);
      EXPECT_LT(lossy.reflectance + lossy.scatteredTransmittance + lossy.unscatteredTransmittance, 1.0) << tau;
    }
    SlabSolution s = solveSlabByAddingDoubling(1.0, tau, 1.0);
    EXPECT_NEAR(s.diffuseReflectance + s.diffuseTransmittance, 1.0, 1e-9) << tau;
  }
  SlabSolution dark = solveSlabByAddingDoubling(0.0, 1.0, 0.5);
  EXPECT_EQ(dark.reflectance, 0.0);
  EXPECT_EQ(dark.scatteredTransmittance, 0.0);
}

TEST(AddingDoubling, ThinSlabIsSingleScattering) {
  // At tau = 1e-6 light scattered twice is a relative 2e-5 of that scattered once (about
  // a tau ln(1/tau), from grazing paths).
  const double a = 0.9, tau = 1e-6, mu0 = 0.7;
  SlabSolution s = solveSlabByAddingDoubling(a, tau, mu0);
  MuQuadrature q = gaussLegendreInSqrtMu(400);
  double r1 = 0.0, t1 = 0.0;
  for (size_t i = 0; i < q.mu.size(); ++i) {
    double mu = q.mu[i], flux = 2 * M_PI * mu * q.weight[i];
    r1 += flux * a * -std::expm1(-tau * (1 / mu0 + 1 / mu)) / (4 * M_PI * (mu0 + mu));
    t1 += flux * a * (std::exp(-tau / mu) - std::exp(-tau / mu0)) / (4 * M_PI * (mu - mu0));
  }
  EXPECT_NEAR(s.reflectance, r1, 3e-5 * r1);
  EXPECT_NEAR(s.scatteredTransmittance, t1, 3e-5 * t1);
}

TEST(AddingDoubling, GridIsConverged) {
  for (double a : {0.5, 0.99})
    for (double tau : {0.25, 2.0}) {
      SlabSolution coarse = solveSlabByAddingDoubling(a, tau, 0.8, 32), fine = solveSlabByAddingDoubling(a, tau, 0.8, 64);
      EXPECT_NEAR(coarse.reflectance, fine.reflectance, 1e-7);
      EXPECT_NEAR(coarse.scatteredTransmittance, fine.scatteredTransmittance, 1e-7);
      EXPECT_NEAR(coarse.diffuseReflectance, fine.diffuseReflectance, 1e-7);
      EXPECT_NEAR(coarse.diffuseTransmittance, fine.diffuseTransmittance, 1e-7);
    }
}

TEST(AddingDoubling, SlabMonteCarloAgreesAtThinThicknesses) {
  // The thin parts of issue 19 (0.5 to 5 mean free paths): reflected and transmitted, by a beam at
  // 1 and 0.5 and by diffuse light, 1e5 paths each, within 4 standard errors.
  for (double a : {0.5, 0.9, 0.99})
    for (double tau : {0.5, 1.0, 2.0, 4.0}) {
      SlabSolution exact = solveSlabByAddingDoubling(a, tau, 1.0);
      for (int incidence = 0; incidence < 3; ++incidence) {
        SlabSettings s;
        s.albedo = a;
        s.thickness = tau;
        s.mu0 = incidence == 1 ? 0.5 : 1.0;
        s.incidence = incidence == 2 ? SlabIncidence::Diffuse : SlabIncidence::Collimated;
        s.paths = 100000;
        SlabTallies t = simulateSlab(s);
        if (incidence == 1) exact = solveSlabByAddingDoubling(a, tau, 0.5);
        double r = incidence == 2 ? exact.diffuseReflectance : exact.reflectance;
        double tr = incidence == 2 ? exact.diffuseTransmittance - t.unscattered : exact.scatteredTransmittance;
        std::string what = "a = " + std::to_string(a) + ", tau = " + std::to_string(tau) + ", incidence " + std::to_string(incidence);
        EXPECT_NEAR(t.reflectance(), r, 4 * t.standardError(t.reflected)) << what;
        EXPECT_NEAR(t.scatteredTransmittance(), tr, 4 * t.standardError(t.transmitted)) << what;
      }
    }
}

TEST(AddingDoubling, RefusesBadInput) {
  EXPECT_THROW(solveSlabByAddingDoubling(1.5, 1.0, 1.0), Error);
  EXPECT_THROW(solveSlabByAddingDoubling(0.5, std::numeric_limits<double>::infinity(), 1.0), Error);
  EXPECT_THROW(solveSlabByAddingDoubling(0.5, 0.0, 1.0), Error);
  EXPECT_THROW(solveSlabByAddingDoubling(0.5, 1.0, 0.0), Error);
}

}  // namespace
}  // namespace subsplat
