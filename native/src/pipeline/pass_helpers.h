// What the passes share: uniform look-ups, the light and camera uniforms,
// texture binding by the binding table, and drawing the scene's meshes.
#pragma once

#include <initializer_list>

#include <glm/glm.hpp>

#include "gl/gl.h"
#include "pipeline/gpu_scene.h"
#include "pipeline/light_views.h"
#include "scene.h"
#include "util/camera.h"

namespace subsplat {

// Uniform helpers shared by the passes.
GLint uniform(GLuint program, const char* name);
// A mesh pass's variant for the scene (common.glsl: TEXTURES, PROFILE_MAPS).
GLuint sceneVariant(gl::ProgramVariants& programs, const Scene& scene);
void setLightUniforms(GLuint program, const LightView& view);
// The view's soft-shadow uniforms (common.glsl: softVisibility).
void setSoftShadowUniforms(GLuint program, const LightView& view);
// Binds `texture` on a unit of the binding table (gl/bindings.h), which the shaders name, and
// no sampler object there (a host's sampler would override the texture's filtering).
void bindTexture(int unit, GLenum target, GLuint texture);

// Draws every mesh of the scene with `program` (mesh.vert) into the bound target.
void drawMeshes(const Scene& scene, const GpuScene& gpu, GLuint program, const glm::mat4& viewProj);
// The start of a pass that draws the meshes into `framebuffer` (width x height): colour attachment i
// cleared to clears[i], the depth buffer cleared, the depth test (less) on; program in use. The pass
// ends with glDisable(GL_DEPTH_TEST).
void beginMeshPass(GLuint framebuffer, int width, int height, std::initializer_list<glm::vec4> clears, GLuint program);
// cameraPosition, cameraForward and orthographic as uniforms.
void setCameraUniforms(GLuint program, const SsCameraDesc& camera);
// The TABULATED model's tables (common.glsl: transportTables, transportGrid) for a program that
// reads them.
void setTransportUniforms(GLuint program, GLuint transportTables);

}  // namespace subsplat
