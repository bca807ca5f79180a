// REFERENCE's table of the TABULATED profile (reference/squared_radius_table.h): it must give the
// profile it tabulates, point by point and in energy, for every measured medium at any scene scale.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "reference/squared_radius_table.h"
#include "testing/procedural.h"

namespace subsplat {
namespace {

std::vector<std::shared_ptr<const TabulatedProfile>> presetChannels(const testing::PresetMedium& m) {
  std::vector<std::shared_ptr<const TabulatedProfile>> channels;
  for (int c = 0; c < 3; ++c)
    channels.push_back(std::make_shared<TabulatedProfile>(DipoleChannel{m.sigmaA[c], m.sigmaSPrime[c], 1.3}));
  return channels;
}

TEST(ReferenceTable, AgreesWithTheProfileItTabulates) {
  double worst = 0.0;
  for (const testing::PresetMedium& medium : testing::kPresetMedia) {
    auto channels = presetChannels(medium);
    for (double mmPerUnit : {0.1, 1.0, 1000.0}) {  // a sub-millimetre part, millimetres, metres
      SquaredRadiusTable table = tabulate(channels, mmPerUnit);
      for (int c = 0; c < 3; ++c) {
        const TabulatedProfile& p = *channels[size_t(c)];
        const double perUnit2 = mmPerUnit * mmPerUnit, peak = p.value(0.0);
        // Point by point, log-uniform from well inside the constant core to past the end, wherever
        // P is at least 1e-6 of its peak (the tail beyond carries nothing REFERENCE can see).
        const double lo = 0.1 * p.innerRadius(), hi = 2.0 * p.outerRadius();
        constexpr int kPoints = 20000;
        for (int i = 0; i <= kPoints; ++i) {
          double r = lo * std::pow(hi / lo, double(i) / kPoints);  // mm
          double exact = p.value(r), got = table.value(r * r / perUnit2, c) / perUnit2;
          if (exact < 1e-6 * peak) {
            EXPECT_LE(got, 1.01e-6 * peak) << medium.name << " channel " << c << " r " << r << " mm";
            continue;
          }
          double error = std::abs(got - exact) / exact;
          worst = std::max(worst, error);
          ASSERT_LT(error, 2e-3) << medium.name << " channel " << c << " at " << mmPerUnit << " mm per unit, r "
                                 << r << " mm: " << got << " against " << exact;
        }
        EXPECT_NEAR(table.value(0.0, c) / perUnit2 / peak, 1.0, 1e-6) << medium.name;
        EXPECT_EQ(table.value(4.0 * p.outerRadius() * p.outerRadius() / perUnit2 * 4.0, c), 0.0) << medium.name;
        // In energy: the midpoint rule over 2 pi r dr on a fine grid in r^2, table against profile.
        double tableEnergy = 0.0, exactEnergy = 0.0;
        const double r2End = p.outerRadius() * p.outerRadius();
        constexpr int kSteps = 100000;
        // Geometric in r^2 from the core (P constant: pi r^2 P there) to the end.
        double r2Start = p.innerRadius() * p.innerRadius() * 0.01;
        tableEnergy = exactEnergy = M_PI * r2Start * peak;
        for (int i = 0; i < kSteps; ++i) {
          double a = r2Start * std::pow(r2End / r2Start, double(i) / kSteps);
          double b = r2Start * std::pow(r2End / r2Start, double(i + 1) / kSteps);
          double m = 0.5 * (a + b);
          exactEnergy += M_PI * (b - a) * p.value(std::sqrt(m));
          tableEnergy += M_PI * (b - a) * table.value(m / perUnit2, c) / perUnit2;
        }
        EXPECT_NEAR(tableEnergy / exactEnergy, 1.0, 1e-5) << medium.name << " channel " << c;
        EXPECT_NEAR(exactEnergy / p.totalEnergy(), 1.0, 2e-3) << medium.name << " channel " << c << " (the quadrature)";
      }
    }
  }
  std::printf("worst relative difference from the profile where P >= 1e-6 of its peak: %.2e\n", worst);
  EXPECT_LT(worst, 2e-3);  // at the profile's knots (squared_radius_table.h); elsewhere within 1e-4
}

TEST(ReferenceTable, TakesAnyRadiusWithoutFailing) {
  auto channels = presetChannels(testing::kPresetMedia[0]);
  SquaredRadiusTable table = tabulate(channels, 1.0);
  for (double r2 : {0.0, -0.0, -1.0, 1e-300, 1e300, double(INFINITY), double(NAN)}) {
    double v[3];
    table.values(r2, v);
    for (double x : v) EXPECT_TRUE(std::isfinite(x) && x >= 0.0) << r2;
  }
}

}  // namespace
}  // namespace subsplat
