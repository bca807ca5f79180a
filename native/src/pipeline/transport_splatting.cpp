#include "pipeline/transport_splatting.h"

#include <algorithm>

#include "material/splat_kernel.h"
#include "util/error.h"

namespace subsplat {

namespace {

constexpr int kSplinesPerGroup = 9;
// A level's splines vary slowly enough to be summed at its resolution where every knot gap is at
// least this many of its pixels (transport_splat.geom): a quadratic spline spans three gaps, a dozen
// pixels. On the calibration scenes 8 and 16 changed no error by more than noise and cost more
// (docs/MATERIAL_EDIT.md, "The precomputation").
constexpr float kKnotPixels = 4.0f;

}  // namespace

const ProfileBasis& TransportSplatting::basis() {
  const ProfileBasis& b = editBasis(kEditIntervals, kEditDegree);
  if (b.size() != EditCoefficients::kSplines)
    fail(SS_INTERNAL_ERROR, "the edit basis has " + std::to_string(b.size()) + " splines, not " +
                                std::to_string(EditCoefficients::kSplines));
  return b;
}

namespace {

// The basis's kernel tables, built once a process (about a second): three splines a layer, each
// kept whole to the last one's end (no cut at a share of the energy).
struct BasisTables {
  std::vector<float> texels;
  std::array<float, TransportSplatting::kGroups * 3> layerSupport{};
};

const BasisTables& basisTables() {
  static const BasisTables tables = [] {
    const ProfileBasis& b = TransportSplatting::basis();
    BasisTables t;
    for (int layer = 0; layer < TransportSplatting::kGroups * 3; ++layer) {
      SplatKernel::Channels channels;
      for (int s = 0; s < 3; ++s) channels[size_t(s)] = std::make_shared<BasisFunction>(b, 3 * layer + s);
      double support = b.supportEnd(3 * layer + 2);
      SplatKernel kernel(channels, 1.0, support);
      t.layerSupport[size_t(layer)] = float(support);
      t.texels.insert(t.texels.end(), kernel.table().begin(), kernel.table().end());
    }
    return t;
  }();
  return tables;
}

}  // namespace

void TransportSplatting::uploadBasis() {
  const ProfileBasis& b = basis();
  const BasisTables& tables = basisTables();
  const std::vector<float>& texels = tables.texels;
  layerSupport_ = tables.layerSupport;
  for (int g = 0; g < kGroups; ++g) {
    groupRange_[size_t(2 * g)] = float(b.supportStart(kSplinesPerGroup * g));
    groupRange_[size_t(2 * g + 1)] = float(b.supportEnd(kSplinesPerGroup * g + kSplinesPerGroup - 1));
  }
  groupSplit_ = groupRange_[2];  // the far group's first distance
  gl::Purpose purpose("the edit basis's kernel tables");
  basisKernels_ = gl::makeTexture2DArray(GL_RGBA32F, SplatKernel::kSizeD, SplatKernel::kSizeA, kGroups * 3, GL_LINEAR);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
  glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, 0, SplatKernel::kSizeD, SplatKernel::kSizeA, kGroups * 3, GL_RGBA,
                  GL_FLOAT, texels.data());
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl::checkErrors("edit basis upload");
}

void TransportSplatting::resize(int width, int height, int levels) {
  if (!accumulateProgram_) {
    accumulateProgram_ = gl::makeProgram("fullscreen.vert", "", "accumulate.frag");
    combineProgram_ = gl::makeProgram("fullscreen.vert", "", "transport_combine.frag");
    empty_ = gl::makeVertexArray();
  }
  if (!basisKernels_) uploadBasis();
  if (width == width_ && height == height_ && size_t(levels) == levels_.size()) return;
  width_ = height_ = 0;
  levels_.clear();
  framebuffers_.clear();
  exitanceFramebuffer_ = gl::Framebuffer();
  exitance_ = gl::Texture();
  factorsFramebuffer_ = gl::Framebuffer();
  factors_ = gl::Texture();
  bytes_ = 0;
  depth_.resize(width, height, levels);
  for (int k = 0; k < levels; ++k) {
    int w = std::max(width >> k, 1), h = std::max(height >> k, 1);
    std::array<gl::Texture, kGroups> textures;
    std::array<gl::Framebuffer, kGroups> framebuffers;
    for (int g = 0; g < kGroups; ++g) {
      textures[size_t(g)] = gl::makeTexture2DArray(GL_RGBA32F, w, h, kLayers);
      framebuffers[size_t(g)] = gl::makeLayeredFramebuffer(textures[size_t(g)].id(), kLayers, depth_.texture(k));
      bytes_ += uint64_t(w) * uint64_t(h) * kLayers * 16u;
    }
    bytes_ += uint64_t(w) * uint64_t(h) * 4u;  // depth_
    levels_.push_back(std::move(textures));
    framebuffers_.push_back(std::move(framebuffers));
  }
  exitance_ = gl::makeTexture2D(GL_RGBA32F, width, height);
  exitanceFramebuffer_ = gl::makeFramebuffer({exitance_.id()}, 0);
  factors_ = gl::makeTexture2D(GL_RGBA32F, width, height);
  factorsFramebuffer_ = gl::makeFramebuffer({factors_.id()}, 0);
  bytes_ += uint64_t(width) * uint64_t(height) * 32u;
  width_ = width;
  height_ = height;
}

void TransportSplatting::clear() {
  const float zero[4] = {0, 0, 0, 0};
  for (const auto& level : framebuffers_)
    for (const gl::Framebuffer& f : level) {
      glBindFramebuffer(GL_FRAMEBUFFER, f.id());
      for (int l = 0; l < kLayers; ++l) glClearBufferfv(GL_COLOR, l, zero);
    }
  depth_.clear();
  counts_.clear();
}

uint64_t TransportSplatting::readSelectionCounts(uint64_t selectedPerLevel[8]) {
  return counts_.read(selectedPerLevel);
}

void TransportSplatting::splat(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
                               const SplattingBuffer& splatting, const KernelTables& kernels,
                               const Selection& selection, StageProfiler& profiler) {
  const ProfileBasis& b = basis();
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  profiler.begin(SS_STAGE_SPLATTING, StageProfiler::kSelection);
  samples_.build(scene, view, irradiance, splatting, selection, &counts_);  // counts_: zeroed by clear()
  profiler.end();
  GLuint p = splatPrograms_.get({{"TRANSMISSION", scene.tabulated()}});
  glUseProgram(p);
  GLint offsets[9];
  setSelectionUniforms(p, scene, view, irradiance, splatting, selection, offsets);
  samples_.bind();
  glUniform1i(uniform(p, "slabGeometries"), 1);
  bindTexture(gl::UNIT_IRRADIANCE_LIGHT_DEPTH, GL_TEXTURE_2D, irradiance.lightDepth());
  if (irradiance.exitDepth()) bindTexture(gl::UNIT_IRRADIANCE_EXIT_DEPTH, GL_TEXTURE_2D, irradiance.exitDepth());
  glUniform2f(uniform(p, "kernelLog2Range"), float(SplatKernel::kMinLog2), float(SplatKernel::kMaxLog2));
  glUniform1f(uniform(p, "footprintReach"), float(SplatKernel::kFootprintReach));
  glUniform2f(uniform(p, "kernelTableSize"), float(SplatKernel::kSizeD), float(SplatKernel::kSizeA));
  std::vector<float> knots(b.knots().begin(), b.knots().end());
  glUniform1i(uniform(p, "knotCount"), GLint(knots.size()));
  glUniform1fv(uniform(p, "knots"), GLsizei(knots.size()), knots.data());
  glUniform1f(uniform(p, "knotPixels"), kKnotPixels);
  glUniform1f(uniform(p, "supportGrowth"), kSupportGrowth);
  glUniform1f(uniform(p, "groupSplit"), groupSplit_);
  int splatLevels = int(levels_.size());
  GLfloat heights[8] = {};
  for (int k = 0; k < splatLevels; ++k) heights[k] = float(std::max(height_ >> k, 1));
  glUniform1i(uniform(p, "splatLevels"), splatLevels);
  glUniform1fv(uniform(p, "levelHeight"), 8, heights);
  bindTexture(gl::UNIT_SPLAT_KERNELS, GL_TEXTURE_2D_ARRAY, kernels.kernels);
  bindTexture(gl::UNIT_BASIS_KERNELS, GL_TEXTURE_2D_ARRAY, basisKernels_.id());
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  glUniform1f(uniform(p, "depthFar"), depth_.far());
  SplatDepth::beginTest();  // pixels whose surface lies beyond a quad's reach (prepareDepth)
  glBindVertexArray(empty_.id());
  for (int k = 0; k < splatLevels; ++k) {
    glViewport(0, 0, std::max(width_ >> k, 1), std::max(height_ >> k, 1));
    glUniform1i(uniform(p, "splatLevel"), k);
    glUniform2f(uniform(p, "viewportSize"), float(std::max(width_ >> k, 1)), float(std::max(height_ >> k, 1)));
    profiler.begin(SS_STAGE_SPLATTING, k);
    for (int g = 0; g < kGroups; ++g) {
      glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[size_t(k)][size_t(g)].id());
      glUniform1i(uniform(p, "group"), g);
      glUniform1fv(uniform(p, "layerSupport"), 3, &layerSupport_[size_t(3 * g)]);
      glUniform2f(uniform(p, "groupRange"), groupRange_[size_t(2 * g)], groupRange_[size_t(2 * g + 1)]);
      samples_.draw();
    }
    profiler.end();
  }
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  SplatDepth::endTest();
  gl::checkErrors("transport splatting");
}

void TransportSplatting::accumulate(const Scene& scene, const SplattingBuffer& splatting, const Accumulation& weights,
                                    StageProfiler& profiler) {
  int levels = int(levels_.size());
  if (levels <= 1) return;
  profiler.begin(SS_STAGE_SPLATTING, StageProfiler::kAccumulation);
  GLuint p = accumulateProgram_.id();
  beginAccumulation(p, scene, splatting, weights, kLayers);
  glBindVertexArray(empty_.id());
  for (int g = 0; g < kGroups; ++g)
    for (int k = levels - 2; k >= 0; --k) {
      glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[size_t(k)][size_t(g)].id());
      glViewport(0, 0, std::max(width_ >> k, 1), std::max(height_ >> k, 1));
      bindTexture(gl::UNIT_COARSE_TRANSPORT, GL_TEXTURE_2D_ARRAY, levels_[size_t(k + 1)][size_t(g)].id());
      glUniform1i(uniform(p, "fineLevel"), k);
      glUniform2i(uniform(p, "coarseSize"), std::max(width_ >> (k + 1), 1), std::max(height_ >> (k + 1), 1));
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  profiler.end();
  gl::checkErrors("transport accumulation");
}

void TransportSplatting::storeFactors(const SplattingBuffer& splatting, GLuint transportTables) {
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  drawCombination(factorsFramebuffer_.id(), true, transportTables);
}

void TransportSplatting::combine(const SplattingBuffer& splatting, const std::vector<EditCoefficients>& coefficients,
                                 GLuint transportTables) {
  size_t bytes = std::max<size_t>(coefficients.size(), 1) * sizeof(EditCoefficients);
  if (bytes > coefficientCapacity_) {
    coefficients_ = gl::makeBuffer(GL_SHADER_STORAGE_BUFFER, bytes, nullptr, GL_DYNAMIC_DRAW);
    coefficientCapacity_ = bytes;
  }
  if (!coefficients.empty()) {
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, coefficients_.id());
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, coefficients.size() * sizeof(EditCoefficients), coefficients.data());
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_EDIT_COEFFICIENTS, coefficients_.id());
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  bindTexture(gl::UNIT_EDIT_FACTORS, GL_TEXTURE_2D, factors_.id());
  drawCombination(exitanceFramebuffer_.id(), false, transportTables);
}

void TransportSplatting::drawCombination(GLuint framebuffer, bool storeFactors, GLuint transportTables) {
  GLuint p = combineProgram_.id();
  glUseProgram(p);
  glUniform1i(uniform(p, "storeFactors"), storeFactors ? 1 : 0);
  setTransportUniforms(p, transportTables);
  bindTexture(gl::UNIT_NEAR_TRANSPORT, GL_TEXTURE_2D_ARRAY, levels_.at(0)[0].id());
  bindTexture(gl::UNIT_FAR_TRANSPORT, GL_TEXTURE_2D_ARRAY, levels_.at(0)[1].id());
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width_, height_);
  glDisable(GL_BLEND);
  glBindVertexArray(empty_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  gl::checkErrors("transport combination");
}

}  // namespace subsplat
