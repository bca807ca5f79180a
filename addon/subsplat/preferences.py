"""Edit > Preferences > Add-ons > SubSplat, and what the engine reads from it."""
import os

import bpy
from bpy.props import IntProperty


class SubsplatPreferences(bpy.types.AddonPreferences):
    """Edit > Preferences > Add-ons > SubSplat."""
    bl_idname = __package__

    memory_budget_mb: IntProperty(
        name="GPU Memory Budget (MiB)", default=0, min=0, max=1 << 24,
        description="GPU memory SubSplat may use for meshes and buffers; a scene beyond it fails with an "
                    "error naming the object or buffer. 0: automatic (90 % of what the driver reports, else "
                    "half of the machine's RAM)")

    def draw(self, context):
        self.layout.prop(self, "memory_budget_mb")


def memory_budget_bytes():
    """The GPU memory budget in bytes, 0 for automatic: the preference where it is set, else the
    environment's SUBSPLAT_GPU_MEMORY_MB (a render farm's limit for each Blender process)."""
    addon = bpy.context.preferences.addons.get(__package__)
    if addon is not None and addon.preferences is not None and addon.preferences.memory_budget_mb > 0:
        return addon.preferences.memory_budget_mb << 20
    setting = os.environ.get("SUBSPLAT_GPU_MEMORY_MB", "").strip()
    return int(setting) << 20 if setting.isdigit() else 0


def memory_budget_warning():
    """What is wrong with the environment's SUBSPLAT_GPU_MEMORY_MB where it is what counts (the
    preference unset) and is not a whole number of megabytes; None otherwise."""
    addon = bpy.context.preferences.addons.get(__package__)
    if addon is not None and addon.preferences is not None and addon.preferences.memory_budget_mb > 0:
        return None
    setting = os.environ.get("SUBSPLAT_GPU_MEMORY_MB")
    if setting is None or setting.strip().isdigit():
        return None
    return (f"SUBSPLAT_GPU_MEMORY_MB={setting!r} is not a whole number of megabytes: ignored, the "
            "memory budget is automatic")


def register():
    bpy.utils.register_class(SubsplatPreferences)


def unregister():
    bpy.utils.unregister_class(SubsplatPreferences)
