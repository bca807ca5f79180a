"""Anti-aliasing in Blender (docs/ANTIALIASING.md): `scene.subsplat.samples` jittered samples per
pixel in final renders (8 for a new scene), spread by Film > Pixel Filter's width; edges take
intermediate values with them and none without; the width out of the library's range is said.
The pixel filter's sampling, the error against 256 samples and the carried exitance are the native
tests' (AntiAliasing.*); the viewport's refinement is tests/blender_ui/test_viewport.py's."""
import math
import unittest

import bpy
import numpy as np

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat.export import settings as export_settings  # noqa: E402


def tilted_plane_scene(size=48):
    """A grey square turned 20 degrees in the image, lit from above, on a transparent background."""
    scene = helpers.empty_scene(size, size)
    scene.render.engine = "SUBSPLAT"
    scene.render.film_transparent = True
    scene.subsplat.quality = "MANUAL"
    scene.subsplat.irradiance_resolution = 128
    material = bpy.data.materials.new("Grey")
    material.diffuse_color = (0.8, 0.8, 0.8, 1.0)
    plane = helpers.plane(scene, 1.2, material)
    plane.rotation_euler = (0.0, 0.0, math.radians(20.0))
    helpers.top_down_camera(scene, 2.0)
    helpers.add_light(scene, "SUN", energy=3.0)
    return scene


class Samples(unittest.TestCase):
    def test_a_new_scene_renders_eight_samples_and_viewport_eight(self):
        bpy.ops.wm.read_homefile(use_empty=True)
        scene = bpy.context.scene
        properties = scene.subsplat.bl_rna.properties
        self.assertEqual(properties["samples"].default, 8)
        self.assertEqual(properties["viewport_samples"].default, 8)
        scene.subsplat.samples = 8
        self.assertEqual(export_settings.render_settings(scene).samples, 8)
        viewport = export_settings.render_settings(scene, viewport_sample=3)
        self.assertEqual((viewport.samples, viewport.first_sample), (1, 3))

    def test_edges_take_intermediate_values_with_samples_and_none_without(self):
        scene = tilted_plane_scene()
        counts = {}
        for samples in (1, 8):
            scene.subsplat.samples = samples
            image = helpers.render(scene, f"antialiasing_{samples}")
            self.assertIsNone(subsplat.last_render_error())
            self.assertEqual(subsplat.last_render_stats()["samples"], samples)
            green, full = image[..., 1], float(image[..., 1].max())
            counts[samples] = int(((green > 0.1 * full) & (green < 0.9 * full)).sum())
            alpha = image[..., 3]
            counts[f"alpha {samples}"] = int(((alpha > 0.05) & (alpha < 0.95)).sum())
        print(f"pixels between the square and the background: {counts}")
        self.assertEqual(counts[1], 0)
        self.assertEqual(counts["alpha 1"], 0)
        # The square's outline crosses about 4 x 1.2 x 48 / 2 = 115 rows and columns of pixels.
        self.assertGreater(counts[8], 60)
        self.assertGreater(counts["alpha 8"], 60)

    def test_the_pixel_filter_width_is_sent_and_out_of_range_said(self):
        scene = tilted_plane_scene()
        scene.render.filter_size = 2.0
        self.assertAlmostEqual(export_settings.render_settings(scene).filter_width, 2.0, places=6)
        # A wider filter blurs more: more pixels take values between.
        scene.subsplat.samples = 16
        narrow_and_wide = []
        for width in (0.5, 2.5):
            scene.render.filter_size = width
            image = helpers.render(scene, f"antialiasing_filter_{width}")
            self.assertAlmostEqual(subsplat.last_render_stats()["filter_width"], width, places=6)
            green, full = image[..., 1], float(image[..., 1].max())
            narrow_and_wide.append(int(((green > 0.05 * full) & (green < 0.95 * full)).sum()))
        print(f"pixels between, filter 0.5 and 2.5 px: {narrow_and_wide}")
        self.assertGreater(narrow_and_wide[1], 1.5 * narrow_and_wide[0])
        for size, sent in ((0.0, 0.01), (50.0, 10.0)):
            scene.render.filter_size = size
            warnings = []
            self.assertAlmostEqual(export_settings.render_settings(scene, warnings=warnings).filter_width, sent,
                                   places=6)
            self.assertEqual(len(warnings), 1)
            self.assertIn("pixel filter's width", warnings[0])
        for size in (0.01, 10.0):  # the range's own ends, which Blender stores as float32
            scene.render.filter_size = size
            warnings = []
            export_settings.render_settings(scene, warnings=warnings)
            self.assertEqual(warnings, [])


if __name__ == "__main__":
    helpers.run_tests()
