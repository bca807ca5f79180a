#include "material/radial_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "material/dipole.h"
#include "material/transport_model.h"

namespace subsplat {
namespace {

// The table against the profiles it tabulates, under the dipole and the TABULATED model, for
// Marble, Skin1 and Ketchup of Jensen et al. 2001 as the three channels of one table, and for a
// long, bright medium beside a short, dark one. Over 200 000 radii from a thousandth of the
// shortest channel's half-energy radius to twice the reach, for each channel: the energy within
// the radius is within 1e-5 of the total, and the energy between neighbouring radii (a ring as thin
// as a near kernel's ray crosses) within 1e-6 of it. P, within the radius keeping all but 1e-6 of
// the energy: the dipole's within 1e-4 of P or, where P is smaller, of a millionth of P at the
// half-energy radius; TABULATED's, which the table leaves to the profile (a cubic misses its
// singular peak and its table's end by up to 90 %, on these media), exact. The held-out images are
// read to 0.1 %.
TEST(RadialTable, AgreesWithTheProfilesItTabulates) {
  const DipoleChannel sets[][3] = {
      {{0.0021, 2.19, 1.3}, {0.032, 0.74, 1.3}, {0.061, 0.18, 1.3}},
      {{0.0001, 5.0, 1.0}, {1.5, 0.5, 1.0}, {0.01, 1.0, 1.0}},
  };
  for (int model : {int(kProfileDipole), int(kProfileTabulated)})
    for (const auto& media : sets) {
      std::array<std::shared_ptr<const RadialProfile>, 3> profiles;
      std::array<const RadialProfile*, 3> channels{};
      double shortest = INFINITY;
      for (int c = 0; c < 3; ++c) {
        profiles[size_t(c)] = makeMediumProfile(media[c], model);
        channels[size_t(c)] = profiles[size_t(c)].get();
        shortest = std::min(shortest, profiles[size_t(c)]->radiusForEnergy(0.5));
      }
      RadialTable table(channels, model == kProfileDipole);
      ASSERT_GT(table.reach(), 0.0);
      for (int c = 0; c < 3; ++c) {
        const RadialProfile& profile = *profiles[size_t(c)];
        const double total = profile.totalEnergy(), within = profile.radiusForEnergy(1.0 - 1e-6),
                     small = 1e-6 * profile.value(profile.radiusForEnergy(0.5));
        double worst = 0.0, worstRing = 0.0, worstValue = 0.0, previous = 0.0, previousExact = 0.0;
        const int n = 200000;
        for (int k = 0; k <= n; ++k) {
          const double r = 1e-3 * shortest * std::pow(2.0 * table.reach() / (1e-3 * shortest), double(k) / n);
          const double e = table.energyWithin(r)[c], exact = profile.energyWithin(r);
          worst = std::max(worst, std::abs(e - exact) / total);
          if (k > 0) worstRing = std::max(worstRing, std::abs((e - previous) - (exact - previousExact)) / total);
          previous = e, previousExact = exact;
          const double p = profile.value(r);
          if (r <= within) worstValue = std::max(worstValue, std::abs(table.value(r)[c] - p) / std::max(p, small));
        }
        std::printf("model %d, sigma_a %.4f sigma_s' %.2f eta %.1f (reach %.3g mm): energy %.2e, ring %.2e of the "
                    "total; P %.2e\n",
                    model, media[c].sigmaA, media[c].sigmaSPrime, media[c].eta, table.reach(), worst, worstRing,
                    worstValue);
        EXPECT_LT(worst, 1e-5);
        EXPECT_LT(worstRing, 1e-6);
        if (model == kProfileDipole) EXPECT_LT(worstValue, 1e-4);
        else EXPECT_EQ(worstValue, 0.0);
        EXPECT_EQ(table.energyWithin(0.0)[c], profile.energyWithin(0.0));
        EXPECT_EQ(table.value(2.0 * table.reach())[c], 0.0);
      }
    }
  EXPECT_EQ(RadialTable().energyWithin(1.0), glm::dvec3(0.0));  // nothing tabulated: nothing
  EXPECT_EQ(RadialTable().value(1.0), glm::dvec3(0.0));
}

}  // namespace
}  // namespace subsplat
