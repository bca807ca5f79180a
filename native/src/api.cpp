// The C API: every entry point validates its input, catches everything and
// turns it into a status plus a message (STYLE.md, Embree's model).
#include <glm/gtc/type_ptr.hpp>

#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <unordered_set>
#include <utility>

#include "gl/gl.h"
#include "gl/state_report.h"
#include "material/profile_set.h"
#include "material/splat_kernel.h"
#include "material/transport_model.h"
#include "renderer.h"
#include "scene_file.h"
#include "subsplat/subsplat.h"
#include "util/error.h"

namespace {

// Live handles of each kind (ssGetResourceCounts).
template <typename Handle>
struct Counted {
  Counted() { live.fetch_add(1, std::memory_order_relaxed); }
  ~Counted() { live.fetch_sub(1, std::memory_order_relaxed); }
  Counted(const Counted&) = delete;
  Counted& operator=(const Counted&) = delete;
  inline static std::atomic<int64_t> live{0};
};

// The handles of one kind that are alive now. A handle is looked up here before it is read, so a
// released (freed) or foreign pointer is refused without touching its memory: releasing twice is an
// error, not a use after free.
template <typename Handle>
class Registry {
 public:
  void add(const Handle* handle) {
    std::lock_guard<std::mutex> lock(mutex_);
    live_.insert(handle);
  }
  bool contains(const Handle* handle) {
    std::lock_guard<std::mutex> lock(mutex_);
    return live_.count(handle) != 0;
  }
  // False when the handle was not live.
  bool remove(const Handle* handle) {
    std::lock_guard<std::mutex> lock(mutex_);
    return live_.erase(handle) != 0;
  }

 private:
  std::mutex mutex_;
  std::unordered_set<const Handle*> live_;
};

}  // namespace

struct SsContext_ : Counted<SsContext_> {
  void* glContext = nullptr;  // the OpenGL context current at ssNewContext, which owns the GL objects
  subsplat::Renderer renderer;
};

struct SsProfileSet_ : Counted<SsProfileSet_> {
  std::shared_ptr<const subsplat::ProfileSet> set;
};

struct SsImage_ : Counted<SsImage_> {
  std::shared_ptr<const subsplat::TextureImage> image;
};

namespace {

thread_local std::string lastError;

Registry<SsContext_> liveContexts;
Registry<SsProfileSet_> liveProfileSets;
Registry<SsImage_> liveImages;

template <typename F>
SsStatus guarded(const char* entry, F&& body) {
  try {
    body();
    lastError.clear();
    return SS_OK;
  } catch (const subsplat::Error& e) {
    lastError = std::string(entry) + ": " + e.what();
    return e.status();
  } catch (const std::bad_alloc&) {
    lastError = std::string(entry) + ": out of memory";
    return SS_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    lastError = std::string(entry) + ": internal error: " + e.what();
    return SS_INTERNAL_ERROR;
  } catch (...) {
    lastError = std::string(entry) + ": unknown internal error";
    return SS_INTERNAL_ERROR;
  }
}

subsplat::Renderer& renderer(SsContext context) {
  if (context == nullptr) subsplat::fail(SS_INVALID_HANDLE, "context is NULL");
  if (!liveContexts.contains(context))
    subsplat::fail(SS_INVALID_HANDLE, "context is not a live subsplat context (released already, or never made)");
  return context->renderer;
}

// The OpenGL context current on this thread, asked of the window-system layers
// (whichever the host loaded: EGL or GLX), or nullptr.
void* currentGlContext() {
  using GetCurrent = void* (*)();
  const std::pair<const char*, const char*> layers[] = {{"libEGL.so.1", "eglGetCurrentContext"},
                                                        {"libGLX.so.0", "glXGetCurrentContext"},
                                                        {"libGL.so.1", "glXGetCurrentContext"}};
  void* current = nullptr;
  for (const auto& [library, function] : layers) {
    void* handle = dlopen(library, RTLD_LAZY | RTLD_NOLOAD);  // only if already loaded
    if (!handle) continue;
    auto get = reinterpret_cast<GetCurrent>(dlsym(handle, function));
    if (current == nullptr && get != nullptr) current = get();
    dlclose(handle);
  }
  return current;
}

// GL calls without a current context crash inside the driver: ask before touching GL.
void* requireGlContext() {
  void* current = currentGlContext();
  if (current == nullptr) subsplat::fail(SS_GL_ERROR, "no OpenGL context is current on this thread");
  if (glGetString(GL_VERSION) == nullptr) subsplat::fail(SS_GL_ERROR, "no OpenGL context is current");
  return current;
}

// A context whose entry point issues GL: its own OpenGL context must be current, since the
// names of its vertex arrays and framebuffers mean other objects, or nothing, in any other.
subsplat::Renderer& ownRenderer(SsContext context) {
  subsplat::Renderer& r = renderer(context);
  void* current = currentGlContext();
  if (current == nullptr) subsplat::fail(SS_GL_ERROR, "no OpenGL context is current on this thread");
  if (current != context->glContext)
    subsplat::fail(SS_GL_ERROR, "the OpenGL context current now is not the one this context was created in");
  subsplat::gl::deleteOrphans(current);
  return r;
}

std::shared_ptr<const subsplat::ProfileSet> profileSet(SsProfileSet handle, const std::string& what) {
  if (handle == nullptr) subsplat::fail(SS_INVALID_HANDLE, what + " is NULL");
  if (!liveProfileSets.contains(handle))
    subsplat::fail(SS_INVALID_HANDLE, what + " is not a live subsplat profile set (released already, or never made)");
  return handle->set;
}

std::shared_ptr<const subsplat::TextureImage> textureImage(SsImage handle, const std::string& what) {
  if (handle == nullptr) return nullptr;
  if (!liveImages.contains(handle))
    subsplat::fail(SS_INVALID_HANDLE, what + " is not a live subsplat image (released already, or never made)");
  return handle->image;
}

double tolerance(float value) {
  if (value == 0.0f) return subsplat::ProfileSet::kDefaultTolerance;
  return value;  // checked by the profile set
}

void newProfileSet(SsProfileSet* out, const std::function<subsplat::ProfileSet()>& make) {
  if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
  *out = nullptr;
  auto handle = std::make_unique<SsProfileSet_>();
  handle->set = std::make_shared<const subsplat::ProfileSet>(make());
  liveProfileSets.add(handle.get());
  *out = handle.release();
}

// One row of ssGetStructLayout's table: a struct of the header, or one of its fields (field "").
struct LayoutEntry {
  const char* type;
  const char* field;
  size_t offset, size;
};

#define SS_STRUCT(T) LayoutEntry{#T, "", 0, sizeof(T)}
#define SS_FIELD(T, f) LayoutEntry{#T, #f, offsetof(T, f), sizeof(T::f)}

// Every struct of subsplat.h and every field of each.
const LayoutEntry kLayouts[] = {
    SS_STRUCT(SsMeshDesc),
    SS_FIELD(SsMeshDesc, positions),
    SS_FIELD(SsMeshDesc, normals),
    SS_FIELD(SsMeshDesc, uvs),
    SS_FIELD(SsMeshDesc, vertex_count),
    SS_FIELD(SsMeshDesc, indices),
    SS_FIELD(SsMeshDesc, triangle_materials),
    SS_FIELD(SsMeshDesc, triangle_count),
    SS_FIELD(SsMeshDesc, default_material),
    SS_FIELD(SsMeshDesc, object_to_world),
    SS_STRUCT(SsMaterialDesc),
    SS_FIELD(SsMaterialDesc, kind),
    SS_FIELD(SsMaterialDesc, base_color),
    SS_FIELD(SsMaterialDesc, sigma_a),
    SS_FIELD(SsMaterialDesc, sigma_s_prime),
    SS_FIELD(SsMaterialDesc, eta),
    SS_FIELD(SsMaterialDesc, mm_per_unit),
    SS_FIELD(SsMaterialDesc, roughness),
    SS_FIELD(SsMaterialDesc, specular),
    SS_FIELD(SsMaterialDesc, profile_model),
    SS_FIELD(SsMaterialDesc, profiles),
    SS_FIELD(SsMaterialDesc, color_texture),
    SS_FIELD(SsMaterialDesc, normal_texture),
    SS_FIELD(SsMaterialDesc, normal_strength),
    SS_STRUCT(SsTextureDesc),
    SS_FIELD(SsTextureDesc, image),
    SS_FIELD(SsTextureDesc, transform),
    SS_FIELD(SsTextureDesc, extension),
    SS_FIELD(SsTextureDesc, interpolation),
    SS_STRUCT(SsEnvironmentDesc),
    SS_FIELD(SsEnvironmentDesc, image),
    SS_FIELD(SsEnvironmentDesc, rotation),
    SS_FIELD(SsEnvironmentDesc, strength),
    SS_STRUCT(SsImageDesc),
    SS_FIELD(SsImageDesc, width),
    SS_FIELD(SsImageDesc, height),
    SS_FIELD(SsImageDesc, rgb),
    SS_STRUCT(SsLightDesc),
    SS_FIELD(SsLightDesc, type),
    SS_FIELD(SsLightDesc, color),
    SS_FIELD(SsLightDesc, strength),
    SS_FIELD(SsLightDesc, position),
    SS_FIELD(SsLightDesc, direction),
    SS_FIELD(SsLightDesc, spot_size),
    SS_FIELD(SsLightDesc, spot_blend),
    SS_FIELD(SsLightDesc, world_directions),
    SS_FIELD(SsLightDesc, area_shape),
    SS_FIELD(SsLightDesc, area_axis),
    SS_FIELD(SsLightDesc, area_size),
    SS_FIELD(SsLightDesc, soft_size),
    SS_FIELD(SsLightDesc, world_below),
    SS_FIELD(SsLightDesc, world_sh),
    SS_STRUCT(SsCameraDesc),
    SS_FIELD(SsCameraDesc, world_to_view),
    SS_FIELD(SsCameraDesc, view_to_clip),
    SS_FIELD(SsCameraDesc, orthographic),
    SS_STRUCT(SsSettings),
    SS_FIELD(SsSettings, method),
    SS_FIELD(SsSettings, irradiance_resolution),
    SS_FIELD(SsSettings, background),
    SS_FIELD(SsSettings, reference_samples),
    SS_FIELD(SsSettings, levels),
    SS_FIELD(SsSettings, z0_factor),
    SS_FIELD(SsSettings, alpha),
    SS_FIELD(SsSettings, epsilon),
    SS_FIELD(SsSettings, lambda_z),
    SS_FIELD(SsSettings, lambda_m),
    SS_FIELD(SsSettings, debug_passes),
    SS_FIELD(SsSettings, target_error),
    SS_FIELD(SsSettings, samples),
    SS_FIELD(SsSettings, filter_width),
    SS_FIELD(SsSettings, first_sample),
    SS_FIELD(SsSettings, shadow_resolution),
    SS_FIELD(SsSettings, precomputed_atlas),
    SS_FIELD(SsSettings, forward_shift),
    SS_STRUCT(SsStats),
    SS_FIELD(SsStats, frame_ms),
    SS_FIELD(SsStats, stage_ms),
    SS_FIELD(SsStats, fragment_invocations),
    SS_FIELD(SsStats, splat_count),
    SS_FIELD(SsStats, width),
    SS_FIELD(SsStats, height),
    SS_FIELD(SsStats, light_views),
    SS_FIELD(SsStats, timers_available),
    SS_FIELD(SsStats, statistics_available),
    SS_FIELD(SsStats, translucent_pixels),
    SS_FIELD(SsStats, lit_translucent_pixels),
    SS_FIELD(SsStats, nonfinite_pixels),
    SS_FIELD(SsStats, kernel_evaluations),
    SS_FIELD(SsStats, levels),
    SS_FIELD(SsStats, selected_per_level),
    SS_FIELD(SsStats, splat_levels),
    SS_FIELD(SsStats, splat_level_ms),
    SS_FIELD(SsStats, splat_level_fragments),
    SS_FIELD(SsStats, accumulation_ms),
    SS_FIELD(SsStats, accumulation_fragments),
    SS_FIELD(SsStats, irradiance_resolution),
    SS_FIELD(SsStats, texels_per_range),
    SS_FIELD(SsStats, samples),
    SS_FIELD(SsStats, shadow_resolution),
    SS_FIELD(SsStats, splatting_complete),
    SS_FIELD(SsStats, splatting_progress),
    SS_FIELD(SsStats, target_reachable),
    SS_FIELD(SsStats, precompute_ms),
    SS_FIELD(SsStats, transport_reused),
    SS_FIELD(SsStats, transport_full_pipeline),
    SS_FIELD(SsStats, precomputed_bytes),
    SS_FIELD(SsStats, precomputed_texels),
    SS_FIELD(SsStats, precomputed_factors),
    SS_FIELD(SsStats, relight_ms),
    SS_FIELD(SsStats, selection_ms),
    SS_STRUCT(SsPrecomputedObject),
    SS_FIELD(SsPrecomputedObject, object_id),
    SS_FIELD(SsPrecomputedObject, vertices),
    SS_FIELD(SsPrecomputedObject, bytes),
    SS_FIELD(SsPrecomputedObject, texels),
    SS_FIELD(SsPrecomputedObject, kernel_taps),
    SS_FIELD(SsPrecomputedObject, factors),
    SS_FIELD(SsPrecomputedObject, atlas_width),
    SS_FIELD(SsPrecomputedObject, atlas_height),
    SS_FIELD(SsPrecomputedObject, texel_size),
    SS_FIELD(SsPrecomputedObject, local_range),
    SS_FIELD(SsPrecomputedObject, precompute_ms),
    SS_FIELD(SsPrecomputedObject, charts),
    SS_FIELD(SsPrecomputedObject, uv_charts),
    SS_FIELD(SsPrecomputedObject, uv_islands_refused),
    SS_STRUCT(SsResourceCounts),
    SS_FIELD(SsResourceCounts, contexts),
    SS_FIELD(SsResourceCounts, profile_sets),
    SS_FIELD(SsResourceCounts, images),
    SS_FIELD(SsResourceCounts, textures),
    SS_FIELD(SsResourceCounts, buffers),
    SS_FIELD(SsResourceCounts, framebuffers),
    SS_FIELD(SsResourceCounts, vertex_arrays),
    SS_FIELD(SsResourceCounts, programs),
    SS_FIELD(SsResourceCounts, queries),
    SS_FIELD(SsResourceCounts, orphaned_gl_objects),
    SS_STRUCT(SsProfileSetDesc),
    SS_FIELD(SsProfileSetDesc, segments),
    SS_FIELD(SsProfileSetDesc, radius_mm),
    SS_FIELD(SsProfileSetDesc, width),
    SS_FIELD(SsProfileSetDesc, height),
    SS_FIELD(SsProfileSetDesc, log_profiles),
    SS_STRUCT(SsProfileSetInfo),
    SS_FIELD(SsProfileSetInfo, segments),
    SS_FIELD(SsProfileSetInfo, profiles),
    SS_FIELD(SsProfileSetInfo, width),
    SS_FIELD(SsProfileSetInfo, height),
    SS_FIELD(SsProfileSetInfo, radius_mm),
    SS_FIELD(SsProfileSetInfo, fit_error),
    SS_FIELD(SsProfileSetInfo, max_fit_error),
    SS_FIELD(SsProfileSetInfo, effective_range_mm),
    SS_FIELD(SsProfileSetInfo, gpu_bytes),
    SS_FIELD(SsProfileSetInfo, source_segments),
    SS_FIELD(SsProfileSetInfo, source_profiles),
    SS_STRUCT(SsProfileInfo),
    SS_FIELD(SsProfileInfo, total_reflectance),
    SS_FIELD(SsProfileInfo, effective_range),
    SS_FIELD(SsProfileInfo, support_radius),
};

#undef SS_FIELD
#undef SS_STRUCT

template <typename T>
const T& deref(const T* p, const char* what) {
  if (p == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, std::string(what) + " is NULL");
  return *p;
}

}  // namespace

extern "C" {

int32_t ssGetApiVersion(void) { return SS_API_VERSION; }

const char* ssGetLastError(void) { return lastError.c_str(); }

SsStatus ssGetStructLayout(const char* type, const char* field, uint32_t* offset, uint32_t* size) {
  return guarded("ssGetStructLayout", [&] {
    if (offset == nullptr || size == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "offset or size is NULL");
    *offset = 0;
    *size = 0;
    const char* typeName = &deref(type, "type");
    const char* fieldName = field != nullptr ? field : "";
    bool knownType = false;
    for (const LayoutEntry& entry : kLayouts) {
      if (std::strcmp(entry.type, typeName) != 0) continue;
      knownType = true;
      if (std::strcmp(entry.field, fieldName) != 0) continue;
      *offset = uint32_t(entry.offset);
      *size = uint32_t(entry.size);
      return;
    }
    if (!knownType) subsplat::fail(SS_INVALID_ARGUMENT, "unknown struct '" + std::string(typeName) + "'");
    subsplat::fail(SS_INVALID_ARGUMENT,
                   "struct " + std::string(typeName) + " has no field '" + std::string(fieldName) + "'");
  });
}

SsSettings ssDefaultSettings(void) {
  using subsplat::Renderer;
  SsSettings s{};
  s.method = SS_METHOD_BRUTE;
  s.irradiance_resolution = 512;
  s.reference_samples = Renderer::kDefaultReferenceSamples;
  s.levels = Renderer::kDefaultLevels;
  s.z0_factor = Renderer::kDefaultZ0Factor;
  s.alpha = Renderer::kDefaultAlpha;
  s.epsilon = Renderer::kDefaultEpsilon;
  s.lambda_z = Renderer::kDefaultLambda;
  s.lambda_m = Renderer::kDefaultLambda;
  s.debug_passes = 0;
  s.target_error = Renderer::kDefaultTargetError;
  s.samples = 1;
  s.filter_width = Renderer::kDefaultFilterWidth;
  s.first_sample = 0;
  return s;
}

SsStatus ssGetResourceCounts(SsResourceCounts* out) {
  return guarded("ssGetResourceCounts", [&] {
    if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
    namespace gl = subsplat::gl;
    *out = SsResourceCounts{};
    out->contexts = Counted<SsContext_>::live;
    out->profile_sets = Counted<SsProfileSet_>::live;
    out->images = Counted<SsImage_>::live;
    out->textures = gl::Texture::live();
    out->buffers = gl::Buffer::live();
    out->framebuffers = gl::Framebuffer::live();
    out->vertex_arrays = gl::VertexArray::live();
    out->programs = gl::Program::live();
    out->queries = gl::Query::live();
    out->orphaned_gl_objects = gl::orphanedObjects();
  });
}

SsStatus ssSetMemoryBudget(uint64_t bytes) {
  return guarded("ssSetMemoryBudget", [&] {
    if (bytes != 0 && bytes < (uint64_t(1) << 20))
      subsplat::fail(SS_INVALID_ARGUMENT, "memory budget must be 0 (automatic) or at least 1 MiB, got " +
                                              std::to_string(bytes) + " bytes");
    subsplat::gl::setMemoryBudget(bytes);
  });
}

SsStatus ssGetMemoryUsage(uint64_t* used, uint64_t* budget) {
  return guarded("ssGetMemoryUsage", [&] {
    if (used == nullptr || budget == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "used or budget is NULL");
    *used = subsplat::gl::gpuBytes();
    // The automatic budget asks the driver once, with a context current.
    *budget = subsplat::gl::memoryBudgetKnown() || currentGlContext() != nullptr ? subsplat::gl::memoryBudget() : 0;
  });
}

SsStatus ssDescribeGlState(char* buffer, uint32_t capacity, uint32_t* length) {
  return guarded("ssDescribeGlState", [&] {
    if (length) *length = 0;
    if (buffer == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "buffer is NULL");
    requireGlContext();
    const std::string text = subsplat::gl::describeState();
    if (length) *length = uint32_t(text.size());
    if (text.size() + 1 > capacity)
      subsplat::fail(SS_LIMIT_EXCEEDED, "buffer of " + std::to_string(capacity) + " bytes is too small for " +
                                            std::to_string(text.size() + 1));
    std::copy(text.begin(), text.end(), buffer);
    buffer[text.size()] = '\0';
  });
}

SsStatus ssNewContext(SsContext* out) {
  return guarded("ssNewContext", [&] {
    if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
    *out = nullptr;
    void* glContext = requireGlContext();
    subsplat::gl::deleteOrphans(glContext);
    auto context = std::make_unique<SsContext_>();
    context->glContext = glContext;
    liveContexts.add(context.get());
    *out = context.release();
  });
}

SsStatus ssReleaseContext(SsContext context) {
  return guarded("ssReleaseContext", [&] {
    if (context == nullptr) subsplat::fail(SS_INVALID_HANDLE, "context is NULL");
    if (!liveContexts.remove(context))
      subsplat::fail(SS_INVALID_HANDLE, "context is not a live subsplat context (released already, or never made)");
    // GL names belong to the context that made them: deleted from any other, they would
    // delete the host's objects of the same names. Away from its own context, a context's GL
    // objects wait for it (deleted by the next call made there: ssNewContext, a render).
    void* current = currentGlContext();
    {
      subsplat::gl::OrphanScope orphans(context->glContext, current != context->glContext);
      delete context;
    }
    if (current != nullptr) subsplat::gl::deleteOrphans(current);
  });
}

SsStatus ssSetMaterial(SsContext context, uint32_t id, const SsMaterialDesc* material) {
  return guarded("ssSetMaterial", [&] {
    const SsMaterialDesc& m = deref(material, "material");
    subsplat::Scene& scene = ownRenderer(context).scene();
    const std::string name = "material " + std::to_string(id);
    subsplat::validateMaterial(m);
    scene.setMaterial(id, m, m.kind == SS_MATERIAL_SUBEDIT ? profileSet(m.profiles, name + ": profiles") : nullptr,
                      textureImage(m.color_texture.image, name + ": colour texture image"),
                      textureImage(m.normal_texture.image, name + ": normal texture image"));
  });
}

SsStatus ssSetMesh(SsContext context, uint32_t objectId, const SsMeshDesc* mesh) {
  return guarded("ssSetMesh", [&] {
    subsplat::gl::StateGuard guard;
    ownRenderer(context).scene().setMesh(objectId, deref(mesh, "mesh"));
  });
}

SsStatus ssRemoveMesh(SsContext context, uint32_t objectId) {
  return guarded("ssRemoveMesh", [&] { ownRenderer(context).scene().removeMesh(objectId); });
}

SsStatus ssClearScene(SsContext context) {
  return guarded("ssClearScene", [&] { ownRenderer(context).scene().clear(); });
}

SsStatus ssSetLights(SsContext context, const SsLightDesc* lights, uint32_t count) {
  return guarded("ssSetLights", [&] { renderer(context).scene().setLights(lights, count); });
}

SsStatus ssSetCamera(SsContext context, const SsCameraDesc* camera) {
  return guarded("ssSetCamera", [&] { renderer(context).setCamera(deref(camera, "camera")); });
}

SsStatus ssSetEnvironment(SsContext context, const SsEnvironmentDesc* environment) {
  return guarded("ssSetEnvironment", [&] {
    const SsEnvironmentDesc& e = deref(environment, "environment");
    subsplat::Scene& scene = renderer(context).scene();
    scene.setEnvironment(e, textureImage(e.image, "environment image"));
  });
}

SsStatus ssSetSettings(SsContext context, const SsSettings* settings) {
  return guarded("ssSetSettings", [&] { renderer(context).setSettings(deref(settings, "settings")); });
}

SsStatus ssGetSettings(SsContext context, SsSettings* out) {
  return guarded("ssGetSettings", [&] {
    if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
    *out = renderer(context).settings();
  });
}

SsStatus ssRender(SsContext context, int32_t width, int32_t height, float* rgba) {
  return guarded("ssRender", [&] { ownRenderer(context).render(width, height, rgba); });
}

SsStatus ssGetStats(SsContext context, SsStats* out) {
  return guarded("ssGetStats", [&] {
    if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
    *out = renderer(context).stats();
  });
}

SsStatus ssGetPrecomputedObjects(SsContext context, SsPrecomputedObject* out, uint32_t capacity, uint32_t* count) {
  return guarded("ssGetPrecomputedObjects", [&] {
    if (count == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "count is NULL");
    if (out == nullptr && capacity > 0) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL with a capacity of " + std::to_string(capacity));
    std::vector<SsPrecomputedObject> objects = renderer(context).precomputedObjects();
    *count = uint32_t(objects.size());
    for (size_t i = 0; i < objects.size() && i < capacity; ++i) out[i] = objects[i];
  });
}

SsStatus ssSetSplatBudget(SsContext context, uint64_t fragments) {
  return guarded("ssSetSplatBudget", [&] { renderer(context).setSplatBudget(fragments); });
}

SsStatus ssGetPass(SsContext context, int32_t pass, int32_t width, int32_t height, float* rgba) {
  return guarded("ssGetPass", [&] { ownRenderer(context).readPass(pass, width, height, rgba); });
}

SsStatus ssSetProgressCallback(SsContext context, SsProgressCallback callback, void* user) {
  return guarded("ssSetProgressCallback", [&] {
    subsplat::Renderer& r = renderer(context);
    if (callback == nullptr) {
      r.setProgress(nullptr);
      return;
    }
    r.setProgress([callback, user](double fraction) { return callback(float(fraction), user) == 0; });
  });
}

SsStatus ssSaveScene(SsContext context, const char* path) {
  return guarded("ssSaveScene", [&] {
    const subsplat::Renderer& r = renderer(context);
    subsplat::saveScene(r, &deref(path, "path"));
  });
}

SsStatus ssLoadScene(SsContext context, const char* path, int32_t* frameWidth, int32_t* frameHeight) {
  return guarded("ssLoadScene", [&] {
    if (frameWidth) *frameWidth = 0;
    if (frameHeight) *frameHeight = 0;
    const char* p = &deref(path, "path");
    subsplat::Renderer& r = ownRenderer(context);
    subsplat::gl::StateGuard guard;
    subsplat::FrameSize frame = subsplat::loadScene(r, p);
    if (frameWidth) *frameWidth = frame.width;
    if (frameHeight) *frameHeight = frame.height;
  });
}

SsStatus ssDipoleTotalReflectance(uint64_t count, const double* reduced_albedo, double eta, double* out) {
  return guarded("ssDipoleTotalReflectance", [&] {
    if (count > 0 && (reduced_albedo == nullptr || out == nullptr))
      subsplat::fail(SS_INVALID_ARGUMENT, "reduced_albedo or out is NULL");
    if (!(std::isfinite(eta) && eta > 0.0)) subsplat::fail(SS_INVALID_ARGUMENT, "eta must be positive, got " + std::to_string(eta));
    for (uint64_t i = 0; i < count; ++i)
      if (!(reduced_albedo[i] >= 0.0 && reduced_albedo[i] <= 1.0))
        subsplat::fail(SS_INVALID_ARGUMENT, "reduced albedo " + std::to_string(i) + " must be in [0, 1], got " +
                                                std::to_string(reduced_albedo[i]));
    for (uint64_t i = 0; i < count; ++i) out[i] = subsplat::dipoleTotalReflectance(reduced_albedo[i], eta);
  });
}

SsStatus ssTotalReflectance(int32_t profile_model, uint64_t count, const double* albedo, double eta, double* out) {
  return guarded("ssTotalReflectance", [&] {
    if (profile_model != SS_PROFILE_DIPOLE && profile_model != SS_PROFILE_TABULATED)
      subsplat::fail(SS_INVALID_ARGUMENT, "unknown profile model " + std::to_string(profile_model));
    if (count > 0 && (albedo == nullptr || out == nullptr)) subsplat::fail(SS_INVALID_ARGUMENT, "albedo or out is NULL");
    if (!(std::isfinite(eta) && eta > 0.0)) subsplat::fail(SS_INVALID_ARGUMENT, "eta must be positive, got " + std::to_string(eta));
    for (uint64_t i = 0; i < count; ++i)
      if (!(albedo[i] >= 0.0 && albedo[i] <= 1.0))
        subsplat::fail(SS_INVALID_ARGUMENT, "albedo " + std::to_string(i) + " must be in [0, 1], got " +
                                                std::to_string(albedo[i]));
    for (uint64_t i = 0; i < count; ++i)
      out[i] = profile_model == SS_PROFILE_TABULATED ? subsplat::tabulatedTotalReflectance(albedo[i], eta)
                                                     : subsplat::dipoleTotalReflectance(albedo[i], eta);
  });
}

SsStatus ssGetProfileInfo(const SsMaterialDesc* material, SsProfileInfo* out) {
  return guarded("ssGetProfileInfo", [&] {
    const SsMaterialDesc& m = deref(material, "material");
    if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
    subsplat::validateMaterial(m);
    if (m.kind == SS_MATERIAL_OPAQUE) subsplat::fail(SS_INVALID_ARGUMENT, "material is not translucent");
    std::shared_ptr<const subsplat::ProfileSet> set;
    std::vector<std::shared_ptr<const subsplat::RadialProfile>> channels;
    for (int c = 0; c < 3; ++c) {
      if (m.kind == SS_MATERIAL_SUBEDIT) {
        if (!set) set = profileSet(m.profiles, "material profiles");
        channels.push_back(std::make_shared<subsplat::SegmentedProfile>(set->channel(0, c)));
      } else {
        channels.push_back(subsplat::makeMediumProfile(subsplat::dipoleMaterial(m).channels[size_t(c)], m.profile_model));
      }
    }
    *out = SsProfileInfo{};
    double support = 0.0;
    for (int c = 0; c < 3; ++c) {
      const subsplat::RadialProfile& d = *channels[size_t(c)];
      out->total_reflectance[c] = float(d.totalEnergy());
      out->effective_range[c] =
          float(d.radiusForEnergy(subsplat::SplatKernel::kEffectiveRangeEnergy) / m.mm_per_unit);
      support = std::max(support, d.radiusForEnergy(subsplat::SplatKernel::kSupportEnergy) / m.mm_per_unit);
    }
    out->support_radius = float(support);
  });
}

SsStatus ssNewProfileSet(const SsProfileSetDesc* desc, float tol, SsProfileSet* out) {
  return guarded("ssNewProfileSet", [&] {
    const SsProfileSetDesc& d = deref(desc, "desc");
    newProfileSet(out, [&] {
      return subsplat::ProfileSet::fromTexels(int(std::min<uint32_t>(d.width, INT32_MAX)),
                                              int(std::min<uint32_t>(d.height, INT32_MAX)),
                                              int(std::min<uint32_t>(d.segments, INT32_MAX)), d.radius_mm,
                                              d.log_profiles, tolerance(tol));
    });
  });
}

SsStatus ssNewProfileSetFromDipoles(uint32_t width, uint32_t height, const float* sigmaA, const float* sigmaSPrime,
                                    float eta, float tol, int32_t profileModel, SsProfileSet* out) {
  return guarded("ssNewProfileSetFromDipoles", [&] {
    newProfileSet(out, [&] {
      return subsplat::ProfileSet::fromDipoles(int(std::min<uint32_t>(width, INT32_MAX)),
                                               int(std::min<uint32_t>(height, INT32_MAX)), sigmaA, sigmaSPrime, eta,
                                               tolerance(tol), profileModel);
    });
  });
}

SsStatus ssLoadProfileSet(const char* path, float tol, SsProfileSet* out) {
  return guarded("ssLoadProfileSet", [&] {
    const char* p = &deref(path, "path");
    newProfileSet(out, [&] { return subsplat::readSubEditFile(p, tolerance(tol)); });
  });
}

SsStatus ssSaveProfileSet(SsProfileSet set, const char* path) {
  return guarded("ssSaveProfileSet", [&] {
    std::shared_ptr<const subsplat::ProfileSet> s = profileSet(set, "set");
    subsplat::writeSubEditFile(*s, &deref(path, "path"));
  });
}

SsStatus ssGetProfileSetInfo(SsProfileSet set, SsProfileSetInfo* out) {
  return guarded("ssGetProfileSetInfo", [&] {
    std::shared_ptr<const subsplat::ProfileSet> s = profileSet(set, "set");
    if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
    const subsplat::ProfileSetInfo& i = s->info();
    *out = SsProfileSetInfo{};
    out->segments = uint32_t(i.segments);
    out->profiles = uint32_t(i.profiles);
    out->width = uint32_t(i.width);
    out->height = uint32_t(i.height);
    out->radius_mm = float(i.radiusMm);
    out->fit_error = float(i.fitError);
    out->max_fit_error = float(i.maxFitError);
    out->source_segments = uint32_t(i.sourceSegments);
    out->source_profiles = uint32_t(i.sourceProfiles);
    double shortest = 1e300, longest = 0.0;
    for (int p = 0; p < i.profiles; ++p)
      for (int c = 0; c < 3; ++c) {
        double r = s->channel(p, c).radiusForEnergy(subsplat::SplatKernel::kEffectiveRangeEnergy);
        shortest = std::min(shortest, r);
        longest = std::max(longest, r);
      }
    out->effective_range_mm[0] = float(shortest);
    out->effective_range_mm[1] = float(longest);
    out->gpu_bytes = uint64_t(i.profiles) * subsplat::SplatKernel::kSizeA * subsplat::SplatKernel::kSizeD * 4 *
                         sizeof(float) +
                     (i.profiles > 1 ? s->map().size() * sizeof(uint16_t) : 0);
  });
}

SsStatus ssReleaseProfileSet(SsProfileSet set) {
  return guarded("ssReleaseProfileSet", [&] {
    if (set == nullptr) subsplat::fail(SS_INVALID_HANDLE, "set is NULL");
    if (!liveProfileSets.remove(set))
      subsplat::fail(SS_INVALID_HANDLE, "set is not a live subsplat profile set (released already, or never made)");
    delete set;
  });
}

SsStatus ssNewImage(const SsImageDesc* desc, SsImage* out) {
  return guarded("ssNewImage", [&] {
    const SsImageDesc& d = deref(desc, "desc");
    if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
    *out = nullptr;
    auto handle = std::make_unique<SsImage_>();
    handle->image = std::make_shared<const subsplat::TextureImage>(d);
    liveImages.add(handle.get());
    *out = handle.release();
  });
}

SsStatus ssReleaseImage(SsImage image) {
  return guarded("ssReleaseImage", [&] {
    if (image == nullptr) subsplat::fail(SS_INVALID_HANDLE, "image is NULL");
    if (!liveImages.remove(image))
      subsplat::fail(SS_INVALID_HANDLE, "image is not a live subsplat image (released already, or never made)");
    delete image;
  });
}

}  // extern "C"
