#include "testing/egl_context.h"

#include <dlfcn.h>
#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <link.h>

#include <cstring>
#include <stdexcept>
#include <vector>

namespace subsplat::testing {

struct EglContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

namespace {

// Keeps the GL driver's libraries loaded until the process ends (RTLD_NODELETE), so that
// LeakSanitizer names their frames at exit and tests/sanitizers/lsan.supp can leave the
// driver's own leaks out; unloaded, they show as "<unknown module>", like a leak of ours would.
void keepDriverLoaded() {
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void*) {
        const char* name = info->dlpi_name;
        if (name && (std::strstr(name, "_dri.so") || std::strstr(name, "libgallium") || std::strstr(name, "libLLVM") ||
                     std::strstr(name, "libEGL_mesa") || std::strstr(name, "libglapi"))) {
          if (void* handle = dlopen(name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE)) dlclose(handle);
        }
        return 0;
      },
      nullptr);
}

// Displays to try, in order: Mesa's surfaceless platform (llvmpipe and Mesa
// GPU drivers), the first EGL device (NVIDIA's headless driver), the default.
std::vector<EGLDisplay> candidateDisplays() {
  std::vector<EGLDisplay> displays;
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (getPlatformDisplay) {
    displays.push_back(getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr));
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    EGLDeviceEXT devices[8];
    EGLint count = 0;
    if (queryDevices && queryDevices(8, devices, &count) && count > 0)
      displays.push_back(getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr));
  }
  displays.push_back(eglGetDisplay(EGL_DEFAULT_DISPLAY));
  return displays;
}

}  // namespace

EglContext::EglContext() : impl_(std::make_unique<Impl>()) {
  for (EGLDisplay display : candidateDisplays()) {
    if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr)) {
      impl_->display = display;
      break;
    }
  }
  if (impl_->display == EGL_NO_DISPLAY) throw std::runtime_error("EGL: no display");
  if (!eglBindAPI(EGL_OPENGL_API)) throw std::runtime_error("EGL: no desktop OpenGL");
  const EGLint config[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                           EGL_NONE};
  EGLConfig chosen = nullptr;
  EGLint count = 0;
  eglChooseConfig(impl_->display, config, &chosen, 1, &count);
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_NONE};
  impl_->context = eglCreateContext(impl_->display, count > 0 ? chosen : EGL_NO_CONFIG_KHR,
                                    EGL_NO_CONTEXT, attributes);
  if (impl_->context == EGL_NO_CONTEXT) throw std::runtime_error("EGL: cannot create a GL 4.5 context");
  if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
    throw std::runtime_error("EGL: cannot make the context current");
  keepDriverLoaded();
}

EglContext::~EglContext() {
  eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(impl_->display, impl_->context);
  eglTerminate(impl_->display);
}

bool EglContext::makeCurrent() const {
  return eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context) == EGL_TRUE;
}

std::string EglContext::renderer() const {
  return reinterpret_cast<const char*>(glGetString(GL_RENDERER));
}

}  // namespace subsplat::testing
