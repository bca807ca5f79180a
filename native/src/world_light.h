// The world light (SS_LIGHT_WORLD, docs/WORLD.md): radiance L from every direction (uniform, two
// halves, or spherical harmonics to order 2), as the renderers draw it. Either K shadowed directions w_k, each drawn as a sun whose irradiance on a
// surface of normal n is
//
//     E_k(n) = L pi max(0, n . w_k) / D(n),   D(n) = sum_j max(0, n . w_j),
//
// so that a surface that sees every direction gets exactly L pi (the hemisphere's irradiance),
// and one that sees some of them the cosine-weighted share it sees; or none, and the world lights
// every surface unshadowed (the remainder). The world's specular reflection is the remainder's in
// both cases (a glossy surface would otherwise show K highlights): L times the GGX lobe's
// directional albedo (Karis 2014's fit).
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <vector>

#include "scene.h"

namespace subsplat {

constexpr int kMaxWorldDirections = 64;

// What the renderers draw for the scene's lights: every light but the world as given, then the
// world's shadowed directions (suns of radiance L above the horizon or below it, flagged `world`),
// and the unshadowed remainder.
struct RenderLights {
  std::vector<SsLightDesc> lights;
  std::vector<bool> world;                 // per light: one of the world's directions
  std::vector<glm::vec3> worldDirections;  // towards the world, unit (K)
  glm::vec3 worldRadiance{0.0f};           // L above the horizon, for the specular remainder
  glm::vec3 worldBelow{0.0f};              // L below it
  bool unshadowed = false;                 // the world is drawn unshadowed (the remainder's diffuse too)
  // A world given as spherical harmonics (SsLightDesc.world_sh): its irradiance over pi, E(n) / pi,
  // as 9 RGB coefficients of the same basis (the radiance's times A_l / pi: 1, 2/3, 1/4).
  bool worldHarmonics = false;
  std::array<glm::vec3, 9> worldIrradiance{};
};

// The real spherical harmonics to order 2 at a unit direction (SsLightDesc.world_sh's basis).
std::array<float, 9> sphericalHarmonics(const glm::vec3& d);
// The world's remainder for a direction d: E(n = d) / pi, the irradiance over pi of a surface
// facing d under the whole world: from the harmonics when given, else worldHemisphereMix.
glm::vec3 worldRemainder(const RenderLights& lights, const glm::vec3& d);

// The world's remainder for a direction of z component z: its radiance above the horizon and below
// mixed by the share of the hemisphere around that direction that is above it, (1 + z) / 2: the
// exact irradiance over pi for a surface of normal z under a world of two halves.
glm::vec3 worldHemisphereMix(const glm::vec3& above, const glm::vec3& below, float z);

// K points spread evenly over the unit sphere (a spherical Fibonacci lattice), deterministic.
std::vector<glm::vec3> worldDirections(int count);
// The shadowed directions SS_LIGHT_WORLD's world_directions = 0 chooses: the world's share of the
// irradiance at the centre of `fit` (pi L against every other light there, unshadowed, by
// luminance): below 10 %, none; below 50 %, 8; else 16 (docs/WORLD.md).
int automaticWorldDirections(const std::vector<SsLightDesc>& lights, const Bounds& fit);
RenderLights renderLights(const Scene& scene);

// pi / D(n): E_k(n) over the sun's L max(0, n . w_k).
float worldWeight(const std::vector<glm::vec3>& directions, const glm::vec3& n);
// The GGX lobe's directional albedo (direct_lighting.frag's specular under a uniform world).
float specularAlbedo(float roughness, float specular, float cosView);
// A translucent entry under the unshadowed world, per unit radiance: the exit radiance is
// L * response * F_t(mu), times, for TABULATED, the half-space's 1 - sqrt(1 - a) H(mu) (exact for
// eta = 1). response: the mean Fresnel transmittance over a cosine-weighted hemisphere times the
// profile's total (DIPOLE, SUBEDIT) or times the total over R(1) (TABULATED: the boundary
// factor); 0 for opaque entries.
glm::vec3 unshadowedResponse(const MaterialEntry& entry);
// The mean Fresnel transmittance 2 int_0^1 F_t(mu) mu dmu.
double diffuseTransmittance(double eta);

}  // namespace subsplat
