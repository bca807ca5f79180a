// RAII wrappers for the GL objects the pipeline owns. Move only.
#pragma once

#include <epoxy/gl.h>

#include <atomic>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <map>
#include <string>
#include <utility>

#include "gl/bindings.h"

namespace subsplat::gl {

// GPU memory held by the library's textures and buffers, over all contexts.
inline std::atomic<uint64_t> heldBytes{0};

// Each kind counts its live objects over all contexts (ssGetResourceCounts: the leak tests) and
// the objects ever made (made(): the tests that objects are reused, not made per frame), and
// each object the GPU memory it holds (gpuBytes, the memory budget).
template <void (*Delete)(GLuint)>
class Object {
 public:
  Object() = default;
  explicit Object(GLuint id, uint64_t bytes = 0) : id_(id), bytes_(id ? bytes : 0) {
    if (id_) {
      live_.fetch_add(1, std::memory_order_relaxed);
      made_.fetch_add(1, std::memory_order_relaxed);
    }
    heldBytes.fetch_add(bytes_, std::memory_order_relaxed);
  }
  ~Object() { reset(); }
  Object(Object&& o) noexcept : id_(std::exchange(o.id_, 0)), bytes_(std::exchange(o.bytes_, 0)) {}
  Object& operator=(Object&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
      bytes_ = std::exchange(o.bytes_, 0);
    }
    return *this;
  }
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;
  void reset() {
    if (id_) {
      Delete(id_);
      live_.fetch_sub(1, std::memory_order_relaxed);
      heldBytes.fetch_sub(bytes_, std::memory_order_relaxed);
    }
    id_ = 0;
    bytes_ = 0;
  }
  GLuint id() const { return id_; }
  uint64_t bytes() const { return bytes_; }
  explicit operator bool() const { return id_ != 0; }
  static int64_t live() { return live_.load(std::memory_order_relaxed); }
  static int64_t made() { return made_.load(std::memory_order_relaxed); }

 private:
  GLuint id_ = 0;
  uint64_t bytes_ = 0;
  inline static std::atomic<int64_t> live_{0}, made_{0};
};

// The memory budget (ssSetMemoryBudget): every texture and buffer the library makes is checked
// against it before the GL allocates, so a scene too big for the GPU fails with SS_LIMIT_EXCEEDED
// naming what asked, never with a GL out-of-memory error. 0 sets the automatic budget: 90 % of
// the memory the driver reports (GL_NVX_gpu_memory_info, GL_ATI_meminfo), else half of the
// machine's RAM (llvmpipe and other drivers that share system memory).
uint64_t gpuBytes();
uint64_t memoryBudget();  // needs a current context the first time, for the automatic budget
bool memoryBudgetKnown();  // set, or measured already
void setMemoryBudget(uint64_t bytes);
// Throws SS_LIMIT_EXCEEDED when `bytes` more would exceed the budget; the message names the
// innermost Purpose on this thread.
void reserve(uint64_t bytes);

// What the allocations made while it lives are for, in the budget's error message
// ("mesh 3 (120000 vertices, 240000 triangles)").
class Purpose {
 public:
  explicit Purpose(std::string what);
  ~Purpose();
  Purpose(const Purpose&) = delete;
  Purpose& operator=(const Purpose&) = delete;

 private:
  std::string what_;
  const Purpose* previous_;
  friend void reserve(uint64_t bytes);
};

// GL names belong to the OpenGL context that made them (vertex arrays, framebuffers and
// queries are never shared). While an OrphanScope(owner, true) lives on a thread, the deletes
// below delete nothing and queue the objects for `owner` instead; deleteOrphans(current)
// deletes those queued for the context current now (Blender's GPU module does the same).
class OrphanScope {
 public:
  OrphanScope(const void* owner, bool away);
  ~OrphanScope();
  OrphanScope(const OrphanScope&) = delete;
  OrphanScope& operator=(const OrphanScope&) = delete;

 private:
  const void* previousOwner_;
  bool previous_;
};
void deleteOrphans(const void* current);
int64_t orphanedObjects();  // queued, waiting for their context

void deleteTexture(GLuint id);
void deleteBuffer(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteVertexArray(GLuint id);
void deleteProgram(GLuint id);
void deleteQuery(GLuint id);

using Texture = Object<deleteTexture>;
using Buffer = Object<deleteBuffer>;
using Framebuffer = Object<deleteFramebuffer>;
using VertexArray = Object<deleteVertexArray>;
using Program = Object<deleteProgram>;
using Query = Object<deleteQuery>;

Texture makeTexture2D(GLenum internalFormat, int width, int height, GLenum filter = GL_NEAREST,
                      int levels = 1);
Texture makeTexture2DArray(GLenum internalFormat, int width, int height, int layers,
                           GLenum filter = GL_NEAREST);
Buffer makeBuffer(GLenum target, size_t bytes, const void* data, GLenum usage = GL_STATIC_DRAW);
// A buffer texture reading `buffer`'s contents as internalFormat texels (GL_TEXTURE_BUFFER).
Texture makeBufferTexture(GLenum internalFormat, const Buffer& buffer);
VertexArray makeVertexArray();
Framebuffer makeFramebuffer(std::initializer_list<GLuint> colorTextures, GLuint depthTexture);
// Layers 0 .. layers - 1 of a 2D array texture as colour attachments 0 .. layers - 1.
Framebuffer makeLayeredFramebuffer(GLuint arrayTexture, int layers, GLuint depthTexture = 0);
// A 2D texture as colour attachment 0, then layers first .. first + layers - 1 of a 2D array
// texture as attachments 1 .. layers.
Framebuffer makeFramebufferWithLayers(GLuint texture, GLuint arrayTexture, int first, int layers);
// Compiles and links shaders by name from the embedded table (shaders/*.glsl);
// throws with the info log on failure. `defines` ("#define NAME value" lines) go before every
// stage's source: a variant of the program (ProgramVariants).
Program makeProgram(const std::string& vertex, const std::string& geometry,
                    const std::string& fragment, const std::string& defines = "");

// A program compiled in variants (makeProgram's defines), each on its first use and kept for the
// context's life: get({{"NAME", value}, ...}) is the one compiled with "#define NAME value" lines.
class ProgramVariants {
 public:
  ProgramVariants(std::string vertex, std::string geometry, std::string fragment)
      : vertex_(std::move(vertex)), geometry_(std::move(geometry)), fragment_(std::move(fragment)) {}
  GLuint get(std::initializer_list<std::pair<const char*, int>> defines);

 private:
  std::string vertex_, geometry_, fragment_;
  std::map<std::string, Program> programs_;  // by their defines
};

Program makeComputeProgram(const std::string& compute);
// The same for a compute shader given as source (the tests that run common.glsl's functions).
Program makeComputeProgramFromSource(const std::string& name, const std::string& source);

// Throws SS_GL_ERROR naming the stage when glGetError reports anything.
void checkErrors(const char* stage);

// Saves the GL state the library touches and restores it on destruction
// (STYLE.md: one guard around each entry point that issues GL).
class StateGuard {
 public:
  StateGuard();
  ~StateGuard();
  StateGuard(const StateGuard&) = delete;
  StateGuard& operator=(const StateGuard&) = delete;

 private:
  GLint drawFramebuffer_ = 0, readFramebuffer_ = 0, program_ = 0, vertexArray_ = 0;
  GLint arrayBuffer_ = 0, activeTexture_ = 0, viewport_[4] = {}, scissorBox_[4] = {};
  // The units and bindings of the binding table (gl/bindings.h): what the passes bind.
  struct TextureUnit {
    GLint texture2D = 0, texture2DArray = 0, textureBuffer = 0, sampler = 0;
  } textures_[std::size(kTextureUnits)];
  GLint uniformBuffer_ = 0;
  GLint shaderStorageBuffer_ = 0;
  struct StorageBinding {
    GLint name = 0;
    GLint64 start = 0, size = 0;
  } storage_[std::size(kStorageBindings)];
  struct ImageUnit {
    GLint name = 0, level = 0, layered = 0, layer = 0, access = GL_READ_ONLY, format = GL_R8;
  } images_[std::size(kImageUnits)];
  GLint packAlignment_ = 4, unpackAlignment_ = 4, packRowLength_ = 0, unpackRowLength_ = 0;
  GLint blendSrcRgb_ = 0, blendDstRgb_ = 0, blendSrcAlpha_ = 0, blendDstAlpha_ = 0;
  GLint blendEqRgb_ = 0, blendEqAlpha_ = 0, depthFunc_ = 0, cullFaceMode_ = 0;
  GLint pixelPackBuffer_ = 0, pixelUnpackBuffer_ = 0, textureBufferBuffer_ = 0, drawIndirectBuffer_ = 0;
  GLboolean depthMask_ = GL_TRUE, colorMask_[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
  GLboolean blend_ = 0, depthTest_ = 0, cullFace_ = 0, scissorTest_ = 0, stencilTest_ = 0;
  GLboolean programPointSize_ = 0, framebufferSrgb_ = 0;
  GLfloat clearColor_[4] = {}, blendColor_[4] = {}, clearDepth_ = 1.0f, depthRange_[2] = {0.0f, 1.0f};
  GLint clipOrigin_ = GL_LOWER_LEFT, clipDepth_ = GL_NEGATIVE_ONE_TO_ONE, polygonMode_[2] = {};
  GLboolean depthClamp_ = 0, polygonOffsetFill_ = 0;
};

}  // namespace subsplat::gl
