#include "material/dipole.h"

#include <gtest/gtest.h>

#include <cmath>

namespace subsplat {
namespace {

// Marble, Skin1, Ketchup of Jensen et al. 2001 (red channel), eta 1.3.
const DipoleChannel kMedia[] = {{0.0021, 2.19, 1.3}, {0.032, 0.74, 1.3}, {0.061, 0.18, 1.3}};

TEST(Dipole, TotalReflectanceMatchesDesignClosedForm) {
  for (const DipoleChannel& c : kMedia) {
    double albedo = c.sigmaSPrime / (c.sigmaA + c.sigmaSPrime);
    double fdr = fresnelDiffuseReflectance(c.eta);
    double A = (1 + fdr) / (1 - fdr);
    double root = std::sqrt(3 * (1 - albedo));
    double expected = albedo / 2 * (1 + std::exp(-4.0 / 3.0 * A * root)) * std::exp(-root);
    EXPECT_NEAR(Dipole(c).totalReflectance(), expected, 1e-12);
  }
}

TEST(Dipole, EnergyWithinIsTheIntegralOfTheProfile) {
  for (const DipoleChannel& c : kMedia) {
    Dipole d(c);
    // Midpoint rule on a geometric grid, against the closed form.
    double r = 1e-6, integral = 0.0;
    while (r < 200.0) {
      double next = r * 1.001;
      double mid = 0.5 * (r + next);
      integral += d.diffuseReflectance(mid) * 2 * M_PI * mid * (next - r);
      r = next;
    }
    EXPECT_NEAR(integral, d.energyWithin(200.0), 1e-4 * d.totalReflectance());
    EXPECT_NEAR(d.energyWithin(1e9), d.totalReflectance(), 1e-12);
  }
}

TEST(Dipole, ProfileValuesMatchJensenFormula) {
  // R_d at r = 1 mm for marble red, computed by hand from xu2007 eq. 4.
  DipoleChannel c{0.0021, 2.19, 1.3};
  double st = c.sigmaA + c.sigmaSPrime, albedo = c.sigmaSPrime / st;
  double str = std::sqrt(3 * c.sigmaA * st), fdr = fresnelDiffuseReflectance(1.3);
  double A = (1 + fdr) / (1 - fdr), zr = 1 / st, zv = zr * (1 + 4 * A / 3);
  double dr = std::sqrt(1 + zr * zr), dv = std::sqrt(1 + zv * zv);
  double expected = albedo / (4 * M_PI) *
                    (zr * (str + 1 / dr) * std::exp(-str * dr) / (dr * dr) +
                     zv * (str + 1 / dv) * std::exp(-str * dv) / (dv * dv));
  EXPECT_NEAR(Dipole(c).diffuseReflectance(1.0), expected, 1e-12);
  EXPECT_GT(Dipole(c).diffuseReflectance(0.1), Dipole(c).diffuseReflectance(1.0));
}

TEST(Dipole, RadiusForEnergyInvertsEnergyWithin) {
  Dipole d(kMedia[0]);
  double r95 = d.radiusForEnergy(0.95);
  EXPECT_NEAR(d.energyWithin(r95) / d.totalReflectance(), 0.95, 1e-9);
  EXPECT_LT(r95, d.radiusForEnergy(0.99));
}

// REFERENCE evaluates R_d in scene units through the same function as Dipole
// (in mm): lengths scale by mm per unit, R_d by its square.
TEST(Dipole, ReflectanceInSceneUnitsIsTheProfileInMillimetres) {
  const double mmPerUnit = 37.0;
  for (const DipoleChannel& c : kMedia) {
    Dipole d(c);
    for (double rMm : {0.0, 0.01, 0.3, 2.0, 15.0}) {
      double rUnits = rMm / mmPerUnit;
      double perUnit2 = dipoleReflectance(rUnits * rUnits, d.realSourceDepth() / mmPerUnit,
                                          d.virtualSourceHeight() / mmPerUnit,
                                          d.effectiveExtinction() * mmPerUnit, d.reducedAlbedo() / (4.0 * M_PI));
      EXPECT_NEAR(perUnit2 / (mmPerUnit * mmPerUnit), d.diffuseReflectance(rMm), 1e-12 * d.diffuseReflectance(rMm))
          << rMm;
    }
  }
}

TEST(Fresnel, TransmittanceAtNormalIncidenceAndGrazing) {
  double eta = 1.5, r0 = std::pow((eta - 1) / (eta + 1), 2);
  EXPECT_NEAR(fresnelTransmittance(eta, 1.0), 1 - r0, 1e-9);
  EXPECT_NEAR(fresnelTransmittance(eta, 0.0), 0.0, 1e-9);
  EXPECT_NEAR(fresnelTransmittance(1.0, 0.3), 1.0, 1e-9);
}

}  // namespace
}  // namespace subsplat
