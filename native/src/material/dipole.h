// The dipole diffusion model of Jensen et al. 2001 (papers/xu2007 table 1,
// papers/lensch2002 fig. 2). Lengths in millimetres, R_d in 1/mm^2.
#pragma once

#include <cmath>

#include "material/radial_profile.h"

namespace subsplat {

// The dipole's R_d at squared distance r2 from the point where light enters
// (Jensen et al. 2001, eq. 4): a real source at depth zr and a virtual one at
// height zv, effective extinction sigmaTr, scale = reduced albedo / (4 pi).
// Lengths in any one unit; R_d in 1 / unit^2. Dipole and REFERENCE both
// evaluate it here.
// In double, or in float where REFERENCE sums millions of them (docs/REFERENCE.md, "Arithmetic").
template <typename T>
inline T dipoleReflectance(T r2, T zr, T zv, T sigmaTr, T scale) {
  T dr2 = r2 + zr * zr, dv2 = r2 + zv * zv;
  T dr = std::sqrt(dr2), dv = std::sqrt(dv2);
  T real = zr * (sigmaTr + T(1) / dr) * std::exp(-sigmaTr * dr) / dr2;
  T virt = zv * (sigmaTr + T(1) / dv) * std::exp(-sigmaTr * dv) / dv2;
  return scale * (real + virt);
}

struct DipoleChannel {
  double sigmaA = 0.0;       // absorption, 1/mm
  double sigmaSPrime = 0.0;  // reduced scattering, 1/mm
  double eta = 1.3;
};

// Fresnel diffuse reflectance F_dr (polynomial fit, Jensen et al. 2001).
double fresnelDiffuseReflectance(double eta);

// Rd_total of a dipole of reduced albedo a' under relative index eta, the energy R_d carries over
// the whole plane (Jensen et al. 2001; DESIGN.md): a'/2 (1 + e^{-4/3 A s}) e^{-s}, s = sqrt(3(1 - a')).
// The one implementation: Dipole::totalReflectance and the add-on's Principled conversion
// (ssDipoleTotalReflectance) call it.
double dipoleTotalReflectance(double reducedAlbedo, double eta);

// Fresnel transmittance F_t = 1 - F_r for unpolarised light entering a
// dielectric of relative index eta at cos(theta) = cosTheta.
double fresnelTransmittance(double eta, double cosTheta);

class Dipole final : public RadialProfile {
 public:
  explicit Dipole(const DipoleChannel& channel);

  // R_d(r): radiant exitance at distance r per unit incident flux.
  double diffuseReflectance(double r) const;
  // Energy within radius r: the integral of R_d over the disk, 2 pi r dr.
  // Closed form: d/dr(e^{-s d}/d) = -(s + 1/d) e^{-s d} r / d^3.
  double energyWithin(double r) const override;
  // Rd_total: energy over the whole plane (DESIGN.md, Jensen et al. 2001).
  double totalReflectance() const;

  double value(double r) const override { return diffuseReflectance(r); }
  double totalEnergy() const override { return totalReflectance(); }
  double scaleHint() const override { return zr_; }

  double reducedAlbedo() const { return albedo_; }
  double effectiveExtinction() const { return sigmaTr_; }
  double realSourceDepth() const { return zr_; }     // z_r = 1 / sigma_t'
  double virtualSourceHeight() const { return zv_; } // z_v = z_r (1 + 4A/3)

 private:
  double albedo_ = 0, eta_ = 1, sigmaTr_ = 0, zr_ = 0, zv_ = 0;
};

}  // namespace subsplat
