"""The viewport's Rendered shading: one native context per viewport engine, kept in sync with the
depsgraph incrementally (docs/VIEWPORT.md).

Blender calls view_update() after every change and view_draw() for every redraw. Only view_draw()
is sure to run with the viewport's GL context current (after a frame change Blender 3.4 calls
view_update() with another context current), so view_update() only reads the depsgraph into
arrays and descriptions, and view_draw() creates the native context, sends it what changed and
renders. A camera move only redraws; an edit re-sends what it touched: a mesh whose geometry
changed is exported again, a moved object is sent again from the arrays already exported, an
edited material, light or setting is described again.
"""
import sys
import time

import dataclasses

import bpy
import gpu
from gpu_extras.presets import draw_texture_2d
import numpy as np

from .. import diagnostics, export, native, preferences
from ..export import background, camera, data, lights, mesh, settings

# The method a viewport uses for each setting: REFERENCE takes minutes, so the viewport shows FULL.
VIEWPORT_METHOD = {"REFERENCE": "FULL"}
# After a fast material edit (docs/VIEWPORT.md, "Material edits"), the next anti-aliasing sample
# (a Full frame) waits this long, so that a slider drag's next step is not held up by it.
EDIT_SETTLE_S = 0.25


class Counters:
    """How much work the viewport did (tests read these through last_viewport())."""

    def __init__(self):
        self.mesh_exports = 0      # meshes evaluated and read into arrays
        self.mesh_uploads = 0      # ssSetMesh calls (exports and moves)
        self.material_exports = 0  # materials described and sent
        self.light_exports = 0     # times the lights were sent
        self.full_syncs = 0
        self.draws = 0             # redraws that rendered (a sample)
        self.displays = 0          # every redraw, also those that only showed the image again
        self.gl_state_changes = []  # with diagnostics.check_gl_state: GL state the library left changed
        self.update_ms = 0.0       # the last view_update: depsgraph to library (exports included)
        self.draw_ms = 0.0         # the last view_draw: render, read back and display
        self.samples_rendered = 0  # anti-aliasing samples rendered, over all views
        self.sample = 0            # samples in the image shown now (restarts at 1 after any change)
        # Progressive splatting (docs/VIEWPORT.md): redraws that stopped at the budget, and the
        # splatting fragment invocations of each redraw.
        self.partial_draws = 0
        self.splat_fragments = []  # of each redraw that rendered, the last 1000
        self.draw_times = []       # view_draw ms of each redraw that rendered, the last 1000
        # Material edits (docs/VIEWPORT.md): the method of the last redraw that rendered, and the
        # redraws that rendered with MATERIAL_EDIT (precomputed or recombined).
        self.frame_method = None
        self.material_edit_draws = 0
        self.last_edit = {}  # of the last MATERIAL_EDIT redraw: precompute_ms, transport_reused, fragments, draw_ms
        self.header = ""  # the text the last redraw that showed an image put in the header

    def as_dict(self):
        return {name: list(value) if isinstance(value, list) else value for name, value in vars(self).items()}


class ViewportSession:
    """What one viewport engine instance keeps between updates and draws."""

    def __init__(self):
        self.context = None
        self.frame = export.Frame()  # the material registry: stable ids, ProfileSets kept alive
        self.holdouts = set()        # names of the objects last exported as holdouts
        self.objects = {}            # instance key -> [object id, data.Mesh]
        self.free_ids = []
        self.next_id = 0
        self.settings = None
        self.counters = Counters()
        self.error = None
        self.stats = {}
        # What view_update() found changed, sent by the next view_draw() (pending_lights and
        # pending_settings: None when unchanged).
        self.pending_materials = {}   # material id -> data.Material
        self.pending_meshes = {}      # object id -> data.Mesh
        self.pending_removals = set()
        self.pending_lights = None
        self.pending_settings = None
        self.world = None  # the world's lights last sent (export.data.Light: WORLD, its map's suns)
        self.environment = None  # the background map last sent (export.data.Environment), or None
        self.pending_environment = False  # whether self.environment waits to be sent
        # Anti-aliasing (docs/ANTIALIASING.md): the samples of the image shown, summed, and what
        # they were rendered for (size and view); a change of either, or anything sent, restarts it.
        self.accumulated = None
        self.samples = 0
        self.view_key = None
        self.context_settings = None   # the SsSettings the native context holds (None: to be sent)
        self.context_budget = None     # the splatting budget the native context holds
        self.partial = None            # the image of a sample whose splatting is under way
        self.first_sample = None       # the first sample's image (diagnostics.last_viewport_first_sample)
        # Fast material edits: whether the image shown started from a change of materials alone, and
        # how many times that streak of edits precomputed the transport.
        self.editing = False
        self.edit_precomputes = 0
        self.edit_frames = 0  # fast-edit frames so far: a delayed redraw is for the latest only

    # -- updates -----------------------------------------------------------------------------

    def update(self, depsgraph):
        start = time.perf_counter()
        try:
            self._sync(depsgraph, full=self.settings is None)
            self.error = None
        except (native.SubsplatError, export.ExportError) as error:
            self.error = str(error)
            print(f"SubSplat viewport: {error}", file=sys.stderr, flush=True)
        self.counters.update_ms = (time.perf_counter() - start) * 1e3

    def _sync(self, depsgraph, full):
        geometry, moved, materials = set(), set(), set()
        lights_changed = full
        if full:
            self.counters.full_syncs += 1
            if not self.objects:  # the session's origin: its camera's place when it began (export.Frame)
                self.frame.origin = camera.camera_origin(depsgraph.scene, depsgraph)
        else:
            for update in depsgraph.updates:
                item = update.id
                if isinstance(item, bpy.types.Material):
                    materials.add(item.name_full)
                elif isinstance(item, bpy.types.Object):
                    if item.type == "LIGHT":
                        lights_changed = True
                    else:
                        if update.is_updated_geometry:
                            geometry.add(item.name_full)
                        if update.is_updated_transform:
                            moved.add(item.name_full)
                elif isinstance(item, (bpy.types.Light, bpy.types.Collection)):
                    lights_changed = True
                elif isinstance(item, bpy.types.Image):
                    # Principled and artist materials read images: describe them all again.
                    materials.update(self.frame.materials)
        for name in materials:
            material = bpy.data.materials.get(name)
            before = self.frame.materials.get(name)
            described = self.frame.refresh_material(material) if material is not None else None
            if described is not None:
                self.pending_materials[described[0]] = described[1]
                self.counters.material_exports += 1
                if before is not None and before[1].uv_maps != described[1].uv_maps:
                    # A mesh sends the UV map its materials' textures read (export.mesh): send them again.
                    geometry.update(key[0] for key in self.objects)

        seen = set()
        light_descs = []
        # Holdout objects (their own flag or their collection's): one that changed state is exported again.
        holdouts = export.holdout_objects(depsgraph)
        geometry |= holdouts ^ self.holdouts
        self.holdouts = holdouts
        for instance in depsgraph.object_instances:
            obj = instance.object
            if obj.type == "LIGHT":
                light_descs.append(lights.light_data(obj, instance.matrix_world, self.frame.warnings,
                                                     self.frame.origin))
                continue
            if not mesh.renders(obj):
                continue
            key = (obj.name_full, tuple(instance.persistent_id) if instance.is_instance else None)
            seen.add(key)
            entry = self.objects.get(key)
            if entry is None or obj.name_full in geometry:
                known = set(self.frame.materials)
                exported = mesh.export_mesh(obj, instance.matrix_world, self.frame, obj.original.name_full in holdouts)
                self.counters.mesh_exports += 1
                self._send_new_materials(known)
                if exported is None:
                    if entry is not None:
                        self._remove(key)
                    continue
                if entry is None:
                    entry = self.objects[key] = [self._new_id(), None]
                entry[1] = exported
                self._upload(entry)
            elif obj.name_full in moved:
                entry[1] = dataclasses.replace(entry[1], object_to_world=data.column_major(instance.matrix_world,
                                                                                           self.frame.origin))
                self._upload(entry)
        for key in set(self.objects) - seen:
            self._remove(key)
        world = settings.world_lights(depsgraph.scene, [])  # the world, or its world_directions, edited
        if world != self.world:
            self.world, lights_changed = world, True
        environment = background.environment(depsgraph.scene, [])
        if environment != self.environment:
            self.environment, self.pending_environment = environment, True
        if lights_changed:
            settings.world_lights(depsgraph.scene, self.frame.warnings)
            self.pending_lights = light_descs + world
            self.counters.light_exports += 1

        scene = depsgraph.scene
        sync = settings.render_settings(scene, method=VIEWPORT_METHOD.get(scene.subsplat.method, scene.subsplat.method),
                                        viewport_sample=0, warnings=self.frame.warnings)
        if self.settings is None or sync != self.settings:
            self.pending_settings = sync
            self.settings = sync

    def _send_new_materials(self, known):
        for name, (material_id, desc) in self.frame.materials.items():
            if name not in known:
                self.pending_materials[material_id] = desc
                self.counters.material_exports += 1

    def _new_id(self):
        if self.free_ids:
            return self.free_ids.pop()
        self.next_id += 1
        return self.next_id - 1

    def _upload(self, entry):
        self.pending_meshes[entry[0]] = entry[1]
        self.pending_removals.discard(entry[0])

    def _remove(self, key):
        object_id = self.objects.pop(key)[0]
        self.pending_meshes.pop(object_id, None)
        self.pending_removals.add(object_id)
        self.free_ids.append(object_id)

    def _send_pending(self):
        """Sends what view_update() found changed; the viewport's GL context is current. True when
        anything was sent (the image shown is then out of date)."""
        sent = self.context is None or bool(self.pending_materials) or self._pending_besides_materials()
        if self.context is None:
            budget_warning = preferences.memory_budget_warning()
            if budget_warning:
                self.report({"WARNING"}, f"SubSplat: {budget_warning}")
            native.set_memory_budget(preferences.memory_budget_bytes())
            self.context = native.Context()
            self.context_settings = None
            self.context_budget = None  # a new context has no budget: the draw sets it
        # Each item leaves its pending set once the library has taken it: what fails (a mesh beyond
        # the memory budget) is sent again by the next draw.
        for material_id, material in list(self.pending_materials.items()):
            self.context.set_material(material_id, material)
            del self.pending_materials[material_id]
        for object_id in list(self.pending_removals):
            self.context.remove_mesh(object_id)
            self.pending_removals.discard(object_id)
        for object_id, pending in reversed(list(self.pending_meshes.items())):
            self.context.set_mesh(object_id, pending)
            del self.pending_meshes[object_id]
            self.counters.mesh_uploads += 1
        if self.pending_lights is not None:
            self.context.set_lights(self.pending_lights)
            self.pending_lights = None
        if self.pending_environment:
            self.context.set_environment(self.environment)
            self.pending_environment = False
        if self.pending_settings is not None:  # draw() sends them, with the frame's method and sample
            self.context_settings = None
            self.pending_settings = None
        return sent

    def _pending_besides_materials(self):
        return bool(self.pending_removals or self.pending_meshes or self.pending_lights is not None
                    or self.pending_settings is not None or self.pending_environment)

    def _materials_only(self):
        """Whether all that waits to be sent is materials (a slider in the Material panel)."""
        return self.context is not None and bool(self.pending_materials) and not self._pending_besides_materials()

    def _frame_method(self, scene):
        """The method of the sample about to render. The viewport's anti-aliasing samples after the
        first are jittered: MATERIAL_EDIT's transport is the first sample's, so they are Full's. With
        Full and Fast Material Edits, the first sample after a change of materials alone is
        MATERIAL_EDIT's (precomputed once, then recombined); a streak that has to precompute again
        (an edit past the transport's reach) goes back to Full until the next other change."""
        chosen = VIEWPORT_METHOD.get(scene.subsplat.method, scene.subsplat.method)
        if chosen == "MATERIAL_EDIT" and self.samples > 0:
            return "FULL"
        if (chosen == "FULL" and self.samples == 0 and self.editing and scene.subsplat.viewport_material_edit
                and self.edit_precomputes < 2):
            return "MATERIAL_EDIT"
        return chosen

    # -- drawing -----------------------------------------------------------------------------

    def draw(self, engine, context, depsgraph):
        if self.settings is None or self.error is not None:
            engine.update_stats("", f"SubSplat: {self.error or 'waiting for the scene'}")
            return
        scene = depsgraph.scene
        region, view = context.region, context.region_data
        divisor = int(scene.subsplat.viewport_scale)
        width, height = max(region.width // divisor, 1), max(region.height // divisor, 1)
        start = time.perf_counter()
        state = native.gl_state() if diagnostics.check_gl_state else None
        target = scene.subsplat.viewport_samples
        method = None
        try:
            materials_only = self._materials_only()
            sent = self._send_pending()
            view_camera = camera.view_data(view, self.frame.origin)
            view_key = (width, height, view_camera, scene.subsplat.viewport_material_edit)
            budget = int(scene.subsplat.viewport_budget * 1e6)
            if budget != self.context_budget:
                self.context.set_splat_budget(budget)
                self.context_budget, sent, materials_only = budget, True, False
            if sent or view_key != self.view_key:
                self.editing = materials_only and view_key == self.view_key
                if not self.editing:
                    self.edit_precomputes = 0
                self.accumulated, self.samples, self.view_key, self.partial = None, 0, view_key, None
            rendered = self.samples < target or self.accumulated is None
            if rendered:
                # Each redraw adds one jittered sample to the image shown, up to viewport_samples; a
                # sample's splatting runs over as many redraws as its budget needs (the library
                # goes on where the last stopped while nothing changed).
                method = self._frame_method(scene)
                wanted = dataclasses.replace(self.settings, method=method, first_sample=self.samples)
                if wanted != self.context_settings:
                    self.context.set_settings(wanted)
                    self.context_settings = wanted
                self.context.set_camera(view_camera)
                pixels = self.context.render(width, height)
                self.stats = self.context.stats()
                self.counters.frame_method = method
                if method == "MATERIAL_EDIT":
                    self.counters.material_edit_draws += 1
                    if not self.stats["transport_reused"] and not self.stats["transport_full_pipeline"]:
                        self.edit_precomputes += 1
                splatted = sum(self.stats["splat_level_fragments"])
                self.counters.splat_fragments = (self.counters.splat_fragments + [splatted])[-1000:]
                if self.stats["splatting_complete"]:
                    self.partial = None
                    self.accumulated = (pixels.astype(np.float64) if self.samples == 0
                                        else self.accumulated + pixels)
                    if self.samples == 0:
                        self.first_sample = pixels
                    self.samples += 1
                    self.counters.samples_rendered += 1
                else:
                    self.partial = pixels
                    self.counters.partial_draws += 1
            frame_ms = (time.perf_counter() - start) * 1e3
        except native.SubsplatError as error:
            self.error = str(error)
            self.accumulated, self.samples, self.partial = None, 0, None
            engine.update_stats("", f"SubSplat: {error}")
            print(f"SubSplat viewport: {error}", file=sys.stderr, flush=True)
            return
        self.counters.sample = self.samples
        if self.samples < target and method == "MATERIAL_EDIT" and self.editing:
            # The next sample once a slider drag pauses: a redraw EDIT_SETTLE_S after the latest edit.
            self.edit_frames += 1
            frame = self.edit_frames
            _tag_redraw_later(engine, EDIT_SETTLE_S, lambda: self.edit_frames == frame)
        elif self.samples < target:
            engine.tag_redraw()  # the next sample, or the rest of this one's splatting
        # The samples complete so far; before the first, the first's splats drawn so far.
        pixels = self.accumulated / self.samples if self.samples else self.partial
        if state is not None:
            changes = native.changed_gl_state(state, native.gl_state())
            self.counters.gl_state_changes = sorted(set(self.counters.gl_state_changes) | set(changes))
        self.counters.displays += 1
        if rendered:
            self.counters.draws += 1
        pixels = np.ascontiguousarray(pixels, dtype=np.float32)
        texture = gpu.types.GPUTexture((width, height), format="RGBA16F",
                                       data=gpu.types.Buffer("FLOAT", pixels.size, pixels))
        gpu.state.blend_set("ALPHA_PREMULT")
        engine.bind_display_space_shader(scene)
        draw_texture_2d(texture, (0, 0), region.width, region.height)
        engine.unbind_display_space_shader()
        gpu.state.blend_set("NONE")
        self.counters.draw_ms = (time.perf_counter() - start) * 1e3
        if rendered:
            self.counters.draw_times = (self.counters.draw_times + [self.counters.draw_ms])[-1000:]
        if method == "MATERIAL_EDIT":
            self.counters.last_edit = {"precompute_ms": self.stats["precompute_ms"],
                                       "transport_reused": self.stats["transport_reused"],
                                       "transport_full_pipeline": self.stats["transport_full_pipeline"],
                                       "fragments": self.stats["fragment_invocations"]["total"],
                                       "draw_ms": self.counters.draw_ms}
        chosen = VIEWPORT_METHOD.get(scene.subsplat.method, scene.subsplat.method)
        progress = ""
        if self.partial is not None:
            progress = f"splatting {100 * self.stats['splatting_progress']:.0f} %, "
        if self.counters.frame_method == "MATERIAL_EDIT":  # what the last frame did with the transport
            if chosen != "MATERIAL_EDIT":
                progress += "material edit: "
            progress += ("rendered with Full (a SubEdit material), " if self.stats["transport_full_pipeline"] else
                         "transport reused, " if self.stats["transport_reused"] else
                         f"transport precomputed in {self.stats['precompute_ms']:.0f} ms, ")
            if not self.stats["transport_full_pipeline"] and settings.forward_shift_applies(scene):
                progress += "without the forward shift, "  # MATERIAL_EDIT's transport does not carry it
        if self.counters.frame_method == "PRECOMPUTED":  # docs/PRECOMPUTED.md
            progress += ((f"relit in {self.stats['relight_ms']:.0f} ms" if self.stats["transport_reused"] else
                          f"precomputed in {self.stats['precompute_ms']:.0f} ms") +
                         f" ({self.stats['precomputed_bytes'] / 2**20:.0f} MiB), ")
        self.counters.header = (f"SubSplat {chosen.replace('_', ' ').title()}: {progress}sample {self.samples}/{target}, "
                                f"{frame_ms:.0f} ms at {width} x {height}, "
                                f"{self.stats['irradiance_resolution']}² irradiance"
                                f"{'' if self.stats['target_reachable'] else ' (short of the target error)'}, "
                                f"{self.stats['splat_count']} splats, {self.stats['levels']} irradiance / "
                                f"{self.stats['splat_levels']} splatting levels")
        engine.update_stats("", self.counters.header)

    def release(self):
        if self.context is not None:
            self.context.release_quietly()
            self.context = None


def _tag_redraw_later(engine, seconds, still_wanted):
    """engine.tag_redraw() in `seconds`, from a timer, if still_wanted() then; nothing if the engine
    is gone by then."""
    def tag():
        try:
            if still_wanted():
                engine.tag_redraw()
        except ReferenceError:  # the viewport was closed
            pass
        return None
    bpy.app.timers.register(tag, first_interval=seconds)
