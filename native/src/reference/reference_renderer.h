// REFERENCE: eq. 4/5 of the paper evaluated in object space on the CPU, the
// ground truth every accuracy figure is measured against (DESIGN.md, "Ground
// truth"; docs/ACCURACY.md).
//
//  1. Surface samples: every translucent triangle is cut into m x m congruent
//     cells (m from the requested sample count, by area); a sample sits at
//     each cell's centroid and carries the flux through the cell,
//     E(x_i) dA(x_i) = E_light |n_g . l| F_t(n_s . l) V dA, with visibility V
//     from a shadow ray to every light.
//  2. Exitance at each camera-ray hit x_o, B(x_o) = sum over the samples of the
//     same object within the profile's support of R_d(|x_o - x_i|) flux_i,
//     R_d(x_i, x_o) = sqrt(P_i P_o) (eq. 8). Near x_o a cell is cut into four
//     until it is small against both its distance and z_r, so the sum
//     integrates the profile's peak instead of point-sampling it.
//  3. Eq. 7 and the same direct lighting (opaque diffuse, GGX specular) as
//     the GPU shaders, with shadow rays.
// Nothing is random: the same scene and settings give the same image.
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <vector>

#include "scene.h"
#include "util/parallel.h"

namespace subsplat {

struct ReferenceOptions {
  uint64_t samples = 200000;      // over all translucent surfaces
  glm::vec4 background{0.0f};
  // Anti-aliasing: jittered camera rays per pixel, the sequence's first index, the filter's
  // width (SsSettings: samples, first_sample, filter_width).
  int pixelSamples = 1, firstSample = 0;
  float filterWidth = 1.5f;
  // The TABULATED model's forward shift (SsSettings::forward_shift; Entering::shift).
  bool forwardShift = true;
};

class RayScene;

// The light entering a translucent surface through a cell of it: E dA with every light's shadow
// rays, the Fresnel transmittance, the TABULATED model's incidence factor and the colour texture's
// tint (sqrt T), as REFERENCE's samples carry it (step 1 below).
struct Entering {
  glm::vec3 flux{0.0f};     // E dA, W
  glm::vec3 fluxMu0{0.0f};  // TABULATED: each light's flux times its incidence cosine, summed
  glm::vec3 normal{0.0f};   // the shading normal, facing the (first) light under TABULATED
  // TABULATED: per channel, where the entering light's reflection is centred, from the entry point
  // (scene units): each light's forward shift along its refracted beam (TransportTables::
  // beamCentroid), weighted by that light's flux in the channel.
  glm::vec3 shift[3]{};
};

// REFERENCE's entering light for other CPU methods (PRECOMPUTED's illumination map,
// precomputed/precomputed_transport.h): the same lights, shadows and factors.
class EnteringLight {
 public:
  // forwardShift: Entering::shift is computed (else left 0).
  EnteringLight(const Scene& scene, const RayScene& rays, bool forwardShift = false);
  ~EnteringLight();
  EnteringLight(const EnteringLight&) = delete;
  EnteringLight& operator=(const EnteringLight&) = delete;
  // Through a cell of `area` at p on triangle `triangle` of the ray scene's mesh `mesh`: ng its
  // geometric normal, ns the shading normal (both unit); `base` the triangle's material entry,
  // `point` the entry at p and pointUv its texture coordinate (for the tint).
  Entering at(uint32_t mesh, uint32_t triangle, const glm::vec3& p, const glm::vec3& ng, const glm::vec3& ns,
              float area, uint32_t base, uint32_t point, const glm::vec2& pointUv) const;

 private:
  struct Context;
  std::unique_ptr<Context> context_;
};

class ReferenceRenderer {
 public:
  // Profiles are summed out to the radius keeping this much of their energy.
  static constexpr double kSupportEnergy = 0.999;
  // A cell is cut while its diameter exceeds kRefineRatio x its distance to
  // x_o and kFinestCell x z_r, at most kMaxDepth times.
  static constexpr double kRefineRatio = 0.25;
  static constexpr double kFinestCell = 0.25;
  static constexpr int kMaxDepth = 24;  // 12 until stop 50: a 0.1-unit cell of a 40 m slab stopped at 0.6 mm, above marble's z_r

  // Renders into rgba (bottom row first) and keeps the exitance pass. Throws
  // Error(SS_CANCELLED) when progress returns false.
  void render(const Scene& scene, const ReferenceOptions& options, int width, int height,
              float* rgba, const ProgressFunction& progress, SsStats& stats);
  // rgb B(x_o), a 1 on translucent pixels; width x height, bottom row first.
  const std::vector<float>& exitance() const { return exitance_; }

 private:
  std::vector<float> exitance_;
};

}  // namespace subsplat
