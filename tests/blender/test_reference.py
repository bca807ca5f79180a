"""REFERENCE through the engine: progress reaches Blender, a cancel stops it, and the same
scene renders the same image twice."""
import unittest

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat_testing import accuracy  # noqa: E402


def slab(size=32):
    scene = accuracy.slab_scene("MARBLE", 100.0, size)
    scene.render.engine = "SUBSPLAT"
    scene.subsplat.method = "REFERENCE"
    return scene


class ReferenceInBlender(unittest.TestCase):
    def setUp(self):
        self.original = subsplat.engine.final.report_progress
        self.progress = []

    def tearDown(self):
        subsplat.engine.final.report_progress = self.original

    def record_progress(self, cancel=False):
        """Records each fraction, then does what the engine does (update_progress, test_break);
        cancel=True answers as if the user had pressed Esc."""
        progress, original = self.progress, self.original

        def report_progress(engine, fraction):
            progress.append(fraction)
            go_on = original(engine, fraction)
            return go_on and not cancel
        subsplat.engine.final.report_progress = report_progress

    def test_progress_reaches_blender(self):
        import bpy
        self.record_progress()
        scene = slab()
        scene.subsplat.reference_samples = 400000
        bpy.ops.render.render()
        self.assertIsNone(subsplat.last_render_error())
        self.assertFalse(subsplat.last_render_stats().get("cancelled", False))
        self.assertGreater(len(self.progress), 0)
        self.assertEqual(self.progress, sorted(self.progress))
        self.assertAlmostEqual(self.progress[-1], 1.0, places=5)

    def test_escape_cancels(self):
        import bpy
        self.record_progress(cancel=True)
        scene = slab(256)
        scene.subsplat.reference_samples = 5000000  # minutes of work if not stopped
        bpy.ops.render.render()
        self.assertTrue(subsplat.last_render_stats().get("cancelled"), subsplat.last_render_stats())
        self.assertIsNone(subsplat.last_render_error())
        self.assertLess(max(self.progress, default=0.0), 0.5)  # stopped before most of the work

    def test_same_scene_same_image(self):
        scene = slab()
        scene.subsplat.reference_samples = 20000
        first, first_b, _ = accuracy.render_passes(scene, "REFERENCE")
        second, second_b, _ = accuracy.render_passes(scene, "REFERENCE")
        self.assertTrue((first == second).all())
        self.assertTrue((first_b == second_b).all())


if __name__ == "__main__":
    helpers.run_tests()
