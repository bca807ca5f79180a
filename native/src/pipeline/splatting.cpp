#include "pipeline/splatting.h"

#include <glm/gtc/type_ptr.hpp>

#include "material/splat_kernel.h"

namespace subsplat {

void Splatting::resize(int width, int height) {
  if (!program_) {
    program_ = gl::makeProgram("splat.vert", "splat.geom", "splat.frag");
    empty_ = gl::makeVertexArray();
  }
  if (width == width_ && height == height_) return;
  exitance_ = gl::makeTexture2D(GL_RGBA32F, width, height);
  framebuffer_ = gl::makeFramebuffer({exitance_.id()}, 0);
  width_ = width;
  height_ = height;
}

void Splatting::clear() {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
}

uint64_t Splatting::splatLevel(const Scene& scene, const IrradianceBuffer& irradiance,
                           const SplattingBuffer& splatting, GLuint kernelTable) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, width_, height_);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  GLuint p = program_.id();
  glUseProgram(p);
  int res = irradiance.resolution();
  glUniform1i(uniform(p, "resolution"), res);
  glUniformMatrix4fv(uniform(p, "worldToView"), 1, GL_FALSE, scene.camera().world_to_view);
  glUniformMatrix4fv(uniform(p, "viewToClip"), 1, GL_FALSE, scene.camera().view_to_clip);
  glUniform2f(uniform(p, "kernelLog2Range"), float(SplatKernel::kMinLog2), float(SplatKernel::kMaxLog2));
  glUniform1f(uniform(p, "footprintReach"), float(SplatKernel::kFootprintReach));
  glUniform2f(uniform(p, "kernelTableSize"), float(SplatKernel::kSizeD), float(SplatKernel::kSizeA));
  bindTexture(0, GL_TEXTURE_2D, irradiance.positionMaterial(), p, "irradiancePositionMaterial");
  bindTexture(1, GL_TEXTURE_2D, irradiance.fluxFootprint(), p, "irradianceFluxFootprint");
  bindTexture(2, GL_TEXTURE_2D, irradiance.normalObject(), p, "irradianceNormalObject");
  bindTexture(3, GL_TEXTURE_2D, splatting.positionObject(), p, "splattingPositionObject");
  bindTexture(4, GL_TEXTURE_2D_ARRAY, kernelTable, p, "splatKernels");
  glBindVertexArray(empty_.id());
  GLuint query = 0;
  glGenQueries(1, &query);
  gl::Query splats(query);
  glBeginQuery(GL_PRIMITIVES_GENERATED, query);
  glDrawArrays(GL_POINTS, 0, res * res);
  glEndQuery(GL_PRIMITIVES_GENERATED);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  GLuint64 emitted = 0;
  glGetQueryObjectui64v(query, GL_QUERY_RESULT, &emitted);
  return emitted;
}

void Shading::resize(int width, int height) {
  if (!directProgram_) {
    directProgram_ = gl::makeProgram("fullscreen.vert", "", "direct_lighting.frag");
    finalProgram_ = gl::makeProgram("fullscreen.vert", "", "final_shading.frag");
    empty_ = gl::makeVertexArray();
  }
  if (width == width_ && height == height_) return;
  direct_ = gl::makeTexture2D(GL_RGBA32F, width, height);
  result_ = gl::makeTexture2D(GL_RGBA32F, width, height);
  directFramebuffer_ = gl::makeFramebuffer({direct_.id()}, 0);
  resultFramebuffer_ = gl::makeFramebuffer({result_.id()}, 0);
  width_ = width;
  height_ = height;
}

void Shading::clear() {
  glBindFramebuffer(GL_FRAMEBUFFER, directFramebuffer_.id());
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
}

void Shading::directLighting(const Scene& scene, const LightView& view,
                             const IrradianceBuffer& irradiance, const SplattingBuffer& splatting) {
  glBindFramebuffer(GL_FRAMEBUFFER, directFramebuffer_.id());
  glViewport(0, 0, width_, height_);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  GLuint p = directProgram_.id();
  glUseProgram(p);
  setLightUniforms(p, view);
  setCameraUniforms(p, scene.camera());
  glUniform1i(uniform(p, "resolution"), irradiance.resolution());
  glUniform1f(uniform(p, "shadowTexelSize"), view.shadowTexelSize);
  glUniform1i(uniform(p, "unshadowedOutside"), view.unshadowedOutside ? 1 : 0);
  bindTexture(0, GL_TEXTURE_2D, splatting.positionObject(), p, "splattingPositionObject");
  bindTexture(1, GL_TEXTURE_2D, splatting.normalMaterial(), p, "splattingNormalMaterial");
  bindTexture(2, GL_TEXTURE_2D, irradiance.lightDepth(), p, "irradianceLightDepth");
  glBindVertexArray(empty_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
}

void Shading::finalShading(const Scene& scene, const SplattingBuffer& splatting, GLuint exitance,
                           const float background[4]) {
  glBindFramebuffer(GL_FRAMEBUFFER, resultFramebuffer_.id());
  glViewport(0, 0, width_, height_);
  GLuint p = finalProgram_.id();
  glUseProgram(p);
  setCameraUniforms(p, scene.camera());
  glUniform4fv(uniform(p, "background"), 1, background);
  bindTexture(0, GL_TEXTURE_2D, splatting.positionObject(), p, "splattingPositionObject");
  bindTexture(1, GL_TEXTURE_2D, splatting.normalMaterial(), p, "splattingNormalMaterial");
  bindTexture(2, GL_TEXTURE_2D, exitance, p, "exitanceBuffer");
  bindTexture(3, GL_TEXTURE_2D, direct_.id(), p, "directRadiance");
  glBindVertexArray(empty_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

}  // namespace subsplat
