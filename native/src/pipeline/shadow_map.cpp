#include "pipeline/shadow_map.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace subsplat {

void ShadowMap::resize(int resolution) {
  if (!program_) program_ = gl::makeProgram("mesh.vert", "", "shadow_depth.frag");
  if (resolution == resolution_) return;
  resolution_ = 0;  // as in IrradianceBuffer::resize
  framebuffer_ = gl::Framebuffer();
  lightDepth_.reset();
  depth_.reset();
  lightDepth_ = gl::makeTexture2D(GL_RG32F, resolution, resolution);
  depth_ = gl::makeTexture2D(GL_DEPTH_COMPONENT32F, resolution, resolution);
  framebuffer_ = gl::makeFramebuffer({lightDepth_.id()}, depth_.id());
  resolution_ = resolution;
}

void ShadowMap::render(const Scene& scene, const GpuScene& gpu, const LightView& view) {
  GLuint p = program_.id();
  beginMeshPass(framebuffer_.id(), resolution_, resolution_, {glm::vec4(1e30f, 0, 0, 0)}, p);
  setLightUniforms(p, view);
  drawMeshes(scene, gpu, p, view.viewProj);
  glDisable(GL_DEPTH_TEST);
}

int chooseShadowResolution(const Scene& scene, const std::vector<LightView>& views, const Bounds& all, int width,
                           int height, int irradiance, int maxTextureSize) {
  if (views.empty() || all.empty()) return irradiance;
  glm::vec3 centre = all.center();
  double texel = 0.0;  // the coarsest view's texel at the centre
  for (const LightView& view : views)
    texel = std::max(texel, double(view.light->type == SS_LIGHT_SUN
                                       ? view.shadowTexelSize
                                       : view.shadowTexelSize * glm::distance(glm::make_vec3(view.light->position), centre)));
  // The image's pixel at the centre: its height over the frame's (P11 scales view y to clip y).
  const SsCameraDesc& camera = scene.camera();
  double p11 = std::abs(double(camera.view_to_clip[5]));
  glm::vec4 inView = glm::make_mat4(camera.world_to_view) * glm::vec4(centre, 1.0f);
  double depth = camera.orthographic ? 1.0 : std::max(double(-inView.z), 1e-6);
  double pixel = p11 > 0.0 ? 2.0 * depth / (p11 * double(height)) : 0.0;
  (void)width;
  if (!(texel > 0.0) || !(pixel > 0.0)) return irradiance;
  double wanted = double(irradiance) * texel / pixel;
  int side = irradiance;
  while (side < wanted && side < kMaxAutomaticShadowResolution) side *= 2;
  return std::min(side, std::max(irradiance, maxTextureSize));
}

}  // namespace subsplat
