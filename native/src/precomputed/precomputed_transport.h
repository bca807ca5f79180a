// PRECOMPUTED (Lensch et al. 2002; docs/PRECOMPUTED.md): the transport of every translucent object
// precomputed once, per object, for a rigid mesh and its materials; each frame then relights it.
//
// Precomputation, per object:
//   - the atlas (precomputed/atlas.h) at a texel chosen from the mesh and the profiles
//     (choosePrecomputation), and the welded vertices with their areas A_i (a third of the
//     triangles around) and profiles;
//   - global response (only where the profile reaches past the local range): the vertex-to-vertex
//     factors F_ij for i != j (the diagonal is zero): the hats' mean of R_d for near pairs
//     (Galerkin), R_d between the vertices beyond, kept where F_ij A_j carries at least
//     kFactorThreshold of a unit flux (a sparse matrix by receiver);
//   - direct weights (Section 5.4): per source texel t, per channel, w_v(t) for the vertices of the
//     triangles its core part lies on, fitted by least squares so that the global response (F plus the direct part
//     D_v = sum_t w_v(t) Phi(t), both linearly interpolated) matches R_d on the receivers just
//     past the local range;
//   - local response: per receiving texel t, a kernel over the source texels s within the local
//     range in 3D (across charts), K(t <- s) = R_d(x_s, x_t) - (the global response at x_t to unit
//     flux at s): within the local range the sum is R_d, beyond it the global response alone.
// A frame: the flux Phi(t) = E dA of every texel (REFERENCE's entering light: shadow rays, Fresnel,
// the TABULATED incidence factor, the tint), its vertex shares Phi_i = sum_t beta_i(t) Phi(t) (beta_i(t):
// the hat of vertex i integrated over t's core part, over t's area),
// B_j = sum_i F_ij Phi_i + D_j at the vertices, and B_l(t) = sum_s K(t <- s) Phi(s) in the atlas;
// B(x) = B_l(x) + sum_j beta_j(x) B_j. Alpha carries the TABULATED model's exitance-weighted
// incidence cosine (the same operators applied to the flux times mu0, summed over the channels).
// R_d(x_i, x_o) = sqrt(P_i P_o) between different profiles (eq. 8 of Chen et al.); under TABULATED,
// times sideWeight(n_i . n_o) of the mesh's normals.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <memory>
#include <vector>

#include "precomputed/atlas.h"
#include "scene.h"
#include "util/parallel.h"

namespace subsplat {

class RayScene;

// The texel and kernel of one object (docs/PRECOMPUTED.md, "Sizes").
struct PrecomputationSize {
  float texel = 0.0f;  // world units
  int radius = 3;      // kernel half-width, texels: (2 radius + 1)^2 taps
  float localRange = 0.0f, edge = 0.0f, detail = 0.0f;  // what they were chosen from (world units)
};

class PrecomputedTransport {
 public:
  static constexpr int kMinRadius = 3, kMaxRadius = 10;
  // Memory: a kernel's tap (source index, rgb weight), a factor (its column and rgb), and an atlas
  // texel's own (its record, kernel start, outputs, direct weights, indices).
  static constexpr double kTapBytes = 16.0, kFactorBytes = 16.0, kTexelBytes = 96.0;
  static constexpr double kDetailTexel = 0.7;  // the texel, of the finest half-energy radius
  // ... and at most this share of the mean edge: the irradiance changes from facet to facet (each
  // its own normal), and a texel wider than a facet blurs that under a profile whose peak is
  // narrower (docs/PRECOMPUTED.md, "Sizes"; chosen on the calibration set).
  static constexpr double kEdgeTexel = 0.5;
  static constexpr double kFactorThreshold = 1e-6;
  static constexpr double kLocalEdges = 4.0;  // the local response reaches this many mean edges
  // The most kernel taps of an object (64 MiB of them) whose texel is finer than kMaxRadius
  // allows: a small object under a long profile (choosePrecomputation).
  static constexpr double kSmallObjectTaps = 4.0e6;
  // The kernels' and factors' memory, all objects together, unless the caller's budget is lower.
  static constexpr size_t kDefaultBytes = size_t(512) << 20;

  PrecomputedTransport();
  ~PrecomputedTransport();
  PrecomputedTransport(const PrecomputedTransport&) = delete;
  PrecomputedTransport& operator=(const PrecomputedTransport&) = delete;
  // Whether the precomputation is for this scene's meshes and materials, and its atlases were made
  // with (ownUvs) or without the meshes' UV maps (lights, camera, other settings, textures and
  // opaque meshes may differ, and a translucent object may have moved rigidly).
  bool serves(const Scene& scene, bool ownUvs = true) const;
  // Whether `to` is `from` turned and moved, not scaled, sheared or mirrored (within 1e-5).
  static bool rigidMove(const glm::mat4& from, const glm::mat4& to);
  // Precomputes for every translucent object of `scene` (materials resolved) within `maxBytes`;
  // ownUvs: each mesh's UV map's islands that fit are charts of its atlas (buildAtlas).
  void precompute(const Scene& scene, size_t maxBytes, const ProgressFunction& progress, bool ownUvs = true);
  // One frame under the scene's lights; forwardShift: the TABULATED model's (SsSettings::
  // forward_shift), each texel's flux moved in the atlas by its light's shift.
  void relight(const Scene& scene, const ProgressFunction& progress, bool forwardShift = false);
  void clear();

  struct Object {
    uint32_t objectId = 0;
    int rayMesh = 0;  // index into the RayScene's meshes
    PrecomputationSize size;
    Atlas atlas;
    std::vector<uint32_t> active;   // texels with a point (not kEmpty)
    std::vector<int32_t> activeOf;  // texel -> index into active, or -1
    // Per receiving active texel: its sources (active indices of core texels) and their weights.
    std::vector<uint32_t> kernelStart, kernelSource;
    std::vector<glm::vec3> kernelWeight;
    int vertices = 0;
    std::vector<uint32_t> vertexOfCorner;  // 3 per triangle; ~0u outside the atlas
    std::vector<glm::vec3> vertexPositions;
    std::vector<uint32_t> rowStart, column;  // F by receiving vertex: sources, ascending
    std::vector<glm::vec3> factor;
    // Per active texel, the vertices its flux goes to (the hats over its core part, Atlas::parts):
    // sourceVertex[sourceStart[a]] .. [sourceStart[a + 1]], with the hats' shares beta_i(t) and the
    // direct weights w_i(t).
    std::vector<uint32_t> sourceStart, sourceVertex;
    std::vector<float> sourceBeta;
    std::vector<glm::vec3> direct;
    size_t factors() const { return column.size(); }
    double precomputeMs = 0.0;  // wall time of this object's precomputation
    size_t bytes() const;
    // The last frame's: B_l per texel (rgb, alpha), B per vertex.
    std::vector<glm::vec4> local, vertexExitance;
  };
  const std::vector<Object>& objects() const { return objects_; }
  size_t bytes() const;

 private:
  std::vector<Object> objects_;
  bool valid_ = false;
  bool ownUvs_ = true;
  uint64_t meshHash_ = 0;
  std::vector<double> materialSignature_;
  std::vector<glm::mat4> transforms_;  // the translucent meshes' at the precomputation
  std::unique_ptr<RayScene> rays_;
  std::vector<const void*> rayIdentity_;  // the meshes the RayScene points into
  static uint64_t hashMeshes(const Scene& scene);
  static std::vector<glm::mat4> transforms(const Scene& scene);
  static std::vector<double> signature(const Scene& scene);
  static std::vector<const void*> identity(const Scene& scene);
};

// The texel and kernel size of an object of surface `area` (world units^2) with mean edge
// `edge`, profiles reaching `support` whose finest half-energy radius is `detail` (world units),
// within maxTexels texels of kernels of at most kMaxRadius.
PrecomputationSize choosePrecomputation(double area, double edge, double support, double detail, size_t maxBytes);

}  // namespace subsplat
