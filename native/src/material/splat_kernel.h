// The splat kernel of one profile (a homogeneous dipole or one SubEdit
// palette entry, material/profile_set.h), averaged over the footprint
// of the irradiance texel it splats.
//
// Eq. 5 sums R_d(|x_i - x_o|) E(x_i) dA(x_i) over irradiance texels. Point
// sampling R_d at texel centres is only right when texels are much smaller
// than the profile: R_d peaks within z_r = 1/sigma_t' of the origin (0.5 mm
// for marble), far below a texel of a 512^2 buffer over a 1 m object, and the
// sum then over- and under-shoots in a texel-sized pattern. Instead each
// texel's flux is spread over a Gaussian footprint of standard deviation
// sigma = kFootprintSigma * texel size, and its kernel is R_d convolved with
// that Gaussian,
//
//   K(d, sigma) = integral of R_d(|x - x_o|) G_sigma(|x - x_i|) dA.
//
// Gaussians of that width on a texel grid sum to a constant within 0.2 %, so
// a plane of texels receives the plane integral of R_d whatever the texel
// size (a disk of the texel's area does not: disks leave gaps at texel
// corners). K stays radial and is tabulated per material over (sigma, d)
// from the closed-form energy of the dipole (docs/SPLATTING.md). The profile
// is cut at the radius holding kSupportEnergy of its energy and
// renormalised, so splats stay finite and no energy is lost.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "material/dipole.h"
#include "material/radial_profile.h"

namespace subsplat {

// A homogeneous medium: its coefficients and the model its profile comes from
// (material/transport_model.h: kProfileDipole, kProfileTabulated).
struct DipoleMaterial {
  std::array<DipoleChannel, 3> channels;
  double mmPerUnit = 1000.0;
  int model = 0;
};

class SplatKernel {
 public:
  static constexpr double kSupportEnergy = 0.99;
  static constexpr double kEffectiveRangeEnergy = 0.95;  // R_P, paper sec. 4
  static constexpr double kFootprintSigma = 0.6;   // x texel size
  static constexpr double kFootprintReach = 4.0;   // x sigma: the Gaussian's cut
  // Table axes: s = log2(sigma / supportRadius) in [kMinLog2, kMaxLog2];
  // t = sqrt(d / (kFootprintReach sigma + supportRadius)) in [0, 1].
  static constexpr int kSizeA = 96;
  static constexpr int kSizeD = 256;
  static constexpr double kMinLog2 = -12.0;
  static constexpr double kMaxLog2 = 12.0;

  using Channels = std::array<std::shared_ptr<const RadialProfile>, 3>;
  explicit SplatKernel(const DipoleMaterial& material);
  SplatKernel(Channels channels, double mmPerUnit);
  // Functions that are not profiles (MATERIAL_EDIT's basis splines, pipeline/transport_splatting.h):
  // kept whole to `supportRadius` (scene units), not cut at kSupportEnergy.
  SplatKernel(Channels channels, double mmPerUnit, double supportRadius);

  // The kernel of a homogeneous medium (either model), shared by the whole process: a new context (Blender's UI
  // makes one for each F12 render and one for each viewport) finds the tables of the dipoles it
  // had before instead of building them again (0.1-0.2 s each). The kDipoleCacheSize dipoles
  // asked for most recently stay built (0.4 MB each).
  static constexpr size_t kDipoleCacheSize = 32;
  static std::shared_ptr<const SplatKernel> forDipole(const DipoleMaterial& material);
  // Kernel tables built since the process started (tests of the sharing).
  static uint64_t builtCount();

  double supportRadius() const { return supportRadius_; }  // scene units
  const std::array<double, 3>& effectiveRange() const { return effectiveRange_; }
  const std::array<double, 3>& totalReflectance() const { return totalReflectance_; }

  // Kernel of a footprint of standard deviation sigma at distance d
  // (1 / scene unit^2), channel c, by quadrature.
  double footprintAverage(int c, double d, double sigma) const;
  // The three channels' at once (the table's): the footprint's weights are the channels' own.
  std::array<double, 3> footprintAverages(double d, double sigma) const;
  // Energy of channel c within radius r (scene units), renormalised.
  double energyWithin(int c, double r) const;

  // Eq. 14: the minimal effective rendering radius R-bar, as a fraction of
  // R_P, of a splatting buffer with T pixels per R_P: the smallest r from
  // which a Riemann sum at spacing 1 / T of the mean normalised profile
  // (eq. 15, 16; the mean of the three channels) over [r, 1] stays within
  // epsilon of its integral (the profile's energy within R_P is 1). R_P is
  // the longest of the three channels' ranges (docs/SPLATTING.md). Tabulated
  // at kRadiusTableSize values of log2 T evenly in [kMinLog2T, kMaxLog2T].
  static constexpr int kRadiusTableSize = 64;
  static constexpr double kMinLog2T = -2.0;
  static constexpr double kMaxLog2T = 12.0;
  std::vector<float> minimalRadiusTable(double epsilon) const;
  // The same over the mean normalised profile of several kernels, weighted
  // (a heterogeneous material's palette, weighted by texel counts).
  static std::vector<float> minimalRadiusTable(const std::vector<std::pair<const SplatKernel*, double>>& kernels,
                                               double epsilon);
  const RadialProfile& channel(int c) const { return *channels_[size_t(c)]; }
  double mmPerUnit() const { return mmPerUnit_; }

  // kSizeA rows of kSizeD RGBA texels (alpha unused), row-major. Made on the first call (0.1-0.3 s,
  // thread-safe): a material that is only projected (MATERIAL_EDIT's edits) never needs it.
  const std::vector<float>& table() const;
  static double tableSigma(int ia, double supportRadius);
  static double tableDistance(int id, double sigma, double supportRadius);

 private:
  Channels channels_;
  std::array<double, 3> normalisation_{}, effectiveRange_{}, totalReflectance_{};
  double mmPerUnit_ = 1.0, supportRadius_ = 0.0;
  mutable std::once_flag tableBuilt_;
  mutable std::vector<float> table_;
};

}  // namespace subsplat
