// A radially symmetric diffuse reflectance profile P(r) of one colour channel:
// the dipole (material/dipole.h) or a SubEdit profile (material/profile_set.h).
// Lengths in millimetres, P in 1/mm^2.
#pragma once

namespace subsplat {

class RadialProfile {
 public:
  virtual ~RadialProfile() = default;
  // P(r).
  virtual double value(double r) const = 0;
  // The integral of P over the disk of radius r, 2 pi s ds.
  virtual double energyWithin(double r) const = 0;
  // The integral over the whole plane.
  virtual double totalEnergy() const = 0;
  // A length on the profile's scale, where the search of radiusForEnergy starts.
  virtual double scaleHint() const = 0;
  // Radius that keeps the given fraction of totalEnergy() (0 for an empty profile).
  double radiusForEnergy(double fraction) const;
};

}  // namespace subsplat
