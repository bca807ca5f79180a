// The transport tables (profile_table.h): the same program and seed give the committed bytes,
// the text reads back exactly, and the half-space totals are the H-function's.
#include "transport/profile_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>

#include "transport/hfunction.h"
#include "util/error.h"

namespace subsplat {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

const std::string kSmallTable = std::string(SUBSPLAT_TRANSPORT_TESTDATA) + "/small_profile_table.txt";

TEST(ProfileTable, RegeneratingTheSmallTableGivesTheCommittedBytes) {
  // Written by: build/native/subsplat_tables --small native/src/transport/testdata/small_profile_table.txt
  std::string committed = readFile(kSmallTable);
  ASSERT_FALSE(committed.empty()) << kSmallTable;
  ProfileTableSpec spec = smallProfileTableSpec();
  spec.threads = 2;  // the threads do not change a count
  EXPECT_TRUE(writeProfileTable(makeProfileTable(spec)) == committed)
      << "the slab Monte Carlo or the table format changed: regenerate " << kSmallTable << " and say why";
}

TEST(ProfileTable, TextReadsBackExactly) {
  std::string text = readFile(kSmallTable);
  ProfileTable table = readProfileTable(text);
  EXPECT_EQ(writeProfileTable(table), text);
  EXPECT_EQ(table.entries.size(), table.spec.albedos.size() * table.spec.thicknesses.size());
}

TEST(ProfileTable, HalfSpaceTotalsAndAnglesAreTheHFunctions) {
  ProfileTable table = readProfileTable(readFile(kSmallTable));
  for (size_t i = 0; i < table.spec.albedos.size(); ++i) {
    double a = table.spec.albedos[i];
    const SlabTallies& t = table.at(i, 0);
    ASSERT_TRUE(std::isinf(t.settings.thickness));
    double exact = halfSpaceAlbedo(HFunction(a), table.spec.mu0);
    EXPECT_NEAR(t.reflectance(), exact, 4 * t.standardError(t.reflected)) << "a = " << a;
    // The radial bins hold what was reflected within the last edge; the rest lies beyond it.
    uint64_t binned = std::accumulate(t.reflectedByRadius.begin(), t.reflectedByRadius.end(), uint64_t{0});
    EXPECT_LE(binned, t.reflected);
    EXPECT_GE(binned, t.reflected * 0.99) << "a = " << a;
    // The exit-cosine bins: a H(mu0) H(mu) / (4 pi (mu0 + mu)) integrated over each.
    HFunction h(a);
    int bins = table.spec.cosineBins;
    ASSERT_EQ(t.reflectedByCosine.size(), static_cast<size_t>(bins));
    EXPECT_EQ(std::accumulate(t.reflectedByCosine.begin(), t.reflectedByCosine.end(), uint64_t{0}), t.reflected);
    MuQuadrature q = gaussLegendreInSqrtMu(16);
    for (int k = 0; k < bins; ++k) {
      double lo = static_cast<double>(k) / bins, hi = static_cast<double>(k + 1) / bins, exact = 0.0;
      for (size_t n = 0; n < q.mu.size(); ++n) {
        double mu = lo + (hi - lo) * q.mu[n];  // the sqrt grid over the bin: fine for the first one's mu log mu
        exact += (hi - lo) * q.weight[n] * 2 * M_PI * mu * halfSpaceReflectedRadiance(h, table.spec.mu0, mu);
      }
      EXPECT_NEAR(t.fraction(t.reflectedByCosine[k]), exact, 4 * t.standardError(t.reflectedByCosine[k]) + 1e-6)
          << "a = " << a << ", bin " << k;
    }
  }
}

TEST(ProfileTable, ProfilesConserveEnergy) {
  ProfileTable table = readProfileTable(readFile(kSmallTable));
  for (const SlabTallies& t : table.entries) {
    EXPECT_NEAR(t.reflectance() + t.transmittance() + t.absorptance(), 1.0, 1e-15);
    double binned = 0.0;
    for (size_t k = 0; k + 1 < t.settings.radiusEdges.size(); ++k) {
      double r0 = t.settings.radiusEdges[k], r1 = t.settings.radiusEdges[k + 1];
      binned += (t.exitanceInRadiusBin(t.reflectedByRadius, k) + t.exitanceInRadiusBin(t.transmittedByRadius, k)) *
                M_PI * (r1 * r1 - r0 * r0);
    }
    EXPECT_LE(binned, t.reflectance() + t.scatteredTransmittance() + 1e-15);
  }
}

TEST(ProfileTable, RefusesWhatItDidNotWrite) {
  std::string text = readFile(kSmallTable);
  EXPECT_THROW(readProfileTable(""), Error);
  EXPECT_THROW(readProfileTable("subsplat-transport-table 2\n"), Error);
  EXPECT_THROW(readProfileTable(text.substr(0, text.size() / 2)), Error);
  EXPECT_THROW(readProfileTable(text + "more\n"), Error);
  std::string changed = text;
  changed.replace(changed.find("reflected "), 11, "reflected 9");  // the counts no longer add up
  EXPECT_THROW(readProfileTable(changed), Error);
}

}  // namespace
}  // namespace subsplat
