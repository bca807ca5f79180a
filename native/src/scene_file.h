// The scene file: everything a context was given (materials, meshes, lights,
// camera, settings, the last frame's size), written so that a program without
// Blender can replay the frame through the same C API (subsplat_replay), and
// so that a user can attach exactly what the library saw to a bug report.
// Format in docs/SCENE_FILE.md. Loading goes through the same validating
// setters as the API calls, so a file is trusted no more than a caller.
#pragma once

#include <string>

#include "renderer.h"

namespace subsplat {

void saveScene(const Renderer& renderer, const std::string& path);
struct FrameSize {
  int width = 0, height = 0;  // 0 x 0: the file was saved before any render
};
// Replaces the renderer's scene and settings; on failure the scene is empty.
// Returns the size of the frame rendered before the file was saved.
FrameSize loadScene(Renderer& renderer, const std::string& path);

}  // namespace subsplat
