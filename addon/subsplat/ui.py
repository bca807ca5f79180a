"""Panels: render settings, material translucency, and the stock panels the engine supports."""
import os

import bpy
from bpy.app.handlers import persistent

from . import export, native, principled
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
        self.draw_settings(context)
        self.layout.operator("subsplat.make_cycles_twin", icon="SCENE_DATA")

    def draw_settings(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.scene.subsplat
        layout.prop(settings, "method")
        samples = layout.column(align=True)
        samples.prop(settings, "samples")
        samples.prop(settings, "viewport_samples")
        layout.prop(settings, "viewport_budget")
        layout.prop(settings, "viewport_material_edit")
        layout.prop(settings, "viewport_scale")
        layout.prop(settings, "world_directions")
        layout.prop(settings, "shadow_resolution")
        layout.prop(settings, "forward_shift")
        if settings.method == "REFERENCE":
            layout.prop(settings, "reference_samples")
            layout.prop(settings, "scene_file")
            layout.label(text="The viewport shows Full; Reference is for final renders", icon="INFO")
            return
        if settings.method == "PRECOMPUTED":
            layout.prop(settings, "precomputed_atlas")
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
        if settings.source in ("DIPOLE", "PRINCIPLED"):
            layout.prop(settings, "profile_model")
        layout.prop(settings, "eta")
        layout.prop(settings, "mm_per_unit")
        layout.prop(settings, "roughness")
        layout.prop(settings, "specular")
        if not settings.enabled:
            return
        summary = material_summary(context.material)
        if summary.error is not None:
            for line in _wrap(summary.error):
                layout.label(text=line, icon="ERROR")
            return
        for warning in summary.warnings:
            for line in _wrap(warning):
                layout.label(text=line, icon="ERROR")
        info, profiles = summary.info, summary.profiles
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


class MaterialSummary:
    """What the material panel shows of a translucent material: the library's ProfileInfo, the
    profile set's info (None for a dipole), the warnings, or the error that stopped it."""

    def __init__(self, info=None, profiles=None, warnings=(), error=None):
        self.info, self.profiles, self.warnings, self.error = info, profiles, list(warnings), error


# Summaries by material: (settings fingerprint, summary). A panel redraws many times a second and a
# summary asks the library and may read image pixels, so it is made again only when the material
# changed: its SubSplat settings (the fingerprint) or, through the depsgraph, its nodes or an image.
_summaries = {}
MAX_SUMMARIES = 64


def _fingerprint(material):
    settings = material.subsplat
    values = []
    for prop in settings.bl_rna.properties:
        if prop.identifier == "rna_type":
            continue
        value = getattr(settings, prop.identifier)
        if isinstance(value, bpy.types.ID):
            value = value.name_full
        elif hasattr(value, "__len__") and not isinstance(value, str):
            value = tuple(value)
        values.append(value)
    if settings.source == "PRINCIPLED":  # the BSDF's inputs the conversion reads, and their images
        node = materials.principled_node(material)
        names = (principled.COLOR_INPUT, principled.RADIUS_INPUT, principled.SCALE_INPUT, principled.WEIGHT_INPUT)
        for name in (name for name in names if name) if node else ():
            socket = node.inputs[name]
            linked = socket.links[0].from_node if socket.is_linked else None
            image = getattr(linked, "image", None)
            values.append((tuple(socket.default_value) if hasattr(socket.default_value, "__len__")
                           else socket.default_value, linked and linked.bl_idname, image and image.name_full))
    if settings.source == "SUBEDIT_FILE":  # the file may change on disk (a stat, not a read)
        try:
            status = os.stat(bpy.path.abspath(settings.subedit_path, library=material.library))
            values.append((status.st_mtime_ns, status.st_size))
        except OSError:
            values.append(None)
    return tuple(values)


def material_summary(material):
    """The panel's summary of a translucent material, made again only when the material changed."""
    key = _fingerprint(material)
    cached = _summaries.get(material.name_full)
    if cached is not None and cached[0] == key:
        return cached[1]
    warnings = []
    try:
        described = materials.material_data(material, warnings)
        info = native.profile_info(described)
        summary = MaterialSummary(info, described.profiles.info() if described.profiles is not None else None,
                                  warnings)
    except (native.SubsplatError, export.ExportError) as error:
        summary = MaterialSummary(error=str(error))
    if len(_summaries) >= MAX_SUMMARIES:
        _summaries.clear()
    _summaries[material.name_full] = (key, summary)
    return summary


@persistent
def _forget_changed_summaries(_scene, depsgraph):
    """depsgraph_update_post: drops the summaries of edited materials (their nodes included), all of
    them when an image or a node group changed."""
    for update in depsgraph.updates:
        item = update.id
        if isinstance(item, bpy.types.Material):
            _summaries.pop(item.original.name_full, None)
        elif isinstance(item, bpy.types.Image) or (isinstance(item, bpy.types.NodeTree) and
                                                    not item.is_embedded_data):
            _summaries.clear()
            return


@persistent
def _forget_summaries(*_args):
    """load_post, undo_post, redo_post: the materials may all be others."""
    _summaries.clear()


HANDLERS = ((bpy.app.handlers.depsgraph_update_post, _forget_changed_summaries),
            (bpy.app.handlers.load_post, _forget_summaries),
            (bpy.app.handlers.undo_post, _forget_summaries),
            (bpy.app.handlers.redo_post, _forget_summaries))


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
    for handlers, handler in HANDLERS:
        handlers.append(handler)


def unregister():
    for handlers, handler in HANDLERS:
        if handler in handlers:
            handlers.remove(handler)
    _summaries.clear()
    for panel in _stock_panels():
        panel.COMPAT_ENGINES.discard("SUBSPLAT")
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
