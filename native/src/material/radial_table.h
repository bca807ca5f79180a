#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "material/radial_profile.h"

namespace subsplat {

// Three channels' profiles P(r) and energy within a radius (RadialProfile::value, energyWithin),
// tabulated for PRECOMPUTED's inner loops: its near kernels ask for the energy twice per ray, its
// far kernels and vertex factors for P once per pair, and the dipole's cost two exponentials (P)
// and four (the energy) a channel. A cubic (Catmull-Rom) through knots uniform in
// u = (r / reach)^(1/4), shared by the channels (one lookup for the three) and dense at the
// profiles' peak; reach is kReachFactor times the longest channel's radius keeping all but
// kReachTail of its energy. Beyond reach the energy is the energy within reach and P is zero;
// within the first two knots (reach 1.5e-11) P is the profiles' own, which may be singular at 0.
// P is tabulated only where asked (values), for a smooth profile (the dipole); otherwise value()
// asks the profiles. TABULATED's P is power laws in log r, singular at 0 and cut at its table's
// end, which a cubic in u misses by up to 90 % (the test), and a SubEdit profile's is cut at its
// radius too; their own lookups are already tables. The table points at the profiles: they must
// outlive it. A channel without energy is zero.
class RadialTable {
 public:
  static constexpr int kKnots = 1024;
  static constexpr double kReachTail = 1e-6;
  static constexpr double kReachFactor = 2.0;

  RadialTable() = default;
  RadialTable(const std::array<const RadialProfile*, 3>& channels, bool values);

  glm::dvec3 energyWithin(double r) const {
    if (energy_.empty()) return glm::dvec3(0.0);
    const double u = knot(r);
    if (!(u < double(kKnots))) return energy_[kKnots + 1];
    return interpolate(energy_, u);
  }
  glm::dvec3 value(double r) const {
    if (energy_.empty()) return glm::dvec3(0.0);
    const double u = knot(r);
    if (!(u < double(kKnots))) return glm::dvec3(0.0);
    if (u < 2.0 || value_.empty()) return exactValue(r);
    return interpolate(value_, u);
  }
  // The radius beyond which the energy is constant and P zero (0 where no channel has energy).
  double reach() const { return energy_.empty() ? 0.0 : 1.0 / inverseReach_; }

 private:
  double knot(double r) const { return std::sqrt(std::sqrt(std::max(r, 0.0) * inverseReach_)) * kKnots; }
  static glm::dvec3 interpolate(const std::vector<glm::dvec3>& knots, double u) {
    const size_t i = size_t(u);
    const double t = u - double(i), t2 = t * t, t3 = t2 * t;
    const glm::dvec3* p = &knots[i];  // knots i - 1 .. i + 2 (knots[0] is knot -1)
    return 0.5 * ((2.0 * t2 - t - t3) * p[0] + (2.0 - 5.0 * t2 + 3.0 * t3) * p[1] +
                  (t + 4.0 * t2 - 3.0 * t3) * p[2] + (t3 - t2) * p[3]);
  }
  glm::dvec3 exactValue(double r) const;

  std::array<const RadialProfile*, 3> channels_{};
  std::vector<glm::dvec3> energy_, value_;  // knots -1 .. kKnots + 1
  double inverseReach_ = 0.0;
};

}  // namespace subsplat
