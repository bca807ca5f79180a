// Shading (paper sec. 4, eq. 7): the direct light of each light view, then
// the exitance through the surface (Fresnel) plus the direct light and the
// background, into the frame's image.
#pragma once

#include <vector>

#include "gl/gl.h"
#include "pipeline/irradiance_buffer.h"
#include "pipeline/light_views.h"
#include "pipeline/splatting_buffer.h"
#include "world_light.h"
#include "scene.h"

namespace subsplat {

// The environment drawn where no object is (material/texture.h: Environment), on the GPU.
struct EnvironmentInputs {
  GLuint texture = 0;  // 0: none (the background colour)
  glm::mat3 rotation{1.0f};
  float strength = 0.0f;
};

class Shading {
 public:
  void resize(int width, int height);
  void clear();
  // Direct light of one light view (diffuse, specular, shadows) and, for TABULATED materials, the
  // light it sends through thin parts (material/transport_model.h); transportTables:
  // MaterialTables::transport().
  // keptView >= 0 (after keepThrough): the light sent through thin parts is kept in that view's
  // layers, not added.
  void directLighting(const Scene& scene, const LightView& view, const ShadowInputs& shadow,
                      const SplattingBuffer& splatting, GLuint transportTables, int keptView = -1);
  // MATERIAL_EDIT (docs/MATERIAL_EDIT.md, "An edit"): the light each view sends through the thin
  // parts of TABULATED materials, kept per view and pixel as it is before the slab's transmission
  // (the entering light with the exit's factors, the thickness, the cosines: two RGBA32F layers a
  // view), so that an edit of their absorption evaluates it again without drawing a light view.
  // keepThrough makes (and zeroes) the layers of `views` views; false, keeping nothing, when they
  // would take more than kKeptThroughBytes. addKeptThrough then adds that light, for the materials
  // as they are now, to the direct light that finalShading reads (until clear()).
  static constexpr uint64_t kKeptThroughBytes = 256ull << 20;
  bool keepThrough(int views);
  void addKeptThrough(const SplattingBuffer& splatting, GLuint transportTables);
  // Eq. 7 (with the TABULATED model's exit factor) and the background (the environment where there
  // is one, else the colour) into `target` (RGBA32F, width x height).
  // world: the world's remainder (its two halves or harmonics) and whether it is drawn unshadowed
  // (world_light.h: RenderLights). Anti-aliasing: the frame's image is the samples' mean; each
  // sample adds `weight` times its own (weight 1: written alone), and `first` clears the target.
  void finalShading(const Scene& scene, const SplattingBuffer& splatting, GLuint exitance, GLuint transportTables,
                    const float background[4], const EnvironmentInputs& environment, const RenderLights& world,
                    float weight = 1.0f, bool first = true);
  GLuint resultFramebuffer() const { return resultFramebuffer_.id(); }

 private:
  int width_ = 0, height_ = 0;
  // direct_lighting.frag by a view's shadow filter and TABULATED materials; final_shading.frag by
  // the environment, TABULATED materials and the world's remainder (their defines: the shaders).
  gl::ProgramVariants directPrograms_{"fullscreen.vert", "", "direct_lighting.frag"};
  gl::ProgramVariants finalPrograms_{"fullscreen.vert", "", "final_shading.frag"};
  gl::Program throughProgram_;
  gl::VertexArray empty_;
  gl::Texture direct_, result_;
  gl::Framebuffer directFramebuffer_, resultFramebuffer_;
  // keepThrough's layers, a framebuffer per view (the direct light, then its two layers), and the
  // direct light with the kept light through added (addKeptThrough).
  gl::Texture through_, throughDirect_;
  std::vector<gl::Framebuffer> throughFramebuffers_;
  gl::Framebuffer throughDirectFramebuffer_;
  int throughViews_ = 0;
  bool readThroughDirect_ = false;
};

}  // namespace subsplat
