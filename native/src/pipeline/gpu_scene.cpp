#include "pipeline/gpu_scene.h"

namespace subsplat {

void GpuScene::meshSet(uint32_t objectId, const Mesh& m) {
  uint32_t vertexCount = uint32_t(m.cpuPositions.size());
  gl::Purpose purpose("mesh " + std::to_string(objectId) + " (" + std::to_string(vertexCount) + " vertices, " +
                      std::to_string(m.triangleCount) + " triangles)");
  meshes_.erase(objectId);
  GpuMesh mesh;
  mesh.vertexArray = gl::makeVertexArray();
  glBindVertexArray(mesh.vertexArray.id());
  mesh.positions = gl::makeBuffer(GL_ARRAY_BUFFER, sizeof(float) * 3 * vertexCount, m.cpuPositions.data());
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  mesh.normals = gl::makeBuffer(GL_ARRAY_BUFFER, sizeof(glm::vec3) * vertexCount, m.cpuNormals.data());
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(1);
  if (m.hasUvs()) {
    mesh.uvs = gl::makeBuffer(GL_ARRAY_BUFFER, sizeof(glm::vec2) * vertexCount, m.cpuUvs.data());
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(2);
  }
  mesh.indices = gl::makeBuffer(GL_ELEMENT_ARRAY_BUFFER, sizeof(uint32_t) * 3 * m.triangleCount,
                                m.cpuIndices.data());
  glBindVertexArray(0);
  mesh.triangleMaterialBuffer =
      gl::makeBuffer(GL_TEXTURE_BUFFER, sizeof(uint32_t) * m.triangleCount, nullptr, GL_DYNAMIC_DRAW);
  mesh.triangleMaterials = gl::makeBufferTexture(GL_R32UI, mesh.triangleMaterialBuffer);
  gl::checkErrors("mesh upload");
  meshes_[objectId] = std::move(mesh);
  uploadedResolution_ = ~0ull;  // its material indices are not uploaded yet
}

void GpuScene::meshRemoved(uint32_t objectId) { meshes_.erase(objectId); }

void GpuScene::update(const Scene& scene) {
  if (uploadedResolution_ == scene.resolutionCount()) return;
  const std::vector<uint16_t>& maps = scene.profileMaps();
  profileMapBuffer_ = gl::makeBuffer(GL_TEXTURE_BUFFER, maps.size() * sizeof(uint16_t), maps.data());
  profileMapTexture_ = gl::makeBufferTexture(GL_R16UI, profileMapBuffer_);
  for (const auto& [objectId, m] : scene.meshes()) {
    const std::vector<uint32_t>& dense = m.denseMaterials;
    glBindBuffer(GL_TEXTURE_BUFFER, meshes_.at(objectId).triangleMaterialBuffer.id());
    glBufferSubData(GL_TEXTURE_BUFFER, 0, GLsizeiptr(dense.size() * sizeof(uint32_t)), dense.data());
  }
  gl::checkErrors("material resolution");
  uploadedResolution_ = scene.resolutionCount();
}

}  // namespace subsplat
