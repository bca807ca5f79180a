"""Operators: Bake SubEdit Material, Make Cycles Twin."""
import bpy
from bpy_extras.io_utils import ExportHelper

from . import export, native, twin
from .export import materials


class SUBSPLAT_OT_bake_subedit(bpy.types.Operator, ExportHelper):
    """Write the material's translucency, whatever its source, to a SubEdit file (OpenEXR) that other
    tools can read and edit and that any SubEdit File material can use"""
    bl_idname = "subsplat.bake_subedit"
    bl_label = "Bake SubEdit Material"
    bl_options = {"REGISTER"}

    filename_ext = ".exr"
    filter_glob: bpy.props.StringProperty(default="*.exr", options={"HIDDEN"})

    @classmethod
    def poll(cls, context):
        material = getattr(context, "material", None)
        return material is not None and material.subsplat.enabled

    def invoke(self, context, event):
        if not self.filepath:
            self.filepath = bpy.path.ensure_ext(bpy.path.clean_name(context.material.name), self.filename_ext)
        return super().invoke(context, event)

    def execute(self, context):
        material = context.material
        path = bpy.path.abspath(self.filepath)
        try:
            profiles = materials.material_profiles(material)
            profiles.save(path)
            info = profiles.info()
        except (export.ExportError, native.SubsplatError) as error:
            self.report({"ERROR"}, f"SubSplat: {error}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"SubSplat: wrote '{path}': {info['width']} x {info['height']} texels, "
                              f"{info['profiles']} profile(s) of {info['segments']} segments")
        return {"FINISHED"}


class SUBSPLAT_OT_make_cycles_twin(bpy.types.Operator):
    """Make a scene "<name> Cycles Twin" with the same objects, camera, lights and world, rendered by
    Cycles, in which every translucent material is the medium it describes (a volume inside the mesh):
    the physical answer that SubSplat's model approximates. The scene itself is not changed"""
    bl_idname = "subsplat.make_cycles_twin"
    bl_label = "Make Cycles Twin"
    bl_options = {"REGISTER"}

    activate: bpy.props.BoolProperty(
        name="Show the Twin", default=True,
        description="Make the twin the window's scene (when there is a window)")

    @classmethod
    def poll(cls, context):
        return context.scene is not None

    def execute(self, context):
        try:
            scene, reports = twin.make_cycles_twin(context.scene)
        except twin.TwinError as error:
            self.report({"ERROR"}, f"SubSplat: {error}")
            return {"CANCELLED"}
        for level, text in reports:
            self.report({level}, f"SubSplat: {text}")
        if self.activate and context.window is not None:
            context.window.scene = scene
        return {"FINISHED"}


CLASSES = (SUBSPLAT_OT_bake_subedit, SUBSPLAT_OT_make_cycles_twin)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
