#include "gl/gl.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <mutex>
#include <unordered_map>
#include <utility>
#include <vector>

#include "gl/bindings.h"
#include "gl/shader_sources.h"
#include "util/error.h"

namespace subsplat::gl {

namespace {
void rawDeleteTexture(GLuint id) { glDeleteTextures(1, &id); }
void rawDeleteBuffer(GLuint id) { glDeleteBuffers(1, &id); }
void rawDeleteFramebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void rawDeleteVertexArray(GLuint id) { glDeleteVertexArrays(1, &id); }
void rawDeleteProgram(GLuint id) { glDeleteProgram(id); }
void rawDeleteQuery(GLuint id) { glDeleteQueries(1, &id); }

struct Orphan {
  void (*remove)(GLuint);
  GLuint id;
};
std::mutex orphanMutex;
std::unordered_map<const void*, std::vector<Orphan>> orphans;  // by owning OpenGL context
int64_t orphanTotal = 0;

thread_local const void* orphanOwner = nullptr;
thread_local bool orphaning = false;

// Queues the object for its own context while an OrphanScope is active.
bool orphaned(void (*remove)(GLuint), GLuint id) {
  if (!orphaning) return false;
  std::lock_guard<std::mutex> lock(orphanMutex);
  orphans[orphanOwner].push_back({remove, id});
  ++orphanTotal;
  return true;
}
}  // namespace

OrphanScope::OrphanScope(const void* owner, bool away)
    : previousOwner_(std::exchange(orphanOwner, away ? owner : orphanOwner)),
      previous_(std::exchange(orphaning, orphaning || away)) {}
OrphanScope::~OrphanScope() {
  orphanOwner = previousOwner_;
  orphaning = previous_;
}

void deleteOrphans(const void* current) {
  std::vector<Orphan> mine;
  {
    std::lock_guard<std::mutex> lock(orphanMutex);
    auto found = orphans.find(current);
    if (found == orphans.end()) return;
    mine = std::move(found->second);
    orphans.erase(found);
    orphanTotal -= int64_t(mine.size());
  }
  for (const Orphan& o : mine) o.remove(o.id);
}

int64_t orphanedObjects() {
  std::lock_guard<std::mutex> lock(orphanMutex);
  return orphanTotal;
}

namespace {
std::atomic<uint64_t> budgetSetting{0};    // ssSetMemoryBudget; 0 = automatic
std::atomic<uint64_t> automaticBudget{0};  // measured once, with a context current
thread_local const Purpose* purpose = nullptr;

uint64_t measureBudget() {
  if (epoxy_has_gl_extension("GL_NVX_gpu_memory_info")) {
    GLint kib = 0;
    glGetIntegerv(0x9048, &kib);  // GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX
    if (glGetError() == GL_NO_ERROR && kib > 0) return uint64_t(kib) * 1024 / 10 * 9;
  }
  if (epoxy_has_gl_extension("GL_ATI_meminfo")) {
    GLint kib[4] = {};
    glGetIntegerv(0x87FC, kib);  // TEXTURE_FREE_MEMORY_ATI: free now, in KiB
    if (glGetError() == GL_NO_ERROR && kib[0] > 0) return (uint64_t(kib[0]) * 1024 + gpuBytes()) / 10 * 9;
  }
  long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
  if (pages > 0 && pageSize > 0) return uint64_t(pages) * uint64_t(pageSize) / 2;
  return uint64_t(4) << 30;
}

std::string mib(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / double(1 << 20));
  return text;
}

uint64_t texelBytes(GLenum format) {
  switch (format) {
    case GL_RGBA32F: case GL_RGBA32UI: return 16;
    case GL_RGBA16F: case GL_RG32F: return 8;
    case GL_R32F: case GL_R32UI: case GL_DEPTH_COMPONENT32F: case GL_RGBA8: case GL_RG16F: return 4;
    case GL_R16F: return 2;
    default: return 16;  // unknown formats count as the widest we use
  }
}
}  // namespace

uint64_t gpuBytes() { return heldBytes.load(std::memory_order_relaxed); }

uint64_t memoryBudget() {
  uint64_t set = budgetSetting.load(std::memory_order_relaxed);
  if (set != 0) return set;
  uint64_t automatic = automaticBudget.load(std::memory_order_relaxed);
  if (automatic == 0) {
    automatic = measureBudget();
    automaticBudget.store(automatic, std::memory_order_relaxed);
  }
  return automatic;
}

bool memoryBudgetKnown() {
  return budgetSetting.load(std::memory_order_relaxed) != 0 || automaticBudget.load(std::memory_order_relaxed) != 0;
}

void setMemoryBudget(uint64_t bytes) { budgetSetting.store(bytes, std::memory_order_relaxed); }

Purpose::Purpose(std::string what) : what_(std::move(what)), previous_(purpose) { purpose = this; }
Purpose::~Purpose() { purpose = previous_; }

void reserve(uint64_t bytes) {
  uint64_t budget = memoryBudget(), held = gpuBytes();
  if (held <= budget && bytes <= budget - held) return;
  std::string what = purpose != nullptr ? purpose->what_ : "GPU data";
  fail(SS_LIMIT_EXCEEDED, what + ": " + mib(bytes) + " more GPU memory would exceed the memory budget (" +
                              mib(held) + " of " + mib(budget) + " in use)");
}

void deleteTexture(GLuint id) { if (!orphaned(rawDeleteTexture, id)) rawDeleteTexture(id); }
void deleteBuffer(GLuint id) { if (!orphaned(rawDeleteBuffer, id)) rawDeleteBuffer(id); }
void deleteFramebuffer(GLuint id) { if (!orphaned(rawDeleteFramebuffer, id)) rawDeleteFramebuffer(id); }
void deleteVertexArray(GLuint id) { if (!orphaned(rawDeleteVertexArray, id)) rawDeleteVertexArray(id); }
void deleteProgram(GLuint id) { if (!orphaned(rawDeleteProgram, id)) rawDeleteProgram(id); }
void deleteQuery(GLuint id) { if (!orphaned(rawDeleteQuery, id)) rawDeleteQuery(id); }


static void setFilter(GLenum target, GLenum filter) {
  glTexParameteri(target, GL_TEXTURE_MIN_FILTER, filter);
  glTexParameteri(target, GL_TEXTURE_MAG_FILTER, filter);
  glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

Texture makeTexture2D(GLenum internalFormat, int width, int height, GLenum filter, int levels) {
  uint64_t bytes = 0;
  for (int k = 0; k < levels; ++k)
    bytes += uint64_t(std::max(width >> k, 1)) * uint64_t(std::max(height >> k, 1)) * texelBytes(internalFormat);
  reserve(bytes);
  GLuint id = 0;
  glGenTextures(1, &id);
  Texture texture(id, bytes);
  glBindTexture(GL_TEXTURE_2D, id);
  glTexStorage2D(GL_TEXTURE_2D, levels, internalFormat, width, height);
  setFilter(GL_TEXTURE_2D, filter);
  checkErrors("texture allocation");
  return texture;
}

Texture makeTexture2DArray(GLenum internalFormat, int width, int height, int layers,
                           GLenum filter) {
  uint64_t bytes = uint64_t(width) * uint64_t(height) * uint64_t(layers) * texelBytes(internalFormat);
  reserve(bytes);
  GLuint id = 0;
  glGenTextures(1, &id);
  Texture texture(id, bytes);
  glBindTexture(GL_TEXTURE_2D_ARRAY, id);
  glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, internalFormat, width, height, layers);
  setFilter(GL_TEXTURE_2D_ARRAY, filter);
  checkErrors("texture array allocation");
  return texture;
}

Texture makeBufferTexture(GLenum internalFormat, const Buffer& buffer) {
  GLuint id = 0;
  glGenTextures(1, &id);
  Texture texture(id);
  glBindTexture(GL_TEXTURE_BUFFER, id);
  glTexBuffer(GL_TEXTURE_BUFFER, internalFormat, buffer.id());
  glBindTexture(GL_TEXTURE_BUFFER, 0);
  return texture;
}

Buffer makeBuffer(GLenum target, size_t bytes, const void* data, GLenum usage) {
  reserve(bytes);
  GLuint id = 0;
  glGenBuffers(1, &id);
  Buffer buffer(id, bytes);
  glBindBuffer(target, id);
  glBufferData(target, GLsizeiptr(bytes), data, usage);
  checkErrors("buffer allocation");
  return buffer;
}

VertexArray makeVertexArray() {
  GLuint id = 0;
  glGenVertexArrays(1, &id);
  return VertexArray(id);
}

// The bound framebuffer's draw buffers; throws unless it is complete.
static void completeFramebuffer(const std::vector<GLenum>& drawBuffers) {
  glDrawBuffers(GLsizei(drawBuffers.size()), drawBuffers.data());
  GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%04x", unsigned(status));
    fail(SS_GL_ERROR, "framebuffer incomplete (status " + std::string(hex) + ")");
  }
}

Framebuffer makeFramebuffer(std::initializer_list<GLuint> colorTextures, GLuint depthTexture) {
  GLuint id = 0;
  glGenFramebuffers(1, &id);
  Framebuffer framebuffer(id);
  glBindFramebuffer(GL_FRAMEBUFFER, id);
  std::vector<GLenum> drawBuffers;
  for (GLuint texture : colorTextures) {
    GLenum attachment = GL_COLOR_ATTACHMENT0 + GLenum(drawBuffers.size());
    glFramebufferTexture(GL_FRAMEBUFFER, attachment, texture, 0);
    drawBuffers.push_back(attachment);
  }
  if (depthTexture) glFramebufferTexture(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, depthTexture, 0);
  completeFramebuffer(drawBuffers);
  return framebuffer;
}

Framebuffer makeFramebufferWithLayers(GLuint texture, GLuint arrayTexture, int first, int layers) {
  GLuint id = 0;
  glGenFramebuffers(1, &id);
  Framebuffer framebuffer(id);
  glBindFramebuffer(GL_FRAMEBUFFER, id);
  glFramebufferTexture(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, texture, 0);
  std::vector<GLenum> drawBuffers{GL_COLOR_ATTACHMENT0};
  for (int l = 0; l < layers; ++l) {
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1 + GLenum(l), arrayTexture, 0, first + l);
    drawBuffers.push_back(GL_COLOR_ATTACHMENT1 + GLenum(l));
  }
  completeFramebuffer(drawBuffers);
  return framebuffer;
}

Framebuffer makeLayeredFramebuffer(GLuint arrayTexture, int layers, GLuint depthTexture) {
  GLuint id = 0;
  glGenFramebuffers(1, &id);
  Framebuffer framebuffer(id);
  glBindFramebuffer(GL_FRAMEBUFFER, id);
  std::vector<GLenum> drawBuffers;
  for (int l = 0; l < layers; ++l) {
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + GLenum(l), arrayTexture, 0, l);
    drawBuffers.push_back(GL_COLOR_ATTACHMENT0 + GLenum(l));
  }
  if (depthTexture) glFramebufferTexture(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, depthTexture, 0);
  completeFramebuffer(drawBuffers);
  return framebuffer;
}

static GLuint compileShader(GLenum type, const std::string& name, const char* source,
                            const std::string& defines = "") {
  std::string header = "#version 430 core\n" + glslBindingDefines() + defines;
  std::string include = shaderSource("common.glsl");
  std::string full = header + include + "\n#line 1\n" + source;
  const char* text = full.c_str();
  GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    fail(SS_GL_ERROR, "shader " + name + " failed to compile: " + log);
  }
  return shader;
}

static GLuint compileShader(GLenum type, const std::string& name, const std::string& defines = "") {
  const char* source = shaderSource(name);
  if (!source) fail(SS_INTERNAL_ERROR, "no embedded shader named " + name);
  return compileShader(type, name, source, defines);
}

// Attaches and links the compiled shaders (and deletes them); throws with the info log.
static void link(const Program& program, const std::vector<GLuint>& shaders, const std::string& name) {
  for (GLuint s : shaders) glAttachShader(program.id(), s);
  glLinkProgram(program.id());
  for (GLuint s : shaders) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
  if (ok) return;
  GLint length = 0;
  glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 1)), '\0');
  glGetProgramInfoLog(program.id(), length, nullptr, log.data());
  fail(SS_GL_ERROR, "program " + name + " failed to link: " + log);
}

Program makeProgram(const std::string& vertex, const std::string& geometry,
                    const std::string& fragment, const std::string& defines) {
  Program program(glCreateProgram());
  std::vector<GLuint> shaders;
  try {
    shaders.push_back(compileShader(GL_VERTEX_SHADER, vertex, defines));
    if (!geometry.empty()) shaders.push_back(compileShader(GL_GEOMETRY_SHADER, geometry, defines));
    shaders.push_back(compileShader(GL_FRAGMENT_SHADER, fragment, defines));
  } catch (...) {
    for (GLuint s : shaders) glDeleteShader(s);
    throw;
  }
  link(program, shaders, vertex + "+" + fragment);
  return program;
}

GLuint ProgramVariants::get(std::initializer_list<std::pair<const char*, int>> defines) {
  std::string key;
  for (const auto& [name, value] : defines) key += "#define " + std::string(name) + " " + std::to_string(value) + "\n";
  auto found = programs_.find(key);
  if (found == programs_.end()) found = programs_.emplace(key, makeProgram(vertex_, geometry_, fragment_, key)).first;
  return found->second.id();
}

Program makeComputeProgram(const std::string& compute) {
  Program program(glCreateProgram());
  link(program, {compileShader(GL_COMPUTE_SHADER, compute)}, compute);
  return program;
}

Program makeComputeProgramFromSource(const std::string& name, const std::string& source) {
  Program program(glCreateProgram());
  link(program, {compileShader(GL_COMPUTE_SHADER, name, source.c_str())}, name);
  return program;
}

void checkErrors(const char* stage) {
  GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  for (int i = 0; i < 32 && glGetError() != GL_NO_ERROR; ++i) {
  }
  const char* name = error == GL_OUT_OF_MEMORY ? "GL_OUT_OF_MEMORY"
                     : error == GL_INVALID_OPERATION ? "GL_INVALID_OPERATION"
                     : error == GL_INVALID_VALUE ? "GL_INVALID_VALUE"
                     : error == GL_INVALID_ENUM ? "GL_INVALID_ENUM"
                     : error == GL_INVALID_FRAMEBUFFER_OPERATION ? "GL_INVALID_FRAMEBUFFER_OPERATION"
                                                                 : "GL error";
  fail(error == GL_OUT_OF_MEMORY ? SS_OUT_OF_MEMORY : SS_GL_ERROR,
       std::string(name) + " during " + stage);
}

StateGuard::StateGuard() {
  // Errors the host left pending are not ours: without this, the first checkErrors of the
  // call would report them (Blender's material preview thread leaves GL_INVALID_OPERATION).
  for (int i = 0; i < 32 && glGetError() != GL_NO_ERROR; ++i) {
  }
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawFramebuffer_);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readFramebuffer_);
  glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vertexArray_);
  glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &arrayBuffer_);
  glGetIntegerv(GL_UNIFORM_BUFFER_BINDING, &uniformBuffer_);
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_BINDING, &shaderStorageBuffer_);
  for (size_t i = 0; i < std::size(kStorageBindings); ++i) {
    GLuint b = GLuint(kStorageBindings[i]);
    glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, b, &storage_[i].name);
    glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, b, &storage_[i].start);
    glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, b, &storage_[i].size);
  }
  for (size_t i = 0; i < std::size(kImageUnits); ++i) {
    GLuint u = GLuint(kImageUnits[i]);
    glGetIntegeri_v(GL_IMAGE_BINDING_NAME, u, &images_[i].name);
    glGetIntegeri_v(GL_IMAGE_BINDING_LEVEL, u, &images_[i].level);
    glGetIntegeri_v(GL_IMAGE_BINDING_LAYERED, u, &images_[i].layered);
    glGetIntegeri_v(GL_IMAGE_BINDING_LAYER, u, &images_[i].layer);
    glGetIntegeri_v(GL_IMAGE_BINDING_ACCESS, u, &images_[i].access);
    glGetIntegeri_v(GL_IMAGE_BINDING_FORMAT, u, &images_[i].format);
  }
  glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pixelPackBuffer_);
  glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &pixelUnpackBuffer_);
  glGetIntegerv(GL_TEXTURE_BUFFER_BINDING, &textureBufferBuffer_);
  glGetIntegerv(GL_DRAW_INDIRECT_BUFFER_BINDING, &drawIndirectBuffer_);
  glGetIntegerv(GL_ACTIVE_TEXTURE, &activeTexture_);
  for (size_t i = 0; i < std::size(kTextureUnits); ++i) {
    glActiveTexture(GLenum(GL_TEXTURE0 + kTextureUnits[i]));
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &textures_[i].texture2D);
    glGetIntegerv(GL_TEXTURE_BINDING_2D_ARRAY, &textures_[i].texture2DArray);
    glGetIntegerv(GL_TEXTURE_BINDING_BUFFER, &textures_[i].textureBuffer);
    glGetIntegerv(GL_SAMPLER_BINDING, &textures_[i].sampler);
  }
  // Left on a unit of the table, so that the binds of uploads and read-backs (on the active
  // unit) land where the destructor restores them.
  glActiveTexture(GLenum(GL_TEXTURE0 + kTextureUnits[0]));
  glGetIntegerv(GL_VIEWPORT, viewport_);
  glGetIntegerv(GL_SCISSOR_BOX, scissorBox_);
  glGetIntegerv(GL_PACK_ALIGNMENT, &packAlignment_);
  glGetIntegerv(GL_UNPACK_ALIGNMENT, &unpackAlignment_);
  glGetIntegerv(GL_PACK_ROW_LENGTH, &packRowLength_);
  glGetIntegerv(GL_UNPACK_ROW_LENGTH, &unpackRowLength_);
  glGetIntegerv(GL_BLEND_SRC_RGB, &blendSrcRgb_);
  glGetIntegerv(GL_BLEND_DST_RGB, &blendDstRgb_);
  glGetIntegerv(GL_BLEND_SRC_ALPHA, &blendSrcAlpha_);
  glGetIntegerv(GL_BLEND_DST_ALPHA, &blendDstAlpha_);
  glGetIntegerv(GL_BLEND_EQUATION_RGB, &blendEqRgb_);
  glGetIntegerv(GL_BLEND_EQUATION_ALPHA, &blendEqAlpha_);
  glGetIntegerv(GL_DEPTH_FUNC, &depthFunc_);
  glGetIntegerv(GL_CULL_FACE_MODE, &cullFaceMode_);
  glGetBooleanv(GL_DEPTH_WRITEMASK, &depthMask_);
  glGetBooleanv(GL_COLOR_WRITEMASK, colorMask_);
  glGetFloatv(GL_COLOR_CLEAR_VALUE, clearColor_);
  glGetFloatv(GL_BLEND_COLOR, blendColor_);
  glGetFloatv(GL_DEPTH_CLEAR_VALUE, &clearDepth_);
  glGetFloatv(GL_DEPTH_RANGE, depthRange_);
  glGetIntegerv(GL_CLIP_ORIGIN, &clipOrigin_);
  glGetIntegerv(GL_CLIP_DEPTH_MODE, &clipDepth_);
  glGetIntegerv(GL_POLYGON_MODE, polygonMode_);
  depthClamp_ = glIsEnabled(GL_DEPTH_CLAMP);
  polygonOffsetFill_ = glIsEnabled(GL_POLYGON_OFFSET_FILL);
  blend_ = glIsEnabled(GL_BLEND);
  depthTest_ = glIsEnabled(GL_DEPTH_TEST);
  cullFace_ = glIsEnabled(GL_CULL_FACE);
  scissorTest_ = glIsEnabled(GL_SCISSOR_TEST);
  stencilTest_ = glIsEnabled(GL_STENCIL_TEST);
  programPointSize_ = glIsEnabled(GL_PROGRAM_POINT_SIZE);
  framebufferSrgb_ = glIsEnabled(GL_FRAMEBUFFER_SRGB);
}

static void setEnabled(GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); }

StateGuard::~StateGuard() {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(drawFramebuffer_));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(readFramebuffer_));
  glUseProgram(GLuint(program_));
  glBindVertexArray(GLuint(vertexArray_));
  glBindBuffer(GL_ARRAY_BUFFER, GLuint(arrayBuffer_));
  glBindBuffer(GL_UNIFORM_BUFFER, GLuint(uniformBuffer_));
  for (size_t i = 0; i < std::size(kStorageBindings); ++i) {
    const StorageBinding& b = storage_[i];
    if (b.name != 0 && b.size > 0)
      glBindBufferRange(GL_SHADER_STORAGE_BUFFER, GLuint(kStorageBindings[i]), GLuint(b.name), GLintptr(b.start),
                        GLsizeiptr(b.size));
    else
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(kStorageBindings[i]), GLuint(b.name));
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, GLuint(shaderStorageBuffer_));
  for (size_t i = 0; i < std::size(kImageUnits); ++i) {
    const ImageUnit& u = images_[i];
    glBindImageTexture(GLuint(kImageUnits[i]), GLuint(u.name), u.level, u.layered ? GL_TRUE : GL_FALSE, u.layer,
                       GLenum(u.access), GLenum(u.format ? u.format : GL_R8));
  }
  glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(pixelPackBuffer_));
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, GLuint(pixelUnpackBuffer_));
  glBindBuffer(GL_TEXTURE_BUFFER, GLuint(textureBufferBuffer_));
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, GLuint(drawIndirectBuffer_));
  for (size_t i = 0; i < std::size(kTextureUnits); ++i) {
    const TextureUnit& u = textures_[i];
    glActiveTexture(GLenum(GL_TEXTURE0 + kTextureUnits[i]));
    glBindTexture(GL_TEXTURE_2D, GLuint(u.texture2D));
    glBindTexture(GL_TEXTURE_2D_ARRAY, GLuint(u.texture2DArray));
    glBindTexture(GL_TEXTURE_BUFFER, GLuint(u.textureBuffer));
    glBindSampler(GLuint(kTextureUnits[i]), GLuint(u.sampler));
  }
  glActiveTexture(GLenum(activeTexture_));
  glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
  glScissor(scissorBox_[0], scissorBox_[1], scissorBox_[2], scissorBox_[3]);
  glPixelStorei(GL_PACK_ALIGNMENT, packAlignment_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, unpackAlignment_);
  glPixelStorei(GL_PACK_ROW_LENGTH, packRowLength_);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, unpackRowLength_);
  glBlendFuncSeparate(GLenum(blendSrcRgb_), GLenum(blendDstRgb_), GLenum(blendSrcAlpha_),
                      GLenum(blendDstAlpha_));
  glBlendEquationSeparate(GLenum(blendEqRgb_), GLenum(blendEqAlpha_));
  glDepthFunc(GLenum(depthFunc_));
  glCullFace(GLenum(cullFaceMode_));
  glDepthMask(depthMask_);
  glColorMask(colorMask_[0], colorMask_[1], colorMask_[2], colorMask_[3]);
  glClearColor(clearColor_[0], clearColor_[1], clearColor_[2], clearColor_[3]);
  glBlendColor(blendColor_[0], blendColor_[1], blendColor_[2], blendColor_[3]);
  glClearDepth(clearDepth_);
  glDepthRange(depthRange_[0], depthRange_[1]);
  glClipControl(GLenum(clipOrigin_), GLenum(clipDepth_));
  glPolygonMode(GL_FRONT_AND_BACK, GLenum(polygonMode_[0]));
  setEnabled(GL_DEPTH_CLAMP, depthClamp_);
  setEnabled(GL_POLYGON_OFFSET_FILL, polygonOffsetFill_);
  setEnabled(GL_BLEND, blend_);
  setEnabled(GL_DEPTH_TEST, depthTest_);
  setEnabled(GL_CULL_FACE, cullFace_);
  setEnabled(GL_SCISSOR_TEST, scissorTest_);
  setEnabled(GL_STENCIL_TEST, stencilTest_);
  setEnabled(GL_PROGRAM_POINT_SIZE, programPointSize_);
  setEnabled(GL_FRAMEBUFFER_SRGB, framebufferSrgb_);
}

}  // namespace subsplat::gl
