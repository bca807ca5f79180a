#include "material/radial_table.h"

namespace subsplat {

RadialTable::RadialTable(const std::array<const RadialProfile*, 3>& channels, bool values) {
  double reach = 0.0;
  for (const RadialProfile* p : channels)
    if (p && p->totalEnergy() > 0.0) reach = std::max(reach, kReachFactor * p->radiusForEnergy(1.0 - kReachTail));
  if (!(reach > 0.0) || !std::isfinite(reach)) return;
  inverseReach_ = 1.0 / reach;
  energy_.assign(kKnots + 3, glm::dvec3(0.0));
  if (values) value_.assign(kKnots + 3, glm::dvec3(0.0));
  for (int c = 0; c < 3; ++c) {
    const RadialProfile* p = channels[size_t(c)];
    if (!p || !(p->totalEnergy() > 0.0)) continue;
    channels_[size_t(c)] = p;
    for (int k = 1; k <= kKnots + 1; ++k) {
      const double u = double(std::min(k, kKnots)) / kKnots, r = reach * (u * u) * (u * u);
      energy_[size_t(k) + 1][c] = p->energyWithin(r);
      if (values) value_[size_t(k) + 1][c] = k <= kKnots ? p->value(r) : 0.0;  // zero beyond reach
    }
    energy_[1][c] = p->energyWithin(0.0);
  }
  energy_[0] = energy_[2];  // the energy is even in u: E(r) = E(reach u^4)
}

glm::dvec3 RadialTable::exactValue(double r) const {
  glm::dvec3 v(0.0);
  for (int c = 0; c < 3; ++c)
    if (channels_[size_t(c)]) v[c] = channels_[size_t(c)]->value(r);
  return v;
}

}  // namespace subsplat
