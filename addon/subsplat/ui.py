"""Panels: render settings, material translucency, and the stock panels the engine supports."""
import bpy

from . import export, native
from .export import materials


class SubsplatPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    COMPAT_ENGINES = {"SUBSPLAT"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class SUBSPLAT_PT_render(SubsplatPanel, bpy.types.Panel):
    bl_label = "SubSplat"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.scene.subsplat
        layout.prop(settings, "method")
        layout.prop(settings, "viewport_scale")
        if settings.method == "REFERENCE":
            layout.prop(settings, "reference_samples")
            layout.prop(settings, "scene_file")
            layout.label(text="The viewport shows Full; Reference is for final renders", icon="INFO")
            return
        layout.prop(settings, "quality")
        manual = layout.column()
        if settings.quality == "AUTO":
            layout.prop(settings, "target_error")
            manual.active = False  # shown for what they would be; editing one makes the quality manual
        manual.prop(settings, "irradiance_resolution")
        if settings.method in {"MULTIRES", "ADAPTIVE", "FULL"}:
            manual.prop(settings, "levels")
        if settings.method in {"ADAPTIVE", "FULL"}:
            manual.prop(settings, "z0_factor")
            manual.prop(settings, "alpha")
        if settings.method in {"MULTIRES", "FULL"}:
            manual.prop(settings, "epsilon")
            layout.prop(settings, "lambda_z")
            layout.prop(settings, "lambda_m")
        layout.prop(settings, "debug_passes")
        layout.prop(settings, "scene_file")


class SUBSPLAT_PT_material(SubsplatPanel, bpy.types.Panel):
    bl_label = "Translucency"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.material is not None

    def draw_header(self, context):
        self.layout.prop(context.material.subsplat, "enabled", text="")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.material.subsplat
        layout.active = settings.enabled
        layout.prop(settings, "source")
        if settings.source == "SUBEDIT_FILE":
            layout.prop(settings, "subedit_path")
            layout.prop(settings, "fit_tolerance")
        elif settings.source == "PRINCIPLED":
            layout.prop(settings, "fit_tolerance")
        elif settings.source == "ARTIST":
            layout.prop(settings, "artist_radius")
            layout.template_ID(settings, "translucency_image", new="image.new", open="image.open")
            layout.prop(settings, "albedo_color")
            layout.template_ID(settings, "albedo_image", new="image.new", open="image.open")
            layout.prop(settings, "fit_tolerance")
        else:
            layout.prop(settings, "preset")
            layout.prop(settings, "sigma_a")
            layout.prop(settings, "sigma_s_prime")
        layout.prop(settings, "eta")
        layout.prop(settings, "mm_per_unit")
        layout.prop(settings, "roughness")
        layout.prop(settings, "specular")
        if not settings.enabled:
            return
        warnings = []
        try:
            info = native.profile_info(materials.material_data(context.material, warnings))
            profiles = materials.source_profiles(context.material)
            profiles = profiles.info() if profiles is not None else None
        except (native.SubsplatError, export.ExportError) as error:
            for line in _wrap(str(error)):
                layout.label(text=line, icon="ERROR")
            return
        for warning in warnings:
            for line in _wrap(warning):
                layout.label(text=line, icon="ERROR")
        col = layout.column(align=True)
        if profiles is not None:
            unit = settings.mm_per_unit
            col.label(text=f"Model: {profiles['profiles']} profile(s) of {profiles['segments']} segments "
                           f"(source: {profiles['source_profiles']} of {profiles['source_segments']})")
            col.label(text=f"Map: {profiles['width']} x {profiles['height']} texels, "
                           f"GPU memory {profiles['gpu_bytes'] / 2 ** 20:.1f} MiB")
            icon = "ERROR" if profiles["fit_error"] > settings.fit_tolerance else "NONE"
            col.label(text=f"Fit error: {100 * profiles['fit_error']:.2f} % mean, "
                           f"{100 * profiles['max_fit_error']:.2f} % largest", icon=icon)
            shortest, longest = profiles["effective_range_mm"]
            col.label(text=f"Scattering range (95%): {shortest / unit:.4g} to {longest / unit:.4g} units")
            col.label(text="Most common profile:")
        col.label(text="Total reflectance: " + ", ".join(f"{v:.3f}" for v in info.total_reflectance))
        col.label(text="Scattering range (95%): " + ", ".join(f"{v:.4g}" for v in info.effective_range) + " units")
        col.label(text=f"Splat radius: {info.support_radius:.4g} units")
        layout.operator("subsplat.bake_subedit", icon="EXPORT")


def _wrap(text, width=60):
    """Long messages as lines a panel can show."""
    lines, line = [], ""
    for word in text.split():
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    return lines + ([line] if line else [])


CLASSES = (SUBSPLAT_PT_render, SUBSPLAT_PT_material)

# Stock panels that make sense for this engine (from the Blender template for external engines).
EXCLUDED_PANELS = {"VIEWLAYER_PT_filter", "VIEWLAYER_PT_layer_passes", "RENDER_PT_eevee_performance"}
# EEVEE's material panels that apply here too: the slots (with preview icons), the preview
# (bl_use_preview: rendered by SubSplat) and the surface nodes (the Principled BSDF source).
INCLUDED_PANELS = {"MATERIAL_PT_preview", "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface"}


def _stock_panels():
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if engines is None or panel.__name__ in EXCLUDED_PANELS:
            continue
        if "BLENDER_RENDER" in engines or panel.__name__ in INCLUDED_PANELS:
            yield panel


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    for panel in _stock_panels():
        panel.COMPAT_ENGINES.add("SUBSPLAT")


def unregister():
    for panel in _stock_panels():
        panel.COMPAT_ENGINES.discard("SUBSPLAT")
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
