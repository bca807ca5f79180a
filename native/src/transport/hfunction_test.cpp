// Chandrasekhar's H-function and the exact half-space (hfunction.h): tabulated values, the
// moment and albedo identities, reciprocity, and agreement with the Python solver the truth
// harness is checked with (tests/subsplat_testing/hfunction.py).
#include "transport/hfunction.h"

#include <gtest/gtest.h>

#include <cmath>

#include "util/error.h"

namespace subsplat {
namespace {

const double kAlbedos[] = {0.05, 0.3, 0.5, 0.8, 0.9, 0.95, 0.99, 0.999, 0.9999, 1.0};

TEST(HFunction, MatchesChandrasekharsTables) {
  // Radiative Transfer (1960), 4 decimals; H(0) = 1 for every albedo.
  HFunction conservative(1.0), h09(0.9);
  EXPECT_NEAR(conservative(0.0), 1.0, 1e-12);
  EXPECT_NEAR(conservative(0.1), 1.2474, 1.5e-4);
  EXPECT_NEAR(conservative(0.5), 2.0128, 1.5e-4);
  EXPECT_NEAR(conservative(1.0), 2.9078, 1.5e-4);
  EXPECT_NEAR(h09(0.0), 1.0, 1e-12);
  EXPECT_NEAR(h09(1.0), 1.8501, 1.5e-4);
}

TEST(HFunction, AgreesWithThePythonSolver) {
  // tests/subsplat_testing/hfunction.py at 96 nodes (printed with repr).
  struct Row { double a, mu, h; };
  const Row rows[] = {{0.05, 0.25, 1.0102714346703616}, {0.05, 1.0, 1.017849010545602},
                      {0.3, 0.25, 1.0692986949750396},  {0.3, 1.0, 1.126844380631286},
                      {0.8, 0.25, 1.2663224876670525},  {0.8, 1.0, 1.5982195185331594},
                      {0.99, 0.25, 1.480742606314495},  {0.99, 1.0, 2.4727928283970244},
                      {0.9999, 0.25, 1.540628200944046}, {0.9999, 1.0, 2.858222446209411},
                      {1.0, 0.25, 1.5473262339796974},  {1.0, 1.0, 2.907810529078603}};
  for (const Row& r : rows) EXPECT_NEAR(HFunction(r.a)(r.mu), r.h, 1e-13) << "a = " << r.a << ", mu = " << r.mu;
}

TEST(HFunction, ZerothMomentIsClosedForm) {
  // int_0^1 H dmu = (2 / a)(1 - sqrt(1 - a)), up to a = 1.
  MuQuadrature q = gaussLegendreInSqrtMu(400);
  for (double a : kAlbedos) {
    HFunction h(a);
    double integral = 0.0;
    for (size_t i = 0; i < q.mu.size(); ++i) integral += q.weight[i] * h(q.mu[i]);
    EXPECT_NEAR(integral, 2.0 / a * (1.0 - std::sqrt(1.0 - a)), 1e-9) << "a = " << a;
  }
}

TEST(HFunction, FirstMomentOfTheConservativeCaseIsTwoOverRootThree) {
  MuQuadrature q = gaussLegendreInSqrtMu(400);
  HFunction h(1.0);
  double integral = 0.0;
  for (size_t i = 0; i < q.mu.size(); ++i) integral += q.weight[i] * q.mu[i] * h(q.mu[i]);
  EXPECT_NEAR(integral, 2.0 / std::sqrt(3.0), 1e-8);
}

TEST(HFunction, GridIsConverged) {
  for (double a : {0.5, 0.99, 1.0}) {
    HFunction coarse(a, 48), fine(a, 160);
    for (int i = 0; i <= 20; ++i) EXPECT_NEAR(coarse(i / 20.0), fine(i / 20.0), 1e-12 * fine(i / 20.0)) << "a = " << a;
  }
}

TEST(HFunction, ReflectedRadianceIntegratesToTheAlbedo) {
  // 2 pi int_0^1 L(mu0, mu) mu dmu = R(mu0) = 1 - sqrt(1 - a) H(mu0): energy leaves as it should.
  MuQuadrature q = gaussLegendreInSqrtMu(400);
  for (double a : kAlbedos) {
    HFunction h(a);
    for (double mu0 : {1.0, 0.8, 0.5, 0.2, 0.05}) {
      double reflected = 0.0;
      for (size_t i = 0; i < q.mu.size(); ++i)
        reflected += 2.0 * M_PI * q.weight[i] * q.mu[i] * halfSpaceReflectedRadiance(h, mu0, q.mu[i]);
      EXPECT_NEAR(reflected, halfSpaceAlbedo(h, mu0), 1e-9) << "a = " << a << ", mu0 = " << mu0;
      EXPECT_LE(halfSpaceAlbedo(h, mu0), 1.0 + 1e-12);
      EXPECT_GE(halfSpaceAlbedo(h, mu0), 0.0);
    }
  }
}

TEST(HFunction, ReflectionIsReciprocalAndSumsToTheUniformSky) {
  MuQuadrature q = gaussLegendreInSqrtMu(400);
  for (double a : {0.5, 0.99, 1.0}) {
    HFunction h(a);
    EXPECT_NEAR(halfSpaceReflectedRadiance(h, 1.0, 0.3), halfSpaceReflectedRadiance(h, 0.3, 1.0), 1e-14);
    EXPECT_NEAR(halfSpaceReflectedRadiance(h, 0.7, 0.2), halfSpaceReflectedRadiance(h, 0.2, 0.7), 1e-14);
    for (double mu : {1.0, 0.5, 0.1}) {
      // A sky of radiance 1 gives irradiance mu0 dOmega from each direction.
      double sky = 0.0;
      for (size_t i = 0; i < q.mu.size(); ++i) sky += 2.0 * M_PI * q.weight[i] * q.mu[i] * halfSpaceReflectedRadiance(h, q.mu[i], mu);
      EXPECT_NEAR(sky, halfSpaceUniformRadiance(h, mu), 1e-9) << "a = " << a << ", mu = " << mu;
    }
  }
}

TEST(HFunction, SingleScatteringAlbedoIsTheFirstOrderRadiance) {
  // H = 1 in the reflected radiance: (a/2)(1 - mu0 ln(1 + 1/mu0)).
  MuQuadrature q = gaussLegendreInSqrtMu(400);
  for (double mu0 : {1.0, 0.5, 0.1}) {
    double reflected = 0.0;
    for (size_t i = 0; i < q.mu.size(); ++i) reflected += 2.0 * M_PI * q.weight[i] * q.mu[i] * 0.7 / (4.0 * M_PI * (mu0 + q.mu[i]));
    EXPECT_NEAR(halfSpaceSingleScatteringAlbedo(0.7, mu0), reflected, 1e-12);
  }
}

TEST(HFunction, RefusesAlbedosOutsideZeroToOne) {
  for (double a : {0.0, -0.1, 1.01, std::nan("")}) EXPECT_THROW(HFunction{a}, Error) << a;
}

}  // namespace
}  // namespace subsplat
