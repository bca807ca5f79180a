"""Final renders (F12, `blender -b -f`, `-a`): export the frame, render it in a native context made
for it, and hand Blender the image and passes."""
import re
import time

import bpy
import numpy as np

from .. import diagnostics, export, native, preferences
from ..export import settings as export_settings
from ..properties import METHOD_ITEMS

EXITANCE_PASS = "SubSplat Exitance"
SAMPLES_PASS = "SubSplat Samples"
MAX_DEBUG_LEVELS = 8


def level_pass(k):
    return f"SubSplat Level {k}"


# Methods whose renders have the exitance pass only.
NO_DEBUG_PASSES = ("REFERENCE", "MATERIAL_EDIT", "PRECOMPUTED")
# The methods whose native context (and so their precomputation) is kept from one final render to
# the next (docs/MATERIAL_EDIT.md, "Final renders"; docs/PRECOMPUTED.md).
KEPT_METHODS = ("MATERIAL_EDIT", "PRECOMPUTED")


def pass_names(scene):
    """The passes a render of scene writes (the compositor's Render Layers node lists them)."""
    names = ["Combined", EXITANCE_PASS]
    if scene is not None and scene.subsplat.debug_passes and scene.subsplat.method not in NO_DEBUG_PASSES:
        names.append(SAMPLES_PASS)
        names += [level_pass(k) for k in range(MAX_DEBUG_LEVELS)]
    return names


def render(engine, depsgraph):
    """A final render of the depsgraph's scene at its output size."""
    render_image(engine, depsgraph, preview=False)


def render_image(engine, depsgraph, preview):
    """Exports the frame, renders it and writes Blender's result; preview: a material preview (its
    warnings are about Blender's preview scene, and it saves no scene file)."""
    diagnostics.set_render_stats({})
    scene = depsgraph.scene
    settings = scene.subsplat
    scale = scene.render.resolution_percentage / 100.0
    full_width = max(int(scene.render.resolution_x * scale), 1)
    full_height = max(int(scene.render.resolution_y * scale), 1)
    engine.update_stats("", "SubSplat: exporting scene")
    start = time.perf_counter()
    frame = export.export_frame(depsgraph, full_width, full_height)
    # A render border: Blender's result is the border's rectangle (and crops to it or not itself);
    # the camera sees only that part of the frame, at the frame's pixel size.
    border = (0, 0, full_width, full_height) if preview else export.camera.border_rect(scene.render, full_width,
                                                                                         full_height)
    frame.camera = export.camera.bordered(frame.camera, border, full_width, full_height)
    width, height = border[2], border[3]
    export_ms = (time.perf_counter() - start) * 1e3
    debug = settings.debug_passes and settings.method not in NO_DEBUG_PASSES
    render_settings = export_settings.render_settings(scene, debug, warnings=frame.warnings)
    label = dict((key, name) for key, name, _ in METHOD_ITEMS)[settings.method]
    if settings.debug_passes and not debug and not preview:
        frame.warnings.append(f"Debug Passes: {label} renders the exitance pass only (the samples and level passes "
                              f"are the splatting pipeline's)")
    if not preview:  # the material preview scene's area lights are Blender's, not the user's
        for warning in frame.warnings:
            engine.report({"WARNING"}, f"SubSplat: {warning}")

    budget_warning = preferences.memory_budget_warning()
    if budget_warning:
        engine.report({"WARNING"}, f"SubSplat: {budget_warning}")
    native.set_memory_budget(preferences.memory_budget_bytes())
    # The native context's GL objects belong to the render GL context, current only inside render().
    # MATERIAL_EDIT and PRECOMPUTED keep their context (and so their precomputation) from one final
    # render to the next while that GL context is the one current (docs/MATERIAL_EDIT.md, "Final
    # renders"; docs/PRECOMPUTED.md): F12 again, or the next frame of an animation.
    keep = settings.method in KEPT_METHODS and not preview
    context = _kept_context(frame, render_settings) if keep else None
    kept = context is not None
    if not keep and not preview:  # a material preview (a thumbnail while editing) leaves it be
        release_kept()
    try:
        if context is None:
            context = native.Context()
            _send(context, frame, render_settings)

        progress = None
        if settings.method == "REFERENCE":
            engine.update_stats("", f"SubSplat Reference: {settings.reference_samples} surface samples, "
                                    f"{render_settings.samples} per pixel")

            def progress(fraction):
                return report_progress(engine, fraction)
        else:
            engine.update_stats("", "SubSplat: rendering")
        diagnostics.set_render_passes({})
        pixels = context.render(width, height, progress)
        exitance = context.exitance_pass(width, height)
        stats = context.stats()
        if settings.scene_file and not preview:
            stats["scene_file"] = scene_file_path(settings.scene_file, scene.frame_current)
            context.save_scene(stats["scene_file"])
        stats.update(method=settings.method, preview=preview, export_ms=export_ms, meshes=len(frame.meshes),
                     context_kept=kept,
                     filter_width=render_settings.filter_width,
                     lights=len(frame.lights), quality=settings.quality, reference_samples=settings.reference_samples)
        if settings.method == "PRECOMPUTED":  # its memory and cost per object (docs/PRECOMPUTED.md, "Memory")
            stats["precomputed_objects"] = [dict(o, name=frame.meshes[o["object_id"]].name)
                                            for o in context.precomputed_objects()]
            if not stats["transport_reused"] and not preview:
                for o in stats["precomputed_objects"]:
                    engine.report({"INFO"}, precomputed_object_line(o))  # (`blender -b` prints "Info: ...")
        diagnostics.set_render_stats(stats)
        if not stats["target_reachable"] and not preview:
            engine.report({"WARNING"}, f"SubSplat: {unreachable_target_warning(settings, stats)}")
        if stats["transport_full_pipeline"] and not preview:
            engine.report({"WARNING"}, f"SubSplat: {FULL_PIPELINE_WARNING}")
        passes = {EXITANCE_PASS: exitance}
        if debug:
            passes[SAMPLES_PASS] = context.render_pass(native.SS_PASS_SELECTION, width, height)
            for k in range(min(stats["splat_levels"], MAX_DEBUG_LEVELS)):
                passes[level_pass(k)] = context.render_pass(native.SS_PASS_LEVEL_EXITANCE + k, width, height)
        if keep:
            _Kept.hold(context, frame)
            context = None
    finally:
        if context is not None:
            context.release_quietly()
    if diagnostics.keep_passes:
        diagnostics.set_render_passes({"Combined": pixels, **passes})

    for name in passes:
        engine.add_pass(name, 4, "RGBA")
    result = engine.begin_result(0, 0, width, height)
    result.layers[0].passes["Combined"].rect = pixels.reshape(-1, 4)
    for name, values in passes.items():
        result.layers[0].passes[name].rect = values.reshape(-1, 4)
    engine.end_result(result)
    if settings.method == "REFERENCE":
        detail = f"{stats['splat_count']} surface samples"
    else:
        detail = (f"{stats['irradiance_resolution']}² irradiance, {stats['shadow_resolution']}² shadows, "
                  f"{stats['splat_count']} splats, "
                  f"{stats['levels']} irradiance / {stats['splat_levels']} splatting levels")
    samples = f"{stats['samples']} sample" + ("s" if stats["samples"] != 1 else "")
    engine.update_stats("", f"SubSplat {label}: {stats['frame_ms']:.0f} ms, {samples}, {detail}")


class _Kept:
    """The native context of the last MATERIAL_EDIT or PRECOMPUTED final render and what it was sent."""
    context = None
    meshes = ()
    lights = None
    environment = None

    @classmethod
    def hold(cls, context, frame):
        cls.context, cls.meshes = context, list(frame.meshes)
        cls.lights, cls.environment = list(frame.lights), frame.environment


def release_kept():
    """Releases the kept MATERIAL_EDIT or PRECOMPUTED context (another method's render, the add-on's unregistering).
    Its GL objects are deleted when their GL context is next current (SsResourceCounts)."""
    if _Kept.context is not None:
        _Kept.context.release_quietly()
    _Kept.context, _Kept.meshes, _Kept.lights, _Kept.environment = None, (), None, None


def _same_mesh(a, b):
    return (a.name == b.name and a.object_to_world == b.object_to_world
            and all(np.array_equal(getattr(a, field), getattr(b, field))
                    for field in ("positions", "normals", "triangles", "triangle_materials"))
            and (a.uvs is None) == (b.uvs is None) and (a.uvs is None or np.array_equal(a.uvs, b.uvs)))


_UNSENT = object()  # _send: nothing was sent before


def _send(context, frame, render_settings, meshes=(), lights=_UNSENT, environment=_UNSENT):
    """Sends the frame to the context. meshes, lights, environment: what the context was sent
    before (a kept context's); only what differs from them is sent again (a mesh, the lights or the
    environment sent again invalidate MATERIAL_EDIT's transport; materials, camera and settings are
    compared by the library)."""
    for material_id, material in frame.materials.values():
        context.set_material(material_id, material)
    for object_id, mesh in enumerate(frame.meshes):
        if object_id >= len(meshes) or not _same_mesh(meshes[object_id], mesh):
            context.set_mesh(object_id, mesh)
    for object_id in range(len(frame.meshes), len(meshes)):
        context.remove_mesh(object_id)
    if lights is _UNSENT or frame.lights != lights:
        context.set_lights(frame.lights)
    if environment is _UNSENT or frame.environment != environment:
        context.set_environment(frame.environment)
    context.set_camera(frame.camera)
    context.set_settings(render_settings)


def _kept_context(frame, render_settings):
    """The kept context brought up to this frame (_send), or None when there is none or its GL
    context is not current."""
    context = _Kept.context
    if context is None:
        return None
    try:
        _send(context, frame, render_settings, _Kept.meshes, _Kept.lights, _Kept.environment)
    except native.SubsplatError as error:
        release_kept()
        if error.status != native.SS_GL_ERROR:
            raise
        return None  # another GL context is current (a new render window): start afresh
    _Kept.context = None  # render_image holds it again when the render succeeds
    return context


# MATERIAL_EDIT on a scene its transport cannot carry (docs/MATERIAL_EDIT.md).
FULL_PIPELINE_WARNING = ("Material Edit: a SubEdit (heterogeneous) material is in the scene, which the precomputed "
                         "transport does not carry; the frame was rendered with Full")


def unreachable_target_warning(settings, stats):
    """What Automatic quality says when its target needs more than the largest irradiance buffer."""
    return (f"Automatic quality: the target error {100 * settings.target_error:.2g} % needs a finer irradiance "
            f"buffer than the largest ({stats['irradiance_resolution']}²; {stats['texels_per_range']:.2f} texels "
            f"across the shortest scattering range), so the error may exceed it. The scattering range is short "
            f"for the lights' views: raise the target, or use Manual quality (docs/AUTO.md)")


def precomputed_object_line(o):
    """One object of PRECOMPUTED's precomputation, for the render's report."""
    return (f"SubSplat Precomputed: object '{o['name']}' precomputed in {o['precompute_ms'] / 1e3:.1f} s: "
            f"{o['bytes'] / 2**20:.0f} MiB ({o['texels']} texels of {o['texel_size']:.3g} units, "
            f"{o['kernel_taps'] / 1e6:.1f} M kernel taps, {o['factors'] / 1e6:.1f} M factors over "
            f"{o['vertices']} vertices; {atlas_charts(o)})")


def atlas_charts(o):
    """What a PRECOMPUTED object's atlas is made of (docs/PRECOMPUTED.md, "The mesh's own UV map")."""
    text = f"{o['charts']} chart{'s' if o['charts'] != 1 else ''}"
    if o["uv_charts"]:
        text += f", {o['uv_charts']} of them from its UV map"
    refused = o["uv_islands_refused"]
    if refused:
        text += (f"; {refused} UV island{'s' if refused != 1 else ''} charted by normals (stretched over 1.5 times, "
                 "folded or over itself)")
    return text


def scene_file_path(setting, frame):
    """The Save Scene File setting as an absolute path, runs of '#' replaced by the zero-padded frame."""
    path = bpy.path.abspath(setting)
    return re.sub(r"#+", lambda run: str(frame).zfill(len(run.group())), path)


def report_progress(engine, fraction):
    """Moves Blender's progress bar; False when the user asked to stop (Esc)."""
    engine.update_progress(fraction)
    return not engine.test_break()
