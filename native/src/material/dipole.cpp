#include "material/dipole.h"

#include <algorithm>
#include <cmath>

namespace subsplat {

double fresnelDiffuseReflectance(double eta) {
  return -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
}

double dipoleTotalReflectance(double reducedAlbedo, double eta) {
  double fdr = fresnelDiffuseReflectance(eta);
  double A = (1.0 + fdr) / (1.0 - fdr);
  double root = std::sqrt(3.0 * (1.0 - reducedAlbedo));
  return 0.5 * reducedAlbedo * (1.0 + std::exp(-4.0 / 3.0 * A * root)) * std::exp(-root);
}

double fresnelTransmittance(double eta, double cosTheta) {
  cosTheta = std::clamp(cosTheta, 0.0, 1.0);
  double sin2T = (1.0 - cosTheta * cosTheta) / (eta * eta);
  if (sin2T >= 1.0) return 0.0;
  double cosT = std::sqrt(1.0 - sin2T);
  double rs = (cosTheta - eta * cosT) / (cosTheta + eta * cosT);
  double rp = (eta * cosTheta - cosT) / (eta * cosTheta + cosT);
  return 1.0 - 0.5 * (rs * rs + rp * rp);
}

Dipole::Dipole(const DipoleChannel& c) {
  double sigmaTPrime = c.sigmaA + c.sigmaSPrime;
  albedo_ = c.sigmaSPrime / sigmaTPrime;
  eta_ = c.eta;
  sigmaTr_ = std::sqrt(3.0 * c.sigmaA * sigmaTPrime);
  double fdr = fresnelDiffuseReflectance(c.eta);
  double A = (1.0 + fdr) / (1.0 - fdr);
  zr_ = 1.0 / sigmaTPrime;
  zv_ = zr_ * (1.0 + 4.0 * A / 3.0);
}

double Dipole::diffuseReflectance(double r) const {
  return dipoleReflectance(r * r, zr_, zv_, sigmaTr_, albedo_ / (4.0 * M_PI));
}

double Dipole::energyWithin(double r) const {
  double dr = std::sqrt(r * r + zr_ * zr_);
  double dv = std::sqrt(r * r + zv_ * zv_);
  return 0.5 * albedo_ *
         (std::exp(-sigmaTr_ * zr_) + std::exp(-sigmaTr_ * zv_) -
          zr_ * std::exp(-sigmaTr_ * dr) / dr - zv_ * std::exp(-sigmaTr_ * dv) / dv);
}

double Dipole::totalReflectance() const { return dipoleTotalReflectance(albedo_, eta_); }

double RadialProfile::radiusForEnergy(double fraction) const {
  double total = totalEnergy();
  if (!(total > 0.0)) return 0.0;
  double target = fraction * total;
  // energyWithin is monotone: bracket, then bisect.
  double hi = scaleHint() > 0.0 ? scaleHint() : 1.0;
  while (energyWithin(hi) < target && hi < 1e12) hi *= 2.0;
  double lo = 0.0;
  for (int i = 0; i < 200; ++i) {
    double mid = 0.5 * (lo + hi);
    (energyWithin(mid) < target ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace subsplat
