// The procedural scenes' profile radii, from the library's own profiles: the tools and tests that
// link its code compile this (native/CMakeLists.txt); subsplat_egl does not, as subsplat_replay
// links the shared library, whose internals are hidden.
#include <algorithm>

#include "material/transport_model.h"
#include "scene.h"
#include "testing/procedural.h"

namespace subsplat::testing {

double shortestRadius(const ProceduralScene& scene, double energy) {
  double shortest = 0.0;
  for (const SsMaterialDesc& m : scene.materials) {
    if (m.kind != SS_MATERIAL_DIPOLE) continue;
    DipoleMaterial medium = dipoleMaterial(m);
    for (int c = 0; c < 3; ++c) {
      double r = makeMediumProfile(medium.channels[size_t(c)], m.profile_model)->radiusForEnergy(energy) / m.mm_per_unit;
      if (r > 0.0) shortest = shortest > 0.0 ? std::min(shortest, r) : r;
    }
  }
  return shortest;
}

}  // namespace subsplat::testing
