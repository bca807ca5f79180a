"""Failure cases of image-space splatting, tested rather than hidden: grazing light and a depth
discontinuity render with finite values and no holes (no translucent pixel left dark where
REFERENCE has light) for every real-time method."""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import helpers  # noqa: E402

subsplat = helpers.enable_addon()
import accuracy  # noqa: E402

METHODS = ("BRUTE", "MULTIRES", "ADAPTIVE", "FULL")


def marble(mm_per_unit=50.0):
    import bpy
    material = bpy.data.materials.new("Marble")
    material.subsplat.enabled = True
    material.subsplat.preset = "MARBLE"
    material.subsplat.mm_per_unit = mm_per_unit
    return material


class HardCases(unittest.TestCase):
    def check_no_holes(self, scene, name):
        scene.render.engine = "SUBSPLAT"
        _, reference_b, _ = accuracy.render_passes(scene, "REFERENCE", 100000)
        lit = (reference_b[..., 3] > 0.5) & (reference_b[..., :3].max(axis=-1) > 1e-3 * reference_b[..., :3].max())
        self.assertGreater(int(lit.sum()), 100, f"{name}: the scene must have lit translucent pixels")
        for method in METHODS:
            image, image_b, stats = accuracy.render_passes(scene, method)
            with self.subTest(case=name, method=method):
                self.assertEqual(stats["nonfinite_pixels"], 0)
                holes = lit & (image_b[..., 3] > 0.5) & (image_b[..., :3].max(axis=-1) <= 0.0)
                if holes.any():
                    helpers.write_difference(f"hard_{name}_{method.lower()}", image_b, reference_b)
                self.assertEqual(int(holes.sum()), 0, f"{name} {method}: {int(holes.sum())} dark pixels where "
                                                      f"REFERENCE has light (of {int(lit.sum())})")

    def test_grazing_sun(self):
        for degrees in (85, 87, 89):
            scene = helpers.empty_scene(64, 64)
            helpers.plane(scene, 4.0, marble())
            helpers.top_down_camera(scene, ortho_scale=1.5)
            helpers.add_light(scene, "SUN", rotation=(math.radians(degrees), 0, 0), energy=5.0, angle=0.0)
            self.check_no_holes(scene, f"grazing_{degrees}")

    def test_depth_discontinuity(self):
        # One object: a slab and, above part of it, a raised block whose top is seen from the
        # camera next to the slab far below, lit by a sun at 40 degrees.
        import bpy
        scene = helpers.empty_scene(64, 64)
        mesh = bpy.data.meshes.new("Step")
        low, high = 0.0, 0.6
        vertices = [(-2, -2, low), (2, -2, low), (2, 2, low), (-2, 2, low),
                    (-0.5, -0.5, high), (0.5, -0.5, high), (0.5, 0.5, high), (-0.5, 0.5, high),
                    (-0.5, -0.5, 0.05), (0.5, -0.5, 0.05), (0.5, 0.5, 0.05), (-0.5, 0.5, 0.05)]
        faces = [(0, 1, 2, 3), (4, 5, 6, 7), (8, 9, 5, 4), (9, 10, 6, 5), (10, 11, 7, 6), (11, 8, 4, 7)]
        mesh.from_pydata(vertices, [], faces)
        mesh.materials.append(marble(25.0))
        step = bpy.data.objects.new("Step", mesh)
        scene.collection.objects.link(step)
        helpers.top_down_camera(scene, ortho_scale=2.0)
        helpers.add_light(scene, "SUN", rotation=(math.radians(40), 0, math.radians(30)), energy=5.0, angle=0.0)
        self.check_no_holes(scene, "depth_discontinuity")


if __name__ == "__main__":
    helpers.run_tests()
