"""SubSplat: real-time translucent materials by multiresolution splatting (Chen et al. 2012).

Layout (as BlendLuxCore's): engine/ (the RenderEngine: final, preview, viewport), export/ (Blender
data to plain data), native.py (plain data to the C library), properties.py, preferences.py, ui.py,
operators.py, twin.py (the Cycles twin); diagnostics.py (test hooks, last_* figures) and version.py (Blender version switches).
"""

bl_info = {
    "name": "SubSplat",
    "author": "subsplat developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > Render Engine > SubSplat",
    "description": "Real-time subsurface scattering for deforming translucent objects",
    "category": "Render",
}

if "bpy" in locals():
    import importlib
    for _module in (version, diagnostics, native, presets, properties, preferences, principled,  # noqa: F821
                    artist, export.data, export.camera, export.lights, export.materials,  # noqa: F821
                    export.mesh, export.settings, export, engine.viewport, engine.final,  # noqa: F821
                    engine.preview, engine, twin, operators, ui):  # noqa: F821
        importlib.reload(_module)

import bpy  # noqa: E402,F401

from . import (version, diagnostics, native, presets, properties, preferences, principled, artist,  # noqa: E402,F401
               export, engine, twin, operators, ui)
from .diagnostics import (last_render_error, last_render_passes, last_render_stats, last_viewport,  # noqa: E402,F401
                          last_viewport_first_sample)


def register():
    native.preload()
    properties.register()
    preferences.register()
    engine.register()
    operators.register()
    ui.register()


def unregister():
    ui.unregister()
    operators.unregister()
    engine.unregister()
    preferences.unregister()
    properties.unregister()
