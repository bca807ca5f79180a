#include "material/splat_kernel.h"

#include <algorithm>
#include <cmath>

namespace subsplat {

SplatKernel::SplatKernel(const DipoleMaterial& m)
    : dipoles_{Dipole(m.channels[0]), Dipole(m.channels[1]), Dipole(m.channels[2])},
      mmPerUnit_(m.mmPerUnit) {
  for (int c = 0; c < 3; ++c) {
    const Dipole& dipole = dipoles_[c];
    totalReflectance_[c] = dipole.totalReflectance();
    effectiveRange_[c] = dipole.radiusForEnergy(kEffectiveRangeEnergy) / mmPerUnit_;
    supportRadius_ = std::max(supportRadius_, dipole.radiusForEnergy(kSupportEnergy) / mmPerUnit_);
  }
  for (int c = 0; c < 3; ++c) {
    double kept = dipoles_[c].energyWithin(supportRadius_ * mmPerUnit_);
    normalisation_[c] = kept > 0.0 ? totalReflectance_[c] / kept : 0.0;
  }

  table_.assign(size_t(kSizeA) * kSizeD * 4, 0.0f);
  for (int ia = 0; ia < kSizeA; ++ia) {
    double sigma = tableSigma(ia, supportRadius_);
    for (int id = 0; id < kSizeD; ++id) {
      double d = tableDistance(id, sigma, supportRadius_);
      float* texel = &table_[(size_t(ia) * kSizeD + id) * 4];
      for (int c = 0; c < 3; ++c) texel[c] = float(footprintAverage(c, d, sigma));
    }
  }
}

double SplatKernel::tableSigma(int ia, double supportRadius) {
  double s = kMinLog2 + (kMaxLog2 - kMinLog2) * ia / (kSizeA - 1);
  return supportRadius * std::exp2(s);
}

double SplatKernel::tableDistance(int id, double sigma, double supportRadius) {
  double t = double(id) / (kSizeD - 1);
  return t * t * (kFootprintReach * sigma + supportRadius);
}

double SplatKernel::energyWithin(int c, double r) const {
  r = std::min(r, supportRadius_);
  return normalisation_[c] * dipoles_[c].energyWithin(r * mmPerUnit_);
}

namespace {

// e^{-x} I_0(x), the exponentially scaled modified Bessel function
// (Abramowitz & Stegun 9.8.1 and 9.8.2, |error| < 2e-7 relative).
double besselI0Scaled(double x) {
  if (x < 3.75) {
    double t = (x / 3.75) * (x / 3.75);
    double i0 = 1.0 + t * (3.5156229 + t * (3.0899424 + t * (1.2067492 + t * (0.2659732 +
                t * (0.0360768 + t * 0.0045813)))));
    return i0 * std::exp(-x);
  }
  double t = 3.75 / x;
  return (0.39894228 + t * (0.01328592 + t * (0.00225319 + t * (-0.00157565 + t * (0.00916281 +
          t * (-0.02057706 + t * (0.02635537 + t * (-0.01647633 + t * 0.00392377)))))))) /
         std::sqrt(x);
}

}  // namespace

double SplatKernel::footprintAverage(int c, double d, double sigma) const {
  // The mean of a 2D Gaussian centred at distance d over a circle of radius r
  // is exp(-(d^2 + r^2) / 2 sigma^2) I_0(d r / sigma^2) / (2 pi sigma^2).
  // Integrate it against the radial energy dE(r) (a Stieltjes sum, so the
  // profile's peak near r = 0 is never missed, however small z_r is).
  double reach = kFootprintReach * sigma;
  double lo = std::max(0.0, d - reach), hi = std::min(d + reach, supportRadius_);
  if (hi <= lo) return 0.0;
  constexpr int kSteps = 64;
  double step = (hi - lo) / kSteps, sum = 0.0;
  double e0 = energyWithin(c, lo);
  for (int j = 0; j < kSteps; ++j) {
    double r = lo + (j + 0.5) * step;
    double e1 = energyWithin(c, lo + (j + 1) * step);
    double x = d * r / (sigma * sigma);
    double weight = std::exp(-(d - r) * (d - r) / (2 * sigma * sigma)) * besselI0Scaled(x);
    sum += weight * (e1 - e0);
    e0 = e1;
  }
  return sum / (2.0 * M_PI * sigma * sigma);
}

}  // namespace subsplat
