"""Render passes a user can look at: SubSplat Exitance always; with Debug Passes, the selected
samples per irradiance level and each splatting level's own exitance. They reach the render
result (compositor, image editor) and scripts (last_render_passes). With Film > Transparent the
Combined pass has alpha 0 (and no colour) where no object is, for compositing over a plate. A render
border renders the border's part of the frame, cropped to it or placed in the frame as Blender does.
Holdout objects and collections leave a hole (alpha 0) where they are seen, and still cast shadows."""
import math
import os
import unittest

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat_testing import accuracy  # noqa: E402
import numpy as np  # noqa: E402


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
        if hasattr(scene.render.image_settings, "media_type"):  # 5.0: a multilayer EXR is a media type
            scene.render.image_settings.media_type = "MULTI_LAYER_IMAGE"
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


class FilmTransparent(unittest.TestCase):
    def test_background_alpha_is_zero_and_objects_opaque(self):
        import bpy
        scene = helpers.empty_scene(64, 64)
        scene.render.engine = "SUBSPLAT"  # was left at EEVEE: its background is exact in 3.4, half floats in 4.2+
        helpers.set_world_colour(scene.world, (0.3, 0.4, 0.5))  # would show, were the film not transparent
        material = bpy.data.materials.new("Skin")
        material.subsplat.enabled = True
        material.subsplat.preset = "SKIN1"
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.25)
        bpy.context.object.data.materials.append(material)
        helpers.top_down_camera(scene, ortho_scale=1.0)
        helpers.add_light(scene, "SUN", rotation=(math.radians(20), 0, 0), energy=3.0, angle=0.0)
        for transparent in (False, True):
            scene.render.film_transparent = transparent
            combined = helpers.render(scene, f"film_transparent_{transparent}")
            corner, middle = combined[:8, :8].reshape(-1, 4), combined[28:36, 28:36].reshape(-1, 4)
            self.assertTrue(np.all(middle[:, 3] == 1.0), "the sphere is opaque")
            self.assertGreater(float(middle[:, :3].max()), 0.0)
            if transparent:
                self.assertTrue(np.all(corner == 0.0), f"transparent background: {corner[0]}")
            else:
                np.testing.assert_allclose(corner[:, :3], np.tile([0.3, 0.4, 0.5], (64, 1)), rtol=1e-5)
                self.assertTrue(np.all(corner[:, 3] == 1.0))


class RenderBorder(unittest.TestCase):
    """Render > Format > Render Region (issue 20, pipeline features): the border's pixels are the
    frame's pixels there; without Crop the rest of the frame is empty, with Crop the image is the
    border's size (Blender places and crops the engine's result: Workbench gives the same sizes)."""

    def scene(self):
        import bpy
        scene = helpers.empty_scene(64, 48)
        scene.render.engine = "SUBSPLAT"
        scene.render.film_transparent = True
        material = bpy.data.materials.new("Skin")
        material.subsplat.enabled = True
        material.subsplat.preset = "SKIN1"
        material.subsplat.mm_per_unit = 30.0
        bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(0.5, 0.2, 0.0))
        bpy.context.object.data.materials.append(material)
        helpers.top_down_camera(scene, ortho_scale=3.0)
        helpers.add_light(scene, "SUN", rotation=(math.radians(30), 0, 0), energy=3.0, angle=0.0)
        return scene

    def test_the_border_renders_its_part_of_the_frame(self):
        scene = self.scene()
        for method in ("REFERENCE", "FULL"):
            scene.subsplat.method = method
            scene.subsplat.reference_samples = 20000
            scene.render.use_border = False
            whole = helpers.render_to(scene, os.path.join(helpers.OUTPUT, f"border_whole_{method}.exr"))
            scene.render.use_border = True
            scene.render.border_min_x, scene.render.border_max_x = 0.25, 0.8  # columns 16 to 50
            scene.render.border_min_y, scene.render.border_max_y = 0.1, 0.6   # rows 4 to 27
            for crop in (False, True):
                scene.render.use_crop_to_border = crop
                image = helpers.render_to(scene, os.path.join(helpers.OUTPUT, f"border_{method}_{crop}.exr"))
                part = image if crop else image[4:28, 16:51]
                self.assertEqual(image.shape[:2], (24, 35) if crop else (48, 64), (method, crop))
                if not crop:
                    outside = image.copy()
                    outside[4:28, 16:51] = 0.0
                    self.assertEqual(float(np.abs(outside).max()), 0.0, f"{method}: nothing outside the border")
                expected = whole[4:28, 16:51]
                difference = float(np.abs(part[..., :3] - expected[..., :3]).mean() / expected[..., :3].mean())
                if difference >= 0.01:
                    helpers.write_difference(f"border_{method}_{crop}", part, expected)
                self.assertLess(difference, 0.01, f"{method}, crop {crop}: the border shows the frame's pixels there")


class Holdout(unittest.TestCase):
    """Object > Visibility > Holdout, and a view layer's holdout collection (issue 20, pipeline
    features): transparent black where the object is seen, with or without Film > Transparent; what
    is behind it stays hidden, and its shadow stays on the others."""

    def scene(self):
        import bpy
        scene = helpers.empty_scene(48, 48)
        scene.render.engine = "SUBSPLAT"
        floor_material = bpy.data.materials.new("Skin")
        floor_material.subsplat.enabled = True
        floor_material.subsplat.preset = "SKIN1"
        floor_material.subsplat.mm_per_unit = 30.0
        helpers.plane(scene, 4.0, floor_material)
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.4, location=(0.0, 0.0, 0.6))
        ball = bpy.context.object
        ball.name = "Ball"
        helpers.top_down_camera(scene, ortho_scale=2.0)
        helpers.add_light(scene, "SUN", rotation=(math.radians(40), 0, 0), energy=3.0, angle=0.0)
        return scene, ball

    def test_holdout_objects_and_collections_leave_a_hole(self):
        import bpy
        scene, ball = self.scene()
        scene.subsplat.reference_samples = 20000
        plain = {}
        for method in ("FULL", "REFERENCE"):
            scene.subsplat.method = method
            plain[method] = helpers.render(scene, f"holdout_none_{method}")
            centre = plain[method][22:26, 22:26].reshape(-1, 4)
            self.assertTrue(np.all(centre[:, 3] == 1.0) and centre[:, :3].max() > 0.0, "the ball is seen")
        for how in ("object", "collection"):
            if how == "object":
                ball.is_holdout = True
            else:
                ball.is_holdout = False
                held = bpy.data.collections.new("Held")
                scene.collection.children.link(held)
                scene.collection.objects.unlink(ball)
                held.objects.link(ball)
                bpy.context.view_layer.layer_collection.children["Held"].holdout = True
            for method in ("FULL", "REFERENCE"):
                scene.subsplat.method = method
                for transparent in (False, True):
                    scene.render.film_transparent = transparent
                    image = helpers.render(scene, f"holdout_{how}_{method}_{transparent}")
                    with self.subTest(how=how, method=method, film_transparent=transparent):
                        hole = image[22:26, 22:26].reshape(-1, 4)
                        self.assertTrue(np.all(hole == 0.0), f"the ball is a hole: {hole[0]}")
                        # Everywhere else, the floor as without the holdout: the ball still casts its
                        # shadow (a sun 40 degrees off, a shadow half a unit away: in the compared part).
                        floor = image[..., 3] == 1.0
                        self.assertGreater(int(floor.sum()), 48 * 48 // 2)
                        shadowed = plain[method][..., :3].sum(axis=-1) < 0.5 * np.median(plain[method][..., :3].sum(axis=-1))
                        self.assertGreater(int((floor & shadowed).sum()), 20, "the shadow is in the compared part")
                        np.testing.assert_allclose(image[floor][:, :3], plain[method][floor][:, :3], rtol=1e-4,
                                                   atol=1e-6)
            scene.render.film_transparent = False
        self.assertIsNone(subsplat.last_render_error())

if __name__ == "__main__":
    helpers.run_tests()
