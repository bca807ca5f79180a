// The GLSL files of native/shaders/, embedded at build time (cmake/embed_files.cmake).
#pragma once
#include <string>

namespace subsplat::gl {
// Source of the named shader file, or nullptr.
const char* shaderSource(const std::string& name);
}  // namespace subsplat::gl
