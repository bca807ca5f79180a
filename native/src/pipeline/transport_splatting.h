// MATERIAL_EDIT (Xu et al. 2007; docs/MATERIAL_EDIT.md): per pixel, the transport T_j of each
// spline of the edit basis (material/profile_basis.h), splatted once for a view, its lights and
// its meshes; an edit of a homogeneous material then projects the new profile onto the basis and
// sums c_j T_j per pixel instead of splatting again.
//
// The precomputation splats the samples FULL selects (splat.vert), with splat.geom's quads over
// the basis's reach (transport_splat.geom) in two draws per splatting level, one per group of nine
// splines (the near group reaches 0.07 R_P, the far group starts at 0.03 R_P), each into the eight RGBA32F
// layers of a level's array (transport_splat.frag). The levels are gathered as eq. 17 gathers
// FULL's (accumulate.frag). The combination (transport_combine.frag) is one pass over the pixels.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "gl/gl.h"
#include "material/profile_basis.h"
#include "pipeline/accumulation.h"
#include "pipeline/irradiance_buffer.h"
#include "pipeline/material_tables.h"
#include "pipeline/sample_selection.h"
#include "pipeline/splat_depth.h"
#include "pipeline/splatting_buffer.h"
#include "pipeline/stage_profiler.h"

namespace subsplat {

// What the combination reads per dense material entry (transport_combine.frag: EditCoefficients):
// the profile's coefficients c_j per channel (rgb, in 1 / R_P^2 of the precomputed material).
struct EditCoefficients {
  static constexpr int kSplines = 18;
  float spline[kSplines][4] = {};
};

class TransportSplatting {
 public:
  static constexpr int kGroups = 2, kLayers = 8;
  // How far the transport is splatted: kSupportGrowth times the precomputed material's support
  // (its kernel's SplatKernel::supportRadius), up to the basis's reach (kEditReach R_P). An edit
  // may lengthen the support that much and still recombine: sigma_s' x 0.5 lengthens the presets'
  // by 1.30-1.63x, Cream's by 1.68x and 2.00x (subsplat_basis; docs/MATERIAL_EDIT.md, "The precomputation"). The quads' area, and with it the
  // precomputation's cost, grows as its square.
  static constexpr float kSupportGrowth = 1.7f;
  // The basis (editBasis(kEditIntervals, kEditDegree)) and its splines' kernel tables.
  static const ProfileBasis& basis();

  // levels: splatting levels (FULL's).
  void resize(int width, int height, int levels);
  void clear();
  // Each level's depth from the splatting buffer (SplatDepth), after clear() and before splat().
  void prepareDepth(const Scene& scene, const SplattingBuffer& splatting) { depth_.prepare(scene, splatting); }
  // Adds the selected samples of one light view to every level (each its range of distances).
  void splat(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
             const SplattingBuffer& splatting, const KernelTables& kernels, const Selection& selection,
             StageProfiler& profiler);
  // The samples selected per irradiance level since clear(), added; their sum (Splatting's).
  uint64_t readSelectionCounts(uint64_t selectedPerLevel[8]);
  // Eq. 17 on every layer, coarse to fine.
  void accumulate(const Scene& scene, const SplattingBuffer& splatting, const Accumulation& weights,
                  StageProfiler& profiler);
  // The precomputed materials' incidence factors per pixel, at the means of what each pixel's light
  // met where it entered (after accumulate(), while those materials are the scene's).
  void storeFactors(const SplattingBuffer& splatting, GLuint transportTables);
  // sum_j c_j T_j per pixel, times the edited over the precomputed incidence factor, into
  // exitance() (rgb; alpha: the mean incidence cosine times the rgb sum, as FULL's exitance).
  // coefficients: one per dense material entry (opaque ones unread).
  void combine(const SplattingBuffer& splatting, const std::vector<EditCoefficients>& coefficients,
               GLuint transportTables);
  GLuint exitance() const { return exitance_.id(); }
  // Bytes of the transport's buffers (the levels' arrays and the exitance).
  uint64_t bytes() const { return bytes_; }

 private:
  int width_ = 0, height_ = 0;
  // transport_splat.frag with or without TABULATED materials.
  gl::ProgramVariants splatPrograms_{"splat.vert", "transport_splat.geom", "transport_splat.frag"};
  gl::Program accumulateProgram_, combineProgram_;
  gl::VertexArray empty_;
  gl::Texture basisKernels_;
  std::array<float, kGroups * 3> layerSupport_{};  // R_P units
  std::array<float, kGroups * 2> groupRange_{};
  float groupSplit_ = 0.0f;
  std::vector<std::array<gl::Texture, kGroups>> levels_;
  std::vector<std::array<gl::Framebuffer, kGroups>> framebuffers_;
  gl::Texture exitance_, factors_;
  gl::Framebuffer exitanceFramebuffer_, factorsFramebuffer_;
  // One pass of transport_combine.frag into `framebuffer`.
  void drawCombination(GLuint framebuffer, bool storeFactors, GLuint transportTables);
  gl::Buffer coefficients_;
  SelectionCounts counts_;
  SampleList samples_;
  SplatDepth depth_;  // attached to framebuffers_
  size_t coefficientCapacity_ = 0;
  uint64_t bytes_ = 0;
  void uploadBasis();
};

}  // namespace subsplat
