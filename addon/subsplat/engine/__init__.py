"""The SubSplat RenderEngine: a thin layer that exports the frame and forwards it to the library."""
import os
import re
import sys
import time

import bpy

from . import export, native, properties, viewport
from .properties import METHOD_ITEMS

_last_stats = {}
_last_error = None
_last_passes = {}

EXITANCE_PASS = "SubSplat Exitance"
SAMPLES_PASS = "SubSplat Samples"
MAX_DEBUG_LEVELS = 8


def level_pass(k):
    return f"SubSplat Level {k}"


def last_render_stats():
    """Figures of the last SubSplat render, as a plain dict (a copy)."""
    return {key: (dict(value) if isinstance(value, dict) else value) for key, value in _last_stats.items()}


def last_render_error():
    """The message of the last failed render, or None."""
    return _last_error


def last_viewport():
    """Counters, stats and error of the most recently updated viewport (a copy; {} before one)."""
    if _last_viewport is None:
        return {}
    return {**_last_viewport.counters.as_dict(), "stats": dict(_last_viewport.stats), "error": _last_viewport.error}


_last_viewport = None


def last_render_passes():
    """With keep_passes set: {"Combined": ..., "SubSplat Exitance": ...} of the last render, as
    float32 arrays (height, width, 4), bottom row first. Used by tests and bench/accuracy.py."""
    return dict(_last_passes)


class SubsplatRenderEngine(bpy.types.RenderEngine):
    bl_idname = "SUBSPLAT"
    bl_label = "SubSplat"
    bl_use_gpu_context = True
    bl_use_shading_nodes_custom = False
    bl_use_preview = True

    def __init__(self):
        # Native GL objects belong to the render GL context: the native
        # context lives only inside render(), where that context is current.
        self._context = None
        self._viewport = None

    def __del__(self):
        # Blender frees a viewport engine from its own window's context, where it drew.
        viewport_session = getattr(self, "_viewport", None)
        if viewport_session is not None:
            viewport_session.release()

    def view_update(self, context, depsgraph):
        global _last_viewport
        if self._viewport is None:
            self._viewport = viewport.ViewportSession()
        _last_viewport = self._viewport
        self._viewport.update(depsgraph)

    def view_draw(self, context, depsgraph):
        if self._viewport is None:
            self.view_update(context, depsgraph)
        self._viewport.draw(self, context, depsgraph)

    def update_render_passes(self, scene=None, renderlayer=None):
        # Lists the passes for the compositor's Render Layers node.
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        self.register_pass(scene, renderlayer, EXITANCE_PASS, 4, "RGBA", "COLOR")
        if scene is not None and scene.subsplat.debug_passes and scene.subsplat.method != "REFERENCE":
            self.register_pass(scene, renderlayer, SAMPLES_PASS, 4, "RGBA", "COLOR")
            for k in range(MAX_DEBUG_LEVELS):
                self.register_pass(scene, renderlayer, level_pass(k), 4, "RGBA", "COLOR")

    def render(self, depsgraph):
        global _last_error
        state = native.gl_state() if viewport.check_gl_state else None
        scene = depsgraph.scene
        scale = scene.render.resolution_percentage / 100.0
        width = max(int(scene.render.resolution_x * scale), 1)
        height = max(int(scene.render.resolution_y * scale), 1)
        try:
            self._render(depsgraph, width, height)
            _last_error = None
        except native.Cancelled:
            # The user pressed Esc: nothing to report, no image to keep.
            _last_error = None
            _last_stats.clear()
            _last_stats["cancelled"] = True
            self.update_stats("", "SubSplat: cancelled")
        except (native.SubsplatError, export.ExportError) as error:
            _last_error = str(error)
            self.report({"ERROR"}, f"SubSplat: {error}")
            print(f"SubSplat: {error}", file=sys.stderr, flush=True)
        finally:
            if self._context is not None:
                self._context.release_quietly()
                self._context = None
        if state is not None:
            _last_stats["gl_state_changes"] = native.changed_gl_state(state, native.gl_state())
        if _last_error is not None and bpy.app.background and exit_on_error:
            # `blender -b ... -f N` exits 0 after a failed render, and a
            # SystemExit raised inside the render job hangs it: a farm must see
            # the failure, so leave with status 1 once our GL objects are gone.
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(1)

    def _render(self, depsgraph, width, height):
        _last_stats.clear()
        scene = depsgraph.scene
        settings = scene.subsplat
        self.update_stats("", "SubSplat: exporting scene")
        start = time.perf_counter()
        frame = export.export_frame(depsgraph, width, height)
        export_ms = (time.perf_counter() - start) * 1e3
        if not self.is_preview:  # the material preview scene's area lights are Blender's, not the user's
            for warning in frame.warnings:
                self.report({"WARNING"}, f"SubSplat: {warning}")

        native.set_memory_budget(properties.memory_budget_bytes())
        self._context = native.Context()
        context = self._context
        for material_id, desc in frame.materials.values():
            context.set_material(material_id, desc)
        for object_id, mesh in enumerate(frame.meshes):
            export.send_mesh(context, object_id, mesh)
        context.set_lights(frame.lights)
        context.set_camera(frame.camera)
        debug = settings.debug_passes and settings.method != "REFERENCE"
        context.set_settings(export.native_settings(scene, debug))

        progress = None
        if settings.method == "REFERENCE":
            self.update_stats("", f"SubSplat Reference: {settings.reference_samples} surface samples")

            def progress(fraction):
                return report_progress(self, fraction)
        else:
            self.update_stats("", "SubSplat: rendering")
        _last_passes.clear()
        pixels = context.render(width, height, progress)
        exitance = context.exitance_pass(width, height)
        stats = context.stats()
        if settings.scene_file and not self.is_preview:
            stats["scene_file"] = scene_file_path(settings.scene_file, scene.frame_current)
            context.save_scene(stats["scene_file"])
        stats.update(method=settings.method, preview=self.is_preview, export_ms=export_ms, meshes=len(frame.meshes),
                     lights=len(frame.lights), quality=settings.quality, reference_samples=settings.reference_samples)
        _last_stats.clear()
        _last_stats.update(stats)
        passes = {EXITANCE_PASS: exitance}
        if debug:
            passes[SAMPLES_PASS] = context.render_pass(native.PASS_SELECTION, width, height)
            for k in range(min(stats["splat_levels"], MAX_DEBUG_LEVELS)):
                passes[level_pass(k)] = context.render_pass(native.PASS_LEVEL_EXITANCE + k, width, height)
        if keep_passes:
            _last_passes.update({"Combined": pixels, **passes})

        for name in passes:
            self.add_pass(name, 4, "RGBA")
        result = self.begin_result(0, 0, width, height)
        result.layers[0].passes["Combined"].rect = pixels.reshape(-1, 4)
        for name, values in passes.items():
            result.layers[0].passes[name].rect = values.reshape(-1, 4)
        self.end_result(result)
        label = dict((key, name) for key, name, _ in METHOD_ITEMS)[settings.method]
        if settings.method == "REFERENCE":
            detail = f"{stats['splat_count']} surface samples"
        else:
            detail = (f"{stats['irradiance_resolution']}² irradiance, {stats['splat_count']} splats, "
                      f"{stats['levels']} irradiance / {stats['splat_levels']} splatting levels")
        self.update_stats("", f"SubSplat {label}: {stats['frame_ms']:.0f} ms, {detail}")


def scene_file_path(setting, frame):
    """The Save Scene File setting as an absolute path, runs of '#' replaced by the zero-padded frame."""
    path = bpy.path.abspath(setting)
    return re.sub(r"#+", lambda run: str(frame).zfill(len(run.group())), path)


def report_progress(engine, fraction):
    """Moves Blender's progress bar; False when the user asked to stop (Esc)."""
    engine.update_progress(fraction)
    return not engine.test_break()


# Scripts that render in background mode and want to handle failures
# themselves (tests) set subsplat.engine.exit_on_error = False.
exit_on_error = True
# Tests and benchmarks set keep_passes = True to read last_render_passes().
keep_passes = False


def register():
    bpy.utils.register_class(SubsplatRenderEngine)


def unregister():
    bpy.utils.unregister_class(SubsplatRenderEngine)
