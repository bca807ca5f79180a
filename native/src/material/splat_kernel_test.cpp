#include "material/splat_kernel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace subsplat {
namespace {

DipoleMaterial marble(double mmPerUnit) {
  DipoleMaterial m;
  m.channels = {DipoleChannel{0.0021, 2.19, 1.3}, DipoleChannel{0.0041, 2.62, 1.3},
                DipoleChannel{0.0071, 3.00, 1.3}};
  m.mmPerUnit = mmPerUnit;
  return m;
}

// Sum of the kernel over a square grid of texels of the given size, at a
// receiver offset (ox, oy) in texels: what a plane of uniform flux receives.
double gridSum(const SplatKernel& k, int c, double texel, double ox, double oy) {
  double sigma = SplatKernel::kFootprintSigma * texel;
  int n = int(std::ceil((k.supportRadius() + SplatKernel::kFootprintReach * sigma) / texel)) + 1;
  double sum = 0.0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j) {
      double d = std::hypot((i - ox) * texel, (j - oy) * texel);
      sum += k.footprintAverage(c, d, sigma) * texel * texel;
    }
  return sum;
}

TEST(SplatKernel, PlaneSumEqualsTotalReflectanceForAnyTexelSize) {
  // 1 scene unit = 20 mm: z_r (red) is 0.023 units, the support ~2 units.
  // Texels from below z_r to well above the support.
  SplatKernel k(marble(20.0));
  for (double fraction : {1.0 / 150, 1.0 / 30, 1.0 / 5, 1.0, 5.0}) {
    double texel = k.supportRadius() * fraction;
    for (auto [ox, oy] : {std::pair{0.0, 0.0}, {0.5, 0.5}, {0.25, 0.1}}) {
      for (int c = 0; c < 3; ++c) {
        double sum = gridSum(k, c, texel, ox, oy);
        EXPECT_NEAR(sum / k.totalReflectance()[c], 1.0, 0.01)
            << "texel " << texel << " offset " << ox << "," << oy << " channel " << c;
      }
    }
  }
}

TEST(SplatKernel, SmallFootprintIsThePointProfile) {
  DipoleMaterial m = marble(20.0);
  SplatKernel k(m);
  Dipole red(m.channels[0]);
  // The cut profile is renormalised to the full energy.
  double renormalise = red.totalReflectance() / red.energyWithin(k.supportRadius() * 20.0);
  for (double d : {0.01, 0.05, 0.2}) {
    double expected = renormalise * red.diffuseReflectance(d * 20.0) * 20.0 * 20.0;  // 1/unit^2
    EXPECT_NEAR(k.footprintAverage(0, d, 1e-5) / expected, 1.0, 1e-3) << d;
  }
}

TEST(SplatKernel, TableMatchesExactKernelAtNodes) {
  SplatKernel k(marble(20.0));
  const auto& table = k.table();
  for (int ia : {0, 40, 95})
    for (int id : {0, 17, 128, 255}) {
      double sigma = SplatKernel::tableSigma(ia, k.supportRadius());
      double d = SplatKernel::tableDistance(id, sigma, k.supportRadius());
      float value = table[(size_t(ia) * SplatKernel::kSizeD + id) * 4 + 1];
      EXPECT_FLOAT_EQ(value, float(k.footprintAverage(1, d, sigma)));
    }
}

TEST(SplatKernel, EffectiveRangeKeeps95PercentOfEnergy) {
  SplatKernel k(marble(20.0));
  for (int c = 0; c < 3; ++c) {
    // Renormalising the cut profile scales it by at most 1 / kSupportEnergy.
    double kept = k.energyWithin(c, k.effectiveRange()[c]) / k.totalReflectance()[c];
    EXPECT_GE(kept, 0.95 - 1e-6);
    EXPECT_LE(kept, 0.95 / SplatKernel::kSupportEnergy + 1e-6);
    EXPECT_LE(k.effectiveRange()[c], k.supportRadius());
  }
}

}  // namespace
}  // namespace subsplat

namespace subsplat {
namespace {

// Eq. 14: finer splatting buffers (more pixels per R_P) can render closer to
// the sample; R-bar falls as T grows and reaches 0 once pixels are far below
// the profile's scale.
TEST(MinimalRadius, FallsWithResolutionAndVanishesWhenFine) {
  DipoleMaterial marble;
  const double sa[3] = {0.0021, 0.0041, 0.0071}, ss[3] = {2.19, 2.62, 3.00};
  for (int c = 0; c < 3; ++c) marble.channels[c] = {sa[c], ss[c], 1.3};
  marble.mmPerUnit = 100.0;
  SplatKernel kernel(marble);
  std::vector<float> table = kernel.minimalRadiusTable(0.001);
  ASSERT_EQ(table.size(), size_t(SplatKernel::kRadiusTableSize));
  for (size_t i = 1; i < table.size(); ++i) EXPECT_LE(table[i], table[i - 1] + 1e-6f) << i;
  EXPECT_GT(table.front(), 0.5f);   // a quarter pixel per R_P: only the tail
  EXPECT_EQ(table.back(), 0.0f);    // 4096 pixels per R_P: everything
  std::vector<float> loose = kernel.minimalRadiusTable(0.01);
  for (size_t i = 0; i < table.size(); ++i) EXPECT_LE(loose[i], table[i] + 1e-6f) << i;
}

// With the paper's epsilon, a long profile keeps R-bar = 1 (the finest
// splatting level takes all of R_P) until a level has some 50 pixels per R_P:
// why multiresolution splatting gains little on wax_jade (docs/MULTIRES.md).
TEST(MinimalRadius, LongProfileStaysWholeBelowFiftyPixelsPerRange) {
  DipoleMaterial skimmilk;  // the wax of wax_jade
  const double sa[3] = {0.0014, 0.0025, 0.0142}, ss[3] = {0.70, 1.22, 1.90};
  for (int c = 0; c < 3; ++c) skimmilk.channels[c] = {sa[c], ss[c], 1.3};
  skimmilk.mmPerUnit = 40.0;
  std::vector<float> table = SplatKernel(skimmilk).minimalRadiusTable(0.001);
  auto at = [&](double T) {  // the entry at or just below T
    double u = (std::log2(T) - SplatKernel::kMinLog2T) / (SplatKernel::kMaxLog2T - SplatKernel::kMinLog2T);
    return table[size_t(std::floor(u * (table.size() - 1)))];
  };
  for (double T : {8.0, 16.0, 32.0, 64.0, 128.0, 256.0}) std::printf("T %5.0f: R-bar %.3f\n", T, at(T));
  EXPECT_EQ(at(32.0), 1.0f);
  EXPECT_LT(at(64.0), 1.0f);
  EXPECT_LT(at(128.0), 0.7f);
}

}  // namespace
}  // namespace subsplat
