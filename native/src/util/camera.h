// The camera's position and viewing direction, from its world-to-view matrix.
#pragma once

#include <glm/glm.hpp>

#include "subsplat/subsplat.h"

namespace subsplat {

// Camera position and forward axis from the world-to-view matrix.
glm::vec3 cameraPosition(const SsCameraDesc& camera);
glm::vec3 cameraForward(const SsCameraDesc& camera);

}  // namespace subsplat
