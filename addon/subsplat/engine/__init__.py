"""The SubSplat RenderEngine: a thin layer that dispatches to final renders (final.py), material
previews (preview.py) and the viewport's Rendered shading (viewport.py)."""
import os
import sys

import bpy

from .. import diagnostics, export, native
from . import final, preview, viewport


class SubsplatRenderEngine(bpy.types.RenderEngine):
    bl_idname = "SUBSPLAT"
    bl_label = "SubSplat"
    bl_use_gpu_context = True
    bl_use_shading_nodes_custom = False
    bl_use_preview = True

    def __init__(self, *args, **kwargs):
        # Blender 4.5 and 5.0 pass arguments that bpy_struct's __init__ must receive; 3.x and 4.2 none.
        super().__init__(*args, **kwargs)
        # Native GL objects belong to the GL context they were made in: a final render's native
        # context lives only inside render(), the viewport's in its session (made in view_draw()).
        self._viewport = None

    def __del__(self):
        # Blender frees a viewport engine from its own window's context, where it drew.
        viewport_session = getattr(self, "_viewport", None)
        if viewport_session is not None:
            viewport_session.release()

    def view_update(self, context, depsgraph):
        if self._viewport is None:
            self._viewport = viewport.ViewportSession()
        diagnostics.set_viewport(self._viewport)
        self._viewport.update(depsgraph)

    def view_draw(self, context, depsgraph):
        if self._viewport is None:
            self.view_update(context, depsgraph)
        self._viewport.draw(self, context, depsgraph)

    def update_render_passes(self, scene=None, renderlayer=None):
        # Lists the passes for the compositor's Render Layers node.
        for name in final.pass_names(scene):
            self.register_pass(scene, renderlayer, name, 4, "RGBA", "COLOR")

    def render(self, depsgraph):
        state = native.gl_state() if diagnostics.check_gl_state else None
        error = None
        try:
            (preview if self.is_preview else final).render(self, depsgraph)
        except native.Cancelled:
            # The user pressed Esc: nothing to report, no image to keep.
            diagnostics.set_render_stats({"cancelled": True})
            self.update_stats("", "SubSplat: cancelled")
        except (native.SubsplatError, export.ExportError) as failure:
            error = str(failure)
            self.report({"ERROR"}, f"SubSplat: {failure}")
            print(f"SubSplat: {failure}", file=sys.stderr, flush=True)
        diagnostics.set_render_error(error)
        if state is not None:
            diagnostics.add_render_stat("gl_state_changes", native.changed_gl_state(state, native.gl_state()))
        if error is not None and bpy.app.background and diagnostics.exit_on_error:
            # `blender -b ... -f N` exits 0 after a failed render, and a SystemExit raised inside the
            # render job hangs it: a farm must see the failure, so leave with status 1 once our GL
            # objects are gone (final.render releases them whatever happens).
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(1)


def register():
    bpy.utils.register_class(SubsplatRenderEngine)


def unregister():
    final.release_kept()
    bpy.utils.unregister_class(SubsplatRenderEngine)
