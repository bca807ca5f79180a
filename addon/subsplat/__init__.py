"""SubSplat: real-time translucent materials by multiresolution splatting (Chen et al. 2012)."""

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
    for _module in (native, presets, properties, principled, artist, export, viewport, engine, operators, ui):  # noqa: F821
        importlib.reload(_module)

import bpy  # noqa: E402,F401

from . import native, presets, properties, principled, artist, export, viewport, engine, operators, ui  # noqa: E402,F401
from .engine import last_render_error, last_render_passes, last_render_stats, last_viewport  # noqa: E402,F401


def register():
    properties.register()
    engine.register()
    operators.register()
    ui.register()


def unregister():
    ui.unregister()
    operators.unregister()
    engine.unregister()
    properties.unregister()
