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
};

class ReferenceRenderer {
 public:
  // Profiles are summed out to the radius keeping this much of their energy.
  static constexpr double kSupportEnergy = 0.999;
  // A cell is cut while its diameter exceeds kRefineRatio x its distance to
  // x_o and kFinestCell x z_r, at most kMaxDepth times.
  static constexpr double kRefineRatio = 0.25;
  static constexpr double kFinestCell = 0.25;
  static constexpr int kMaxDepth = 12;

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
