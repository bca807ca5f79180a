#include "pipeline/precomputed_display.h"

#include <glm/gtc/type_ptr.hpp>

#include "pipeline/pass_helpers.h"
#include "util/error.h"

namespace subsplat {

void PrecomputedDisplay::resize(int width, int height) {
  if (!program_) program_ = gl::makeProgram("precomputed.vert", "", "precomputed.frag");
  if (width == width_ && height == height_) return;
  width_ = height_ = 0;
  framebuffer_.reset();
  exitance_.reset();
  depth_.reset();
  exitance_ = gl::makeTexture2D(GL_RGBA32F, width, height);
  depth_ = gl::makeTexture2D(GL_DEPTH_COMPONENT32F, width, height);
  framebuffer_ = gl::makeFramebuffer({exitance_.id()}, depth_.id());
  width_ = width;
  height_ = height;
}

void PrecomputedDisplay::draw(const PrecomputedTransport& transport, const Scene& scene, const SsCameraDesc& camera) {
  const auto& objects = transport.objects();
  if (objects_.size() != objects.size()) objects_.resize(objects.size());
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, width_, height_);
  // The passes before leave their state: additive blending (the direct light), culling (the exit
  // depth of TABULATED materials).
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  GLuint p = program_.id();
  glUseProgram(p);
  glm::mat4 viewProj = glm::make_mat4(camera.view_to_clip) * glm::make_mat4(camera.world_to_view);
  glUniformMatrix4fv(uniform(p, "viewProj"), 1, GL_FALSE, glm::value_ptr(viewProj));
  for (size_t o = 0; o < objects.size(); ++o) {
    const PrecomputedTransport::Object& object = objects[o];
    ObjectGpu& gpu = objects_[o];
    const Atlas& atlas = object.atlas;
    const Mesh* mesh = nullptr;
    for (const auto& [id, m] : scene.meshes())
      if (id == object.objectId) mesh = &m;
    if (mesh == nullptr) continue;
    gl::Purpose purpose("PRECOMPUTED's atlas of object " + std::to_string(object.objectId) + " (" +
                        std::to_string(atlas.width) + " x " + std::to_string(atlas.height) + " texels)");
    if (gpu.width != atlas.width || gpu.height != atlas.height || !gpu.local) {
      gpu.local = gl::makeTexture2D(GL_RGBA32F, atlas.width, atlas.height, GL_LINEAR);
      gpu.width = atlas.width, gpu.height = atlas.height;
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glBindTexture(GL_TEXTURE_2D, gpu.local.id());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, atlas.width, atlas.height, GL_RGBA, GL_FLOAT, object.local.data());
    // The corners: world position, atlas coordinate, the vertex's global response.
    std::vector<float> corners;
    const glm::mat4& toWorld = mesh->objectToWorld;
    for (uint32_t t = 0; t < mesh->triangleCount; ++t) {
      if (atlas.chartOfTriangle[t] < 0) continue;
      for (int k = 0; k < 3; ++k) {
        glm::vec3 w = glm::vec3(toWorld * glm::vec4(mesh->cpuPositions[mesh->cpuIndices[3 * size_t(t) + size_t(k)]], 1.0f));
        glm::vec2 uv = atlas.cornerTexel[3 * size_t(t) + size_t(k)] / glm::vec2(float(atlas.width), float(atlas.height));
        glm::vec4 b = object.vertexExitance[object.vertexOfCorner[3 * size_t(t) + size_t(k)]];
        corners.insert(corners.end(), {w.x, w.y, w.z, uv.x, uv.y, b.x, b.y, b.z, b.w});
      }
    }
    gpu.corners = corners.size() / 9;
    if (gpu.corners == 0) continue;
    gpu.vertices = gl::makeBuffer(GL_ARRAY_BUFFER, corners.size() * sizeof(float), corners.data(), GL_STREAM_DRAW);
    if (!gpu.array) gpu.array = gl::makeVertexArray();
    glBindVertexArray(gpu.array.id());
    glBindBuffer(GL_ARRAY_BUFFER, gpu.vertices.id());
    const GLsizei stride = 9 * sizeof(float);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(5 * sizeof(float)));
    bindTexture(gl::UNIT_EXITANCE_BUFFER, GL_TEXTURE_2D, gpu.local.id());
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(gpu.corners));
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
  }
  glDisable(GL_DEPTH_TEST);
  gl::checkErrors("PRECOMPUTED exitance");
}

}  // namespace subsplat
