// Heterogeneous materials: SubEdit profiles (Song et al. 2009; the paper's
// eq. 8, 9) mapped over a surface by UV.
//
// Every texel of a SubEdit material has its own profile, ln P(r) piecewise
// linear with n segments on [0, r_s], per colour channel. Kept that way, a
// material would need a splat kernel per texel. A ProfileSet instead models
// the material with no more than it needs (docs/HETEROGENEOUS.md):
//   - texels with the same profile share one palette entry; when more than
//     kMaxProfiles differ, the profiles are clustered (k-means on their energy
//     and mean radius per channel) and each texel takes its cluster's mean
//     profile (the mean of ln P);
//   - the number of segments is the smallest that keeps every palette
//     profile within the fit tolerance of the source;
//   - a map of one profile collapses to one texel.
// The palette is what the GPU gets: one splat kernel per entry, and a map of
// palette indices sampled by UV (nearest texel, repeating).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "material/dipole.h"
#include "material/radial_profile.h"

namespace subsplat {

class SplatKernel;

// One channel of a SubEdit profile: ln P at r_k = k r_s / n, k = 0..n;
// P = 0 beyond r_s.
class SegmentedProfile final : public RadialProfile {
 public:
  SegmentedProfile(const float* logKnots, int segments, double radiusMm, int stride = 1);

  double value(double r) const override;
  double energyWithin(double r) const override;
  double totalEnergy() const override { return cumulative_.back(); }
  double scaleHint() const override { return radiusMm_ / segments_; }

 private:
  std::vector<double> knots_;       // ln P
  std::vector<double> cumulative_;  // energy within r_k
  // Per segment, ln P's slope and 2 pi P(r_k): segmentEnergy's terms that do not depend on the
  // length (the kernel tables call it millions of times; the values are the ones it computed).
  std::vector<double> slope_, scale_;
  int segments_;
  double radiusMm_;
  double segmentEnergy(int k, double length) const;  // energy in [r_k, r_k + length]
};

struct ProfileSetInfo {
  int segments = 0, profiles = 0, width = 0, height = 0;
  double radiusMm = 0.0;
  // Relative energy error of the model against its source texels: the mean
  // over texels and channels, and the largest (docs/HETEROGENEOUS.md).
  double fitError = 0.0, maxFitError = 0.0;
  int sourceSegments = 0, sourceProfiles = 0, sourceWidth = 0, sourceHeight = 0;
};

class ProfileSet {
 public:
  static constexpr int kMaxSegments = 1024;
  static constexpr int kMaxProfiles = 64;
  // fromDipoles: the most distinct media whose profiles are evaluated; more are merged first.
  static constexpr int kMaxMedia = 2048;
  static constexpr int kMaxSide = 16384;
  static constexpr uint64_t kMaxSourceFloats = uint64_t(1) << 28;  // 1 GiB of source data
  static constexpr double kMaxLogValue = 50.0;                     // ln P, P in 1/mm^2
  static constexpr double kDefaultTolerance = 0.01;

  // width x height texels of ln P (1/mm^2) at n + 1 knots on [0, r_s] in mm,
  // texel-major, then knot, then RGB; texel row 0 at v = 0. tolerance: the
  // mean relative energy error allowed to the model, in [1e-6, 1]. maxTotal:
  // the most energy a profile may carry (its integral P 2 pi r dr, per channel);
  // a texel beyond it is refused, named (SubEdit files: 1, light is not made).
  static ProfileSet fromTexels(int width, int height, int segments, double radiusMm, const float* logKnots,
                               double tolerance, double maxTotal = std::numeric_limits<double>::infinity());
  // A homogeneous medium per texel (sigma_a, sigma_s' per mm, RGB per texel), its radial profile
  // from `model` (material/transport_model.h: kProfileDipole, kProfileTabulated), each profile
  // scaled to keep the model's total reflectance. (The TABULATED model's angular and thin-part
  // factors are a homogeneous material's: a profile set keeps the radial profiles alone.)
  static ProfileSet fromDipoles(int width, int height, const float* sigmaA, const float* sigmaSPrime, double eta,
                                double tolerance, int model = 0);
  // The model itself, as written to scene files: no fitting, only checks.
  static ProfileSet fromPalette(int segments, double radiusMm, std::vector<float> palette, int width, int height,
                                std::vector<uint16_t> map, const ProfileSetInfo& info);

  int segments() const { return info_.segments; }
  double radiusMm() const { return info_.radiusMm; }
  int profileCount() const { return info_.profiles; }
  int width() const { return info_.width; }
  int height() const { return info_.height; }
  const ProfileSetInfo& info() const { return info_; }
  const std::vector<float>& palette() const { return palette_; }  // profiles x (n + 1) x RGB
  const std::vector<uint16_t>& map() const { return map_; }         // width x height, row 0 at v = 0
  const std::vector<uint32_t>& texelCounts() const { return counts_; }
  const float* profile(int index) const { return palette_.data() + size_t(index) * (segments() + 1) * 3; }
  // Palette index at (u, v): the nearest texel, repeating outside [0, 1).
  int profileAt(float u, float v) const;
  // The profile of palette entry index, channel c.
  SegmentedProfile channel(int index, int c) const;
  // ln P per texel, the layout fromTexels takes (what a SubEdit file holds).
  std::vector<float> texels() const;
  // A splat kernel per palette entry at this scene scale, built on all cores
  // the first time and kept: every context and render that uses the set at
  // that scale shares them.
  std::vector<std::shared_ptr<const SplatKernel>> kernels(double mmPerUnit) const;

 private:
  int stride() const { return (segments() + 1) * 3; }
  std::vector<float> palette_;
  std::vector<uint16_t> map_;
  std::vector<uint32_t> counts_;
  ProfileSetInfo info_;
  struct KernelCache {
    std::mutex mutex;
    double mmPerUnit = 0.0;
    std::vector<std::shared_ptr<const SplatKernel>> kernels;
  };
  std::shared_ptr<KernelCache> kernelCache_ = std::make_shared<KernelCache>();
};

// SubEdit files (docs/SUBEDIT_FILE.md): OpenEXR, one FLOAT channel per knot
// and colour (P<k>.R, P<k>.G, P<k>.B) holding ln P at r_k, and metadata for
// the format, its version, n and r_s. Errors name the file and what is wrong.
ProfileSet readSubEditFile(const std::string& path, double tolerance);
void writeSubEditFile(const ProfileSet& set, const std::string& path);

}  // namespace subsplat
