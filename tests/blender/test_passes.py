"""Render passes a user can look at: SubSplat Exitance always; with Debug Passes, the selected
samples per irradiance level and each splatting level's own exitance. They reach the render
result (compositor, image editor) and scripts (last_render_passes)."""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import helpers  # noqa: E402

subsplat = helpers.enable_addon()
import accuracy  # noqa: E402


class DebugPasses(unittest.TestCase):
    def scene(self):
        import bpy
        scene = helpers.empty_scene(64, 64)
        material = bpy.data.materials.new("Marble")
        material.subsplat.enabled = True
        material.subsplat.preset = "MARBLE"
        material.subsplat.mm_per_unit = 200.0
        helpers.plane(scene, 4.0, material)
        helpers.top_down_camera(scene, ortho_scale=1.0)
        helpers.add_light(scene, "SUN", rotation=(math.radians(20), 0, 0), energy=3.0, angle=0.0)
        scene.subsplat.levels = 3
        scene.subsplat.alpha = 0.1  # coarse irradiance levels count as fine enough
        return scene

    def test_levels_and_samples(self):
        scene = self.scene()
        scene.subsplat.debug_passes = True
        accuracy.render_passes(scene, "FULL")
        passes = subsplat.last_render_passes()
        for name in ("Combined", "SubSplat Exitance", "SubSplat Samples", "SubSplat Level 0", "SubSplat Level 1",
                     "SubSplat Level 2"):
            self.assertIn(name, passes)
            self.assertEqual(passes[name].shape, (64, 64, 4))
        self.assertNotIn("SubSplat Level 3", passes)
        samples = passes["SubSplat Samples"]
        landed = samples[..., 3] > 0.5
        self.assertGreater(int(landed.sum()), 0)
        # Colours are those of levels: every landed pixel is one of the palette's entries.
        self.assertTrue(((samples[landed][:, :3] == 0.0) | (samples[landed][:, :3] == 1.0)
                         | (samples[landed][:, :3] == 0.5)).all())
        self.assertGreater(float(passes["SubSplat Level 0"][..., 0].sum()), 0.0)
        self.assertGreater(float(passes["SubSplat Level 1"][..., 0].sum() + passes["SubSplat Level 2"][..., 0].sum()),
                           0.0)
        # Written to a multilayer EXR as named layers a compositor can pick.
        import bpy
        path = os.path.join(helpers.OUTPUT, "passes.exr")
        scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
        scene.render.filepath = path
        bpy.ops.render.render(write_still=True)
        with open(path, "rb") as f:
            header = f.read(65536)
        for name in (b"SubSplat Samples", b"SubSplat Level 1", b"SubSplat Exitance"):
            self.assertIn(name, header)

    def test_off_by_default(self):
        scene = self.scene()
        accuracy.render_passes(scene, "FULL")
        passes = subsplat.last_render_passes()
        self.assertIn("SubSplat Exitance", passes)
        self.assertNotIn("SubSplat Samples", passes)


if __name__ == "__main__":
    helpers.run_tests()
