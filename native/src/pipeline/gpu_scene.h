// The GPU's copy of the scene: each mesh's vertex and index buffers, uploaded
// when the mesh is set (so that a mesh beyond the memory budget fails there),
// and the dense material indices and profile maps of the last resolution.
#pragma once

#include <map>

#include "gl/gl.h"
#include "scene.h"

namespace subsplat {

struct GpuMesh {
  gl::VertexArray vertexArray;
  gl::Buffer positions, normals, uvs, indices, triangleMaterialBuffer;
  gl::Texture triangleMaterials;  // buffer texture of dense material indices
};

class GpuScene final : public MeshObserver {
 public:
  void meshSet(uint32_t objectId, const Mesh& mesh) override;
  void meshRemoved(uint32_t objectId) override;
  // Uploads the scene's dense material indices and profile maps where they
  // changed since the last call (after Scene::resolveMaterials).
  void update(const Scene& scene);

  const GpuMesh& mesh(uint32_t objectId) const { return meshes_.at(objectId); }
  // Scene::profileMaps() as an R16UI buffer texture.
  GLuint profileMaps() const { return profileMapTexture_.id(); }

 private:
  std::map<uint32_t, GpuMesh> meshes_;
  gl::Buffer profileMapBuffer_;
  gl::Texture profileMapTexture_;
  uint64_t uploadedResolution_ = ~0ull;
};

}  // namespace subsplat
