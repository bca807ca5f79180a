// A surfaceless EGL + OpenGL 4.5 core context for native tests and tools.
#pragma once

#include <memory>
#include <string>

namespace subsplat::testing {

class EglContext {
 public:
  // Creates and makes current a context; throws std::runtime_error.
  EglContext();
  ~EglContext();
  std::string renderer() const;
  bool makeCurrent() const;  // makes this context current again

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace subsplat::testing
