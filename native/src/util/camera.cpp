#include "util/camera.h"

#include <glm/gtc/type_ptr.hpp>

namespace subsplat {

glm::vec3 cameraPosition(const SsCameraDesc& camera) {
  return glm::vec3(glm::inverse(glm::make_mat4(camera.world_to_view))[3]);
}

glm::vec3 cameraForward(const SsCameraDesc& camera) {
  return -glm::normalize(glm::vec3(glm::inverse(glm::make_mat4(camera.world_to_view))[2]));
}

}  // namespace subsplat
