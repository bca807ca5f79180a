#include "reference/ray_scene.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "scene.h"
#include "util/error.h"

namespace subsplat {

namespace {

void checkDevice(RTCDevice device, const char* what) {
  RTCError error = rtcGetDeviceError(device);
  if (error == RTC_ERROR_NONE) return;
  if (error == RTC_ERROR_OUT_OF_MEMORY) fail(SS_OUT_OF_MEMORY, std::string("Embree: out of memory in ") + what);
  fail(SS_INTERNAL_ERROR, std::string("Embree error ") + std::to_string(int(error)) + " in " + what);
}

}  // namespace

RayScene::RayScene(const Scene& scene) {
  device_ = rtcNewDevice(nullptr);
  if (!device_) fail(SS_INTERNAL_ERROR, "Embree: could not create a device (error " +
                                            std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  Bounds bounds = scene.bounds(false);
  epsilon_ = 1e-5f * std::max(1.0f, glm::length(bounds.hi - bounds.lo) +
                                        glm::length(glm::abs(bounds.center())));

  meshes_.reserve(scene.meshes().size());
  for (const auto& [id, mesh] : scene.meshes()) {
    WorldMesh world;
    world.mesh = &mesh;
    world.object = mesh.index;
    world.indices = &mesh.cpuIndices;
    world.materials = &mesh.denseMaterials;
    glm::mat3 normalMatrix = glm::inverseTranspose(glm::mat3(mesh.objectToWorld));
    world.positions.reserve(mesh.cpuPositions.size());
    for (const glm::vec3& p : mesh.cpuPositions)
      world.positions.push_back(glm::vec3(mesh.objectToWorld * glm::vec4(p, 1.0f)));
    world.normals.reserve(mesh.cpuNormals.size());
    for (const glm::vec3& n : mesh.cpuNormals) {
      glm::vec3 w = normalMatrix * n;
      float length = glm::length(w);
      world.normals.push_back(length > 0 && std::isfinite(length) ? w / length : glm::vec3(0, 0, 1));
    }

    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(glm::vec3), world.positions.size()));
    auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), mesh.triangleCount));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      checkDevice(device_, "geometry buffers");
      fail(SS_OUT_OF_MEMORY, "Embree: could not allocate geometry buffers");
    }
    std::memcpy(vertices, world.positions.data(), world.positions.size() * sizeof(glm::vec3));
    std::memcpy(indices, mesh.cpuIndices.data(), mesh.cpuIndices.size() * sizeof(uint32_t));
    rtcCommitGeometry(geometry);
    unsigned geomId = rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    if (geomId != meshes_.size()) fail(SS_INTERNAL_ERROR, "Embree: unexpected geometry id");
    meshes_.push_back(std::move(world));
  }
  rtcCommitScene(scene_);
  checkDevice(device_, "scene build");
}

RayScene::~RayScene() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

Hit RayScene::intersect(const glm::vec3& o, const glm::vec3& d, float tNear, float tFar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
  rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
  rh.ray.tnear = tNear;
  rh.ray.tfar = tFar;
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  Hit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.mesh = int(rh.hit.geomID);
  hit.triangle = rh.hit.primID;
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  hit.distance = rh.ray.tfar;
  return hit;
}

bool RayScene::occluded(const glm::vec3& o, const glm::vec3& d, float tNear, float tFar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = o.x, ray.org_y = o.y, ray.org_z = o.z;
  ray.dir_x = d.x, ray.dir_y = d.y, ray.dir_z = d.z;
  ray.tnear = tNear;
  ray.tfar = tFar;
  ray.mask = ~0u;
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

}  // namespace subsplat
