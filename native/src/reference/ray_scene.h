// The scene's triangles in world space, for rays (Embree 3).
#pragma once

#include <glm/glm.hpp>

#include <embree3/rtcore.h>

#include <vector>

namespace subsplat {

class Scene;
struct Mesh;

// One mesh in world space: what rays hit and samples are taken from.
struct WorldMesh {
  const Mesh* mesh = nullptr;
  int object = 0;  // Mesh::index
  std::vector<glm::vec3> positions, normals;  // world space
  const std::vector<uint32_t>* indices = nullptr;
  const std::vector<uint32_t>* materials = nullptr;  // dense, per triangle

  glm::uvec3 triangle(uint32_t t) const {
    const uint32_t* i = indices->data() + 3 * size_t(t);
    return {i[0], i[1], i[2]};
  }
};

struct Hit {
  int mesh = -1;  // index into RayScene::meshes()
  uint32_t triangle = 0;
  float u = 0, v = 0, distance = 0;
  bool valid() const { return mesh >= 0; }
};

class RayScene {
 public:
  explicit RayScene(const Scene& scene);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  const std::vector<WorldMesh>& meshes() const { return meshes_; }
  // Nearest hit along origin + t direction, t in (tNear, tFar).
  Hit intersect(const glm::vec3& origin, const glm::vec3& direction, float tNear, float tFar) const;
  // Whether anything lies along the segment (tNear, tFar).
  bool occluded(const glm::vec3& origin, const glm::vec3& direction, float tNear, float tFar) const;
  // A distance that separates a point from its own surface: scales with the scene.
  float epsilon() const { return epsilon_; }

 private:
  std::vector<WorldMesh> meshes_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  float epsilon_ = 1e-5f;
};

}  // namespace subsplat
