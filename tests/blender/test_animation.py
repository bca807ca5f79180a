"""Animation renders of deforming meshes, as a render farm runs them:
- frames rendered in one `blender -b -a` process equal the same frames rendered one by one, each in
  a process of its own, bit for bit, for the modifier-deformed heterogeneous candle, the armature
  and shape-key finger, and a mesh whose vertex count changes every frame: the library keeps
  nothing between frames that changes a result, and the add-on computes corner normals in a fixed
  order (Blender 3.4's own differ in their last bit between processes; docs/ANIMATION.md);
- those corner normals are Blender's, to float32 rounding.
Long runs in one process (the deforming candle among them) are test_soak.py's.

Images of the compared frames and of any difference go to $SUBSPLAT_TEST_OUTPUT/animation_*.
"""
import glob
import os
import unittest

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
import bpy  # noqa: E402
import numpy as np  # noqa: E402

# Frames of one scene rendered in different processes: bit for bit the same.
SAME_FRAME_BOUND = 0.0
# Small frames keep the many processes cheap; the settings are the scene's own otherwise.
SMALL = ("import bpy; s = bpy.context.scene; s.render.resolution_percentage = 25; "
         "s.render.image_settings.file_format = 'OPEN_EXR'; s.render.image_settings.color_depth = '32'")


def growing_mesh_scene():
    """A skin sphere whose subdivision level is animated 0, 1, 2, 1: its vertex count changes every
    frame. Saved as animation_growing.blend."""
    scene = helpers.empty_scene(200, 150)
    scene.render.engine = "SUBSPLAT"
    scene.frame_start, scene.frame_end = 1, 4
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=1.0)
    sphere = bpy.context.object
    sphere.name = "GrowingSphere"
    material = bpy.data.materials.new("Skin")
    material.subsplat.enabled = True
    material.subsplat.preset = "SKIN1"
    material.subsplat.mm_per_unit = 30.0
    sphere.data.materials.append(material)
    subdivision = sphere.modifiers.new("Subdivision", "SUBSURF")
    for frame, level in ((1, 0), (2, 1), (3, 2), (4, 1)):
        subdivision.levels = subdivision.render_levels = level
        subdivision.keyframe_insert("levels", frame=frame)
        subdivision.keyframe_insert("render_levels", frame=frame)
    camera = helpers.top_down_camera(scene, ortho_scale=3.0)
    camera.data.type = "PERSP"
    helpers.add_light(scene, "SUN", rotation=(0.6, 0.3, 0.0), energy=3.0)
    path = os.path.join(helpers.OUTPUT, "animation_growing.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    vertex_counts = []
    for frame in range(1, 5):
        scene.frame_set(frame)
        evaluated = sphere.evaluated_get(bpy.context.evaluated_depsgraph_get())
        vertex_counts.append(len(evaluated.data.vertices))
    return path, vertex_counts


class AnimationRendersAreDeterministic(unittest.TestCase):
    def render_sequence_and_singles(self, name, path, frames, env=None, expr=SMALL):
        """(sequence frames, single frames): dicts frame -> pixels. env: extra environment variables;
        expr: the Python each process runs first (SMALL)."""
        env = dict(os.environ, **(env or {}))
        sequence_out = os.path.join(helpers.OUTPUT, f"animation_{name}_sequence_")
        single_out = os.path.join(helpers.OUTPUT, f"animation_{name}_single_")
        for old in glob.glob(sequence_out + "*") + glob.glob(single_out + "*"):
            os.remove(old)
        first, last, step = frames[0], frames[-1], frames[1] - frames[0]
        result = helpers.run_blender(path, "--python-expr", expr, "-E", "SUBSPLAT", "-o", sequence_out,
                                     "-s", str(first), "-e", str(last), "-j", str(step), "-a", env=env)
        self.assertEqual(result.returncode, 0, result.stdout[-3000:] + result.stderr[-3000:])
        sequence = {f: helpers.read_exr(f"{sequence_out}{f:04d}.exr") for f in frames}
        singles = {}
        for f in frames:
            result = helpers.run_blender(path, "--python-expr", expr, "-E", "SUBSPLAT", "-o", single_out,
                                         "-f", str(f), env=env)
            self.assertEqual(result.returncode, 0, result.stdout[-3000:] + result.stderr[-3000:])
            singles[f] = helpers.read_exr(f"{single_out}{f:04d}.exr")
        return sequence, singles

    def assert_same(self, name, sequence, singles, relative):
        """Every pixel of every frame within `relative` of its value (0: bit for bit)."""
        frames = sorted(sequence)
        for f in frames:
            a, b = sequence[f], singles[f]
            self.assertEqual(a.shape, b.shape)
            self.assertTrue(np.all(np.isfinite(a)))
            off = np.abs(a - b).max(axis=-1)
            allowed = relative * np.abs(b).max(axis=-1)
            differing = int(np.count_nonzero(off > 0))
            worst = float((off / np.maximum(np.abs(b).max(axis=-1), 1e-30)).max())
            print(f"{name} frame {f}: {differing} pixels differ, largest by {worst:.2e} of the pixel's value")
            if np.any(off > allowed):
                path = helpers.write_difference(f"animation_{name}_{f:04d}", a, b)
                self.fail(f"{name} frame {f}: {int(np.count_nonzero(off > allowed))} pixels differ by more than "
                          f"{relative:g} of their value between the -a run and the single render (largest "
                          f"{worst:.2e}); see {path}")
        # The frames are of a moving object: comparing them would prove nothing if they were all alike.
        for f, g in zip(frames, frames[1:]):
            changed = float(np.mean(np.any(np.abs(sequence[f] - sequence[g]) > 1e-4, axis=-1)))
            self.assertGreater(changed, 0.01, f"{name}: frames {f} and {g} look the same; nothing deformed")

    def test_modifier_deformed_heterogeneous_candle(self):
        path = os.path.join(helpers.SOURCE, "example_blends", "candle_twist.blend")
        # At a manual 256² (AUTO chose 768² for the SubEdit candle: 46 s for the four renders); the
        # finger and the growing sphere render at AUTO's choice.
        sequence, singles = self.render_sequence_and_singles(
            "candle", path, [1, 33], expr=SMALL + "; s.subsplat.irradiance_resolution = 256")
        self.assert_same("candle", sequence, singles, SAME_FRAME_BOUND)

    def test_armature_and_shape_key_finger(self):
        path = os.path.join(helpers.SOURCE, "example_blends", "finger_pose.blend")
        sequence, singles = self.render_sequence_and_singles("finger", path, [1, 23])
        self.assert_same("finger", sequence, singles, SAME_FRAME_BOUND)

    def test_vertex_count_changing_every_frame(self):
        path, vertex_counts = growing_mesh_scene()
        self.assertEqual(len(set(vertex_counts[:3])), 3, f"vertex counts {vertex_counts}")
        sequence, singles = self.render_sequence_and_singles("growing", path, [1, 2, 3, 4])
        self.assert_same("growing", sequence, singles, SAME_FRAME_BOUND)


class CornerNormals(unittest.TestCase):
    """The add-on's own corner normals (export.mesh.smooth_corner_normals: a fixed summation order) are
    Blender's, to float32 rounding, on smooth, flat and deformed meshes."""

    def compare(self, obj):
        from subsplat.export import mesh as export_mesh
        mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
        try:
            vertices = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
            mesh.vertices.foreach_get("co", vertices)
            loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
            mesh.loops.foreach_get("vertex_index", loop_vertex)
            ours = export_mesh.smooth_corner_normals(mesh, vertices.reshape(-1, 3), loop_vertex)
            mesh.calc_normals_split()
            blender = np.empty(len(mesh.loops) * 3, dtype=np.float32)
            mesh.loops.foreach_get("normal", blender)
            difference = float(np.abs(ours - blender.reshape(-1, 3)).max())
            print(f"{obj.name}: {len(mesh.loops)} corners, largest difference to Blender's {difference:.1e}")
            self.assertLess(difference, 1e-4, obj.name)
        finally:
            obj.to_mesh_clear()

    def test_examples_and_primitives(self):
        bpy.ops.wm.open_mainfile(filepath=os.path.join(helpers.SOURCE, "example_blends", "finger_pose.blend"))
        bpy.context.scene.frame_set(12)
        self.compare(bpy.data.objects["Finger"])  # armature and shape key
        bpy.ops.wm.open_mainfile(filepath=os.path.join(helpers.SOURCE, "example_blends", "skin_suzanne.blend"))
        self.compare(bpy.data.objects["Suzanne"])  # subdivision surface, smooth
        helpers.empty_scene(8, 8)
        bpy.ops.mesh.primitive_cube_add()  # flat
        self.compare(bpy.context.object)
        bpy.ops.mesh.primitive_monkey_add()  # flat, with triangles and quads
        self.compare(bpy.context.object)


if __name__ == "__main__":
    helpers.run_tests()
