#include "pipeline/pass_helpers.h"

#include "material/transport_model.h"
#include "reference/lighting.h"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>

namespace subsplat {

GLint uniform(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

GLuint sceneVariant(gl::ProgramVariants& programs, const Scene& scene) {
  return programs.get({{"TEXTURES", scene.textured()}, {"PROFILE_MAPS", scene.heterogeneous()}});
}

void bindTexture(int unit, GLenum target, GLuint texture) {
  glActiveTexture(GLenum(GL_TEXTURE0 + unit));
  glBindTexture(target, texture);
  glBindSampler(GLuint(unit), 0);  // the texture's own filtering and wrapping, not the host's sampler
}

void setLightUniforms(GLuint program, const LightView& view) {
  const SsLightDesc& l = *view.light;
  float scale = l.type == SS_LIGHT_SUN ? 1.0f : 1.0f / (4.0f * float(M_PI));  // W -> W/sr
  glm::vec3 radiant = glm::make_vec3(l.color) * (l.strength * scale);
  std::vector<glm::vec3> corners;
  if (l.type == SS_LIGHT_AREA) {  // its radiance, and its corners
    radiant = glm::make_vec3(l.color) * areaRadiance(l);
    corners = areaCorners(l);
  }
  glUniform1i(uniform(program, "lightAreaCorners"), int(corners.size()));
  if (!corners.empty())
    glUniform3fv(uniform(program, "lightAreaPolygon"), GLsizei(corners.size()), glm::value_ptr(corners.front()));
  glm::vec3 direction = l.type == SS_LIGHT_POINT ? glm::vec3(0, 0, -1)
                                                 : glm::normalize(glm::make_vec3(l.direction));
  float cosHalf = std::cos(0.5f * l.spot_size);
  glUniformMatrix4fv(uniform(program, "lightViewProj"), 1, GL_FALSE, glm::value_ptr(view.viewProj));
  glUniform3fv(uniform(program, "lightPosition"), 1, l.position);
  glUniform3fv(uniform(program, "lightDirection"), 1, glm::value_ptr(direction));
  glUniform3fv(uniform(program, "lightRadiant"), 1, glm::value_ptr(radiant));
  glUniform1i(uniform(program, "lightType"), l.type);
  glUniform1f(uniform(program, "lightCosHalfSpot"), l.type == SS_LIGHT_SPOT ? cosHalf : -2.0f);
  glUniform1f(uniform(program, "lightSpotSmooth"), (1.0f - cosHalf) * l.spot_blend);
  int worldCount = view.worldDirections ? int(view.worldDirections->size()) : 0;
  glUniform1i(uniform(program, "worldDirectionCount"), worldCount);
  if (worldCount > 0)
    glUniform3fv(uniform(program, "worldDirections"), worldCount, glm::value_ptr(view.worldDirections->front()));
}

void setSoftShadowUniforms(GLuint program, const LightView& view) {
  glUniform1f(uniform(program, "shadowTexelSize"), view.shadowTexelSize);
  glUniform1f(uniform(program, "lightSoftSize"), view.softSize);
  glUniform1f(uniform(program, "lightNearDepth"), view.nearDepth);
  glUniform3fv(uniform(program, "lightSoftAxes"), 2, glm::value_ptr(view.softAxes[0]));
  glUniform1i(uniform(program, "lightSoftRectangle"), view.softRectangle ? 1 : 0);
}

void drawMeshes(const Scene& scene, const GpuScene& gpu, GLuint program, const glm::mat4& viewProj) {
  glUniformMatrix4fv(uniform(program, "viewProj"), 1, GL_FALSE, glm::value_ptr(viewProj));
  bindTexture(gl::UNIT_PROFILE_MAPS, GL_TEXTURE_BUFFER, gpu.profileMaps());
  for (const auto& [id, mesh] : scene.meshes()) {
    glm::mat3 normalToWorld = glm::transpose(glm::inverse(glm::mat3(mesh.objectToWorld)));
    glUniformMatrix4fv(uniform(program, "objectToWorld"), 1, GL_FALSE,
                       glm::value_ptr(mesh.objectToWorld));
    glUniformMatrix3fv(uniform(program, "normalToWorld"), 1, GL_FALSE, glm::value_ptr(normalToWorld));
    glUniform1f(uniform(program, "objectIndex"), float(mesh.index));
    glUniform1i(uniform(program, "meshHasUvs"), mesh.hasUvs() ? 1 : 0);
    const GpuMesh& buffers = gpu.mesh(id);
    bindTexture(gl::UNIT_TRIANGLE_MATERIALS, GL_TEXTURE_BUFFER, buffers.triangleMaterials.id());
    glBindVertexArray(buffers.vertexArray.id());
    glDrawElements(GL_TRIANGLES, GLsizei(3 * mesh.triangleCount), GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
}

void beginMeshPass(GLuint framebuffer, int width, int height, std::initializer_list<glm::vec4> clears, GLuint program) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width, height);
  int attachment = 0;
  for (const glm::vec4& value : clears) glClearBufferfv(GL_COLOR, attachment++, glm::value_ptr(value));
  glDepthMask(GL_TRUE);  // before the clear: a masked depth buffer is not cleared
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glUseProgram(program);
}

void setCameraUniforms(GLuint program, const SsCameraDesc& camera) {
  glm::vec3 position = cameraPosition(camera), forward = cameraForward(camera);
  glUniform3fv(uniform(program, "cameraPosition"), 1, glm::value_ptr(position));
  glUniform3fv(uniform(program, "cameraForward"), 1, glm::value_ptr(forward));
  glUniform1i(uniform(program, "orthographic"), camera.orthographic);
}

void setTransportUniforms(GLuint program, GLuint transportTables) {
  bindTexture(gl::UNIT_TRANSPORT_TABLES, GL_TEXTURE_2D_ARRAY, transportTables);
  glUniform3f(uniform(program, "transportGrid"), float(TransportTables::firstSlab()),
              float(TransportTables::thicknessLogStep()), float(TransportTables::thickestSlab()));
  glUniform1i(uniform(program, "transportThicknesses"), TransportTables::thicknessCount());
}

}  // namespace subsplat
