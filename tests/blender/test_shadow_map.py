"""The hard shadows' own map (docs/SOFT_SHADOWS.md, "Shadow maps"): `scene.subsplat.shadow_resolution`
is sent (0: automatic), the render's stats say what was used, and a value below the library's range
is said. The staircase against REFERENCE is the native test's (ShadowMap.*)."""
import math
import unittest

import bpy

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat.export import settings as export_settings  # noqa: E402


def box_on_floor(size=128):
    scene = helpers.empty_scene(size, size)
    scene.render.engine = "SUBSPLAT"
    scene.subsplat.quality = "MANUAL"
    scene.subsplat.irradiance_resolution = 64
    material = bpy.data.materials.new("Grey")
    helpers.plane(scene, 8.0, material)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 0.5), rotation=(0.0, 0.0, math.radians(30)))
    helpers.top_down_camera(scene, 4.0)
    helpers.add_light(scene, "SUN", rotation=(math.radians(45), 0, 0), energy=3.0, angle=0.0)
    return scene


class ShadowResolution(unittest.TestCase):
    def test_the_setting_is_sent_and_the_stats_say_what_was_used(self):
        scene = box_on_floor()
        self.assertEqual(export_settings.render_settings(scene).shadow_resolution, 0)
        helpers.render(scene, "shadow_map_automatic")
        self.assertIsNone(subsplat.last_render_error())
        automatic = subsplat.last_render_stats()["shadow_resolution"]
        # Texels no larger than the pixels: finer than the 64-texel irradiance buffer, a power of two.
        self.assertGreater(automatic, 64)
        self.assertEqual(automatic & (automatic - 1), 0)
        scene.subsplat.shadow_resolution = 96
        helpers.render(scene, "shadow_map_96")
        self.assertEqual(subsplat.last_render_stats()["shadow_resolution"], 96)

    def test_a_resolution_below_the_librarys_range_is_said(self):
        scene = box_on_floor()
        scene.subsplat.shadow_resolution = 8
        warnings = []
        self.assertEqual(export_settings.render_settings(scene, warnings=warnings).shadow_resolution, 16)
        self.assertEqual(len(warnings), 1)
        self.assertIn("Shadow Resolution 8 is below 16 texels", warnings[0])


if __name__ == "__main__":
    helpers.run_tests()
