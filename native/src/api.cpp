// The C API: every entry point validates its input, catches everything and
// turns it into a status plus a message (STYLE.md, Embree's model).
#include <glm/gtc/type_ptr.hpp>

#include <dlfcn.h>

#include <cmath>
#include <new>
#include <string>
#include <utility>

#include "material/splat_kernel.h"
#include "renderer.h"
#include "scene_file.h"
#include "subsplat/subsplat.h"
#include "util/error.h"

struct SsContext_ {
  static constexpr uint64_t kMagic = 0x5355425350'4c4154ull;
  uint64_t magic = kMagic;
  subsplat::Renderer renderer;
};

namespace {

thread_local std::string lastError;

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
  if (context->magic != SsContext_::kMagic)
    subsplat::fail(SS_INVALID_HANDLE, "context is not a live subsplat context");
  return context->renderer;
}

// GL calls without a current context crash inside the driver, so ask the
// window-system layers (whichever the host loaded) before touching GL.
void requireGlContext() {
  using GetCurrent = void* (*)();
  const std::pair<const char*, const char*> layers[] = {{"libEGL.so.1", "eglGetCurrentContext"},
                                                        {"libGLX.so.0", "glXGetCurrentContext"},
                                                        {"libGL.so.1", "glXGetCurrentContext"}};
  bool current = false;
  for (const auto& [library, function] : layers) {
    void* handle = dlopen(library, RTLD_LAZY | RTLD_NOLOAD);  // only if already loaded
    if (!handle) continue;
    auto get = reinterpret_cast<GetCurrent>(dlsym(handle, function));
    current = current || (get != nullptr && get() != nullptr);
    dlclose(handle);
  }
  if (!current) subsplat::fail(SS_GL_ERROR, "no OpenGL context is current on this thread");
  if (glGetString(GL_VERSION) == nullptr) subsplat::fail(SS_GL_ERROR, "no OpenGL context is current");
}

template <typename T>
const T& deref(const T* p, const char* what) {
  if (p == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, std::string(what) + " is NULL");
  return *p;
}

}  // namespace

extern "C" {

int32_t ssGetApiVersion(void) { return SS_API_VERSION; }

const char* ssGetLastError(void) { return lastError.c_str(); }

SsStatus ssNewContext(SsContext* out) {
  return guarded("ssNewContext", [&] {
    if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
    *out = nullptr;
    requireGlContext();
    *out = new SsContext_();
  });
}

SsStatus ssReleaseContext(SsContext context) {
  return guarded("ssReleaseContext", [&] {
    renderer(context);
    context->magic = 0;
    delete context;
  });
}

SsStatus ssSetMaterial(SsContext context, uint32_t id, const SsMaterialDesc* material) {
  return guarded("ssSetMaterial", [&] {
    renderer(context).scene().setMaterial(id, deref(material, "material"));
  });
}

SsStatus ssSetMesh(SsContext context, uint32_t objectId, const SsMeshDesc* mesh) {
  return guarded("ssSetMesh", [&] {
    subsplat::gl::StateGuard guard;
    renderer(context).scene().setMesh(objectId, deref(mesh, "mesh"));
  });
}

SsStatus ssRemoveMesh(SsContext context, uint32_t objectId) {
  return guarded("ssRemoveMesh", [&] { renderer(context).scene().removeMesh(objectId); });
}

SsStatus ssClearScene(SsContext context) {
  return guarded("ssClearScene", [&] { renderer(context).scene().clear(); });
}

SsStatus ssSetLights(SsContext context, const SsLightDesc* lights, uint32_t count) {
  return guarded("ssSetLights", [&] { renderer(context).scene().setLights(lights, count); });
}

SsStatus ssSetCamera(SsContext context, const SsCameraDesc* camera) {
  return guarded("ssSetCamera", [&] { renderer(context).scene().setCamera(deref(camera, "camera")); });
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
  return guarded("ssRender", [&] { renderer(context).render(width, height, rgba); });
}

SsStatus ssGetStats(SsContext context, SsStats* out) {
  return guarded("ssGetStats", [&] {
    if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
    *out = renderer(context).stats();
  });
}

SsStatus ssGetPass(SsContext context, int32_t pass, int32_t width, int32_t height, float* rgba) {
  return guarded("ssGetPass", [&] { renderer(context).readPass(pass, width, height, rgba); });
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
    subsplat::Renderer& r = renderer(context);
    const char* p = &deref(path, "path");
    requireGlContext();
    subsplat::gl::StateGuard guard;
    subsplat::FrameSize frame = subsplat::loadScene(r, p);
    if (frameWidth) *frameWidth = frame.width;
    if (frameHeight) *frameHeight = frame.height;
  });
}

SsStatus ssGetProfileInfo(const SsMaterialDesc* material, SsProfileInfo* out) {
  return guarded("ssGetProfileInfo", [&] {
    const SsMaterialDesc& m = deref(material, "material");
    if (out == nullptr) subsplat::fail(SS_INVALID_ARGUMENT, "out is NULL");
    subsplat::validateMaterial(m);
    if (m.kind != SS_MATERIAL_DIPOLE) subsplat::fail(SS_INVALID_ARGUMENT, "material is not translucent");
    subsplat::DipoleMaterial dipole = subsplat::dipoleMaterial(m);
    *out = SsProfileInfo{};
    double support = 0.0;
    for (int c = 0; c < 3; ++c) {
      subsplat::Dipole d(dipole.channels[c]);
      out->total_reflectance[c] = float(d.totalReflectance());
      out->effective_range[c] =
          float(d.radiusForEnergy(subsplat::SplatKernel::kEffectiveRangeEnergy) / m.mm_per_unit);
      support = std::max(support, d.radiusForEnergy(subsplat::SplatKernel::kSupportEnergy) / m.mm_per_unit);
    }
    out->support_radius = float(support);
  });
}

}  // extern "C"
