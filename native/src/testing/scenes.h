// Small scenes built through the C API, shared by native tests and tools.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "subsplat/subsplat.h"

namespace subsplat::testing {

struct Quad {
  std::vector<float> positions{-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  std::vector<float> normals{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  std::vector<float> uvs{0, 0, 1, 0, 1, 1, 0, 1};
  std::vector<uint32_t> indices{0, 1, 2, 0, 2, 3};
  SsMeshDesc desc(float halfSize, uint32_t material) const;
};

// An axis-aligned box from lo to hi (8 corners, flat normals, outward winding), no UVs.
struct Box {
  Box(const glm::vec3& lo, const glm::vec3& hi);
  std::vector<float> positions;
  std::vector<uint32_t> indices;
  SsMeshDesc desc(uint32_t material) const;
};

// A grey Lambertian opaque material (roughness 1, no specular).
SsMaterialDesc greyMaterial(float albedo);

// A UV sphere of unit radius with smooth normals; u runs around z, v from
// the -z pole (0) to the +z pole (1).
struct Sphere {
  explicit Sphere(int segments = 48, int rings = 24);
  std::vector<float> positions, normals, uvs;
  std::vector<uint32_t> indices;
  SsMeshDesc desc(const glm::vec3& centre, float radius, uint32_t material) const;
};

SsMaterialDesc marbleMaterial(float mmPerUnit);
SsMaterialDesc skinMaterial(float mmPerUnit);  // Skin1, Jensen et al. 2001
// `material` (id 0) on a slab of half-size 2 (the quad), seen from above over
// a square of half-size 0.5: the plane tests' scene. First failure, or SS_OK.
SsStatus setSlab(SsContext context, const Quad& quad, const SsMaterialDesc& material);
// `material` (id 0) on a sphere of radius 0.3, lit by a sun at 70 degrees and
// a point light behind it, seen from above: terminators, curvature and a
// thin rim. First failure, or SS_OK.
SsStatus setLitSphere(SsContext context, const Sphere& sphere, const SsMaterialDesc& material);

// Orthographic camera looking down -z at the origin from z = 5.
SsCameraDesc topDownCamera(float halfWidth);
SsLightDesc sunLight(float strength, float incidenceDegrees);

// The lines of `after` ("name=value" lines, as ssDescribeGlState writes) that differ from
// `before`, each as "before -> new value" ("" when none): the GL state tests' report.
std::string changedLines(const std::string& before, const std::string& after);

}  // namespace subsplat::testing

namespace subsplat::testing {

// Writes `ours`, `reference` (width x height RGBA, bottom row first) and a false-colour
// |ours - reference| / mean(reference) image (x10: 10 % is full red) as PNGs named
// <name>_ours.png, <name>_reference.png and <name>_difference.png into $SUBSPLAT_TEST_OUTPUT (else
// test_output/), for a person to look at when an image test fails. Returns the difference's path.
std::string writeComparison(const std::string& name, const std::vector<float>& ours,
                            const std::vector<float>& reference, int width, int height);

}  // namespace subsplat::testing
