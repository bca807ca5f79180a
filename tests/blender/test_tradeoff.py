"""The speed/accuracy chart command (bench/tradeoff.py) on its reduced sweep: one small scene, a few
SubSplat points, one EEVEE and one Cycles point. It must write a valid chart PNG, a table with a row
for every point, and figures that make sense: finite positive times and errors, a Pareto front, and
SubSplat's default FULL below 5 % relative RMSE (it measures 0.7 % on this machine). The full sweep is a
benchmark (docs/TRADEOFF.md), not a test. Output: $SUBSPLAT_TEST_OUTPUT/tradeoff/.
"""
import json
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import helpers  # noqa: E402

helpers.enable_addon()
import bpy  # noqa: E402
import numpy as np  # noqa: E402

BUILD = os.environ.get("SUBSPLAT_BUILD_DIR", os.path.join(helpers.SOURCE, "build"))
SCENE = "skin_suzanne"


class ReducedSweep(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.output = os.path.join(helpers.OUTPUT, "tradeoff")
        os.makedirs(cls.output, exist_ok=True)
        cls.result = helpers.run_blender(
            "--python", os.path.join(helpers.SOURCE, "bench", "tradeoff.py"), "--",
            "--scenes", SCENE, "--percentage", "10", "--samples", "20000", "--runs", "1", "--quick",
            "--eevee-samples", "1", "--cycles-samples", "4", "--output", cls.output,
            "--replay", os.path.join(BUILD, "native", "subsplat_replay"),
            env=dict(os.environ, SUBSPLAT_TEST_OUTPUT=cls.output))
        print(cls.result.stdout[-4000:], cls.result.stderr[-2000:])

    def test_the_command_succeeds(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr[-3000:])

    def test_the_chart_is_a_png_of_the_points(self):
        path = os.path.join(self.output, "images", "tradeoff", f"{SCENE}.png")
        with open(path, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        image = bpy.data.images.load(path, check_existing=False)
        width, height = image.size
        pixels = np.empty(width * height * image.channels, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        bpy.data.images.remove(image)
        self.assertEqual((width, height), (750, 500))
        self.assertGreater(float(pixels.std()), 0.05, "the chart is not blank")

    def test_the_table_has_every_point_and_sane_figures(self):
        with open(os.path.join(self.output, "images", "tradeoff", "tradeoff.json")) as f:
            points = json.load(f)[SCENE]
        engines = {p["engine"] for p in points}
        self.assertEqual(engines, {"SubSplat", "EEVEE", "Cycles"})
        self.assertEqual({p["method"] for p in points if p["engine"] == "SubSplat"}, {"BRUTE", "FULL"})
        for p in points:
            self.assertTrue(math.isfinite(p["ms"]) and p["ms"] > 0, p)
            self.assertTrue(math.isfinite(p["error"]) and p["error"] > 0, p)
        with open(os.path.join(self.output, "TRADEOFF.md")) as f:
            document = f.read()
        for p in points:
            self.assertIn(f"| {p['label']}", document)
        self.assertIn("| yes |", document, "the Pareto front is marked")
        full = next(p for p in points if p["method"] == "FULL" and p["default"])
        self.assertLess(full["error"], 0.05, full)
        for what in ("full_default", "eevee", "cycles"):
            self.assertTrue(os.path.isfile(os.path.join(self.output, "images", "tradeoff", f"{SCENE}_{what}.png")))


if __name__ == "__main__":
    helpers.run_tests()
