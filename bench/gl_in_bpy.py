"""Does a RenderEngine with bl_use_gpu_context get an OpenGL context in background mode, in Debian's
Blender and in the `bpy` module (docs/VERSIONS.md, "GL inside the bpy module")?

    build/bpy-<version>/bin/python bench/gl_in_bpy.py
    blender -b --factory-startup --python bench/gl_in_bpy.py

A minimal engine asks, inside render(), for EGL's current context and display and GL's vendor,
renderer and version (through the system's libEGL and libOpenGL, as libsubsplat does through
libepoxy), and draws nothing; the same questions are asked outside render(), where the gpu module is not yet
started in background mode (its functions raise "not available in background mode" or crash 3.4), so
gpu.platform is asked only inside render(). Prints one line
per question; exits 1 when render() had no current GL context.
"""
import ctypes
import os
import sys

import bpy
import gpu

GL_VENDOR, GL_RENDERER, GL_VERSION = 0x1F00, 0x1F01, 0x1F02
egl = ctypes.CDLL("libEGL.so.1")
egl.eglGetCurrentContext.restype = ctypes.c_void_p
egl.eglGetCurrentDisplay.restype = ctypes.c_void_p
opengl = ctypes.CDLL("libOpenGL.so.0")
opengl.glGetString.restype = ctypes.c_char_p
opengl.glGetString.argtypes = [ctypes.c_uint]
found = {}


def ask(where):
    context = egl.eglGetCurrentContext()
    answer = {"egl_context": hex(context) if context else None}
    if context:
        answer.update({name: (opengl.glGetString(code) or b"").decode()
                       for name, code in (("vendor", GL_VENDOR), ("renderer", GL_RENDERER), ("version", GL_VERSION))})
    found[where] = answer
    print(f"{where}: {answer}", flush=True)


class GLProbe(bpy.types.RenderEngine):
    bl_idname = "GL_PROBE"
    bl_label = "GL Probe"
    bl_use_gpu_context = True

    def render(self, depsgraph):
        ask("inside render()")
        if found["inside render()"]["egl_context"]:
            backend = gpu.platform.backend_type_get() if hasattr(gpu.platform, "backend_type_get") else "OPENGL"
            print(f"gpu.platform inside render(): {backend}, {gpu.platform.renderer_get()}, "
                  f"{gpu.platform.version_get()}", flush=True)
        scene = depsgraph.scene
        result = self.begin_result(0, 0, scene.render.resolution_x, scene.render.resolution_y)
        self.end_result(result)


def main():
    print(f"Blender {bpy.app.version_string}, {'bpy module' if not bpy.app.binary_path else bpy.app.binary_path}, "
          f"background {bpy.app.background}", flush=True)
    ask("outside render()")
    bpy.utils.register_class(GLProbe)
    scene = bpy.context.scene
    scene.render.engine = "GL_PROBE"
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 8, 8, 100
    bpy.ops.render.render()
    bpy.utils.unregister_class(GLProbe)
    ok = bool(found.get("inside render()", {}).get("egl_context"))
    print("GL context inside render(): " + ("yes" if ok else "NO"), flush=True)
    sys.stdout.flush()
    os._exit(0 if ok else 1)  # os._exit: the 4.2.23 module can crash at exit (docs/VERSIONS.md)


main()
