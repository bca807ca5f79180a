// The scene file: everything a context was given (materials, meshes, lights,
// camera, settings, the last frame's size), written so that a program without
// Blender can replay the frame through the same C API (subsplat_replay), and
// so that a user can attach exactly what the library saw to a bug report.
// Format in docs/SCENE_FILE.md. Loading goes through the same validating
// setters as the API calls, so a file is trusted no more than a caller.
// Scene files need no GL context: they read and write the CPU scene.
#pragma once

#include <functional>
#include <string>

#include "scene.h"

namespace subsplat {

class Renderer;

struct FrameSize {
  int width = 0, height = 0;  // 0 x 0: the file was saved before any render
};

// A scene with the settings and the size of the last frame rendered from it.
void saveScene(const Scene& scene, const SsSettings& settings, FrameSize frame, const std::string& path);
// Replaces the scene; the settings go to applySettings as they are read (it
// validates them). On failure the scene is empty. Returns the size of the frame
// rendered before the file was saved.
FrameSize loadScene(Scene& scene, const std::function<void(const SsSettings&)>& applySettings,
                    const std::string& path);

// The same with a renderer's scene and settings (ssSaveScene, ssLoadScene).
void saveScene(const Renderer& renderer, const std::string& path);
FrameSize loadScene(Renderer& renderer, const std::string& path);

}  // namespace subsplat
