"""The native replay: a frame Blender rendered, saved with Save Scene File, renders to the same
image in subsplat_replay's own EGL context without Blender, and the replay reports every figure
bench/replay.py needs (per-stage and per-level time and fragments, RMSE against REFERENCE)."""
import json
import os
import subprocess
import unittest

import numpy as np

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat_testing import accuracy  # noqa: E402

BUILD = os.environ.get("SUBSPLAT_BUILD_DIR", os.path.join(helpers.SOURCE, "build"))
REPLAY = os.path.join(BUILD, "native", "subsplat_replay")


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(height, width, 3)


class Replay(unittest.TestCase):
    def test_replay_matches_blender_and_reports_every_figure(self):
        out = os.path.join(helpers.OUTPUT, "replay")
        os.makedirs(out, exist_ok=True)
        scene = accuracy.open_example("marble_pieces", 12)
        scene.frame_current = 7
        scene.subsplat.levels = 3
        scene.subsplat.scene_file = os.path.join(out, "marble_pieces_###.ssscene")
        combined, _, stats = accuracy.render_passes(scene, "FULL")
        path = os.path.join(out, "marble_pieces_007.ssscene")
        self.assertEqual(stats["scene_file"], path, "'#' runs become the zero-padded frame")
        self.assertTrue(os.path.isfile(path))

        figures = os.path.join(out, "marble_pieces.json")
        run = subprocess.run([REPLAY, "--methods", "BRUTE,FULL,MULTIRES:2@0.01", "--runs", "1",
                              "--reference-samples", "20000",
                              "--images", out, "--json", figures, path], capture_output=True, text=True)
        print(run.stdout, run.stderr)
        self.assertEqual(run.returncode, 0, run.stderr)

        # The same scene, settings and frame size give Blender's image.
        replayed = read_pfm(os.path.join(out, "marble_pieces_007_FULL.pfm"))
        self.assertEqual(replayed.shape, combined[..., :3].shape)
        scale = float(np.abs(combined[..., :3]).max())
        difference = float(np.abs(replayed - combined[..., :3]).max())
        if difference > 1e-4 * scale:
            accuracy.write_strip(os.path.join(out, "replay_difference.png"), np.dstack([replayed, combined[..., 3:]]),
                                 combined, combined[..., 3] > 0)
        self.assertLessEqual(difference, 1e-4 * scale)

        with open(figures) as f:
            report = json.load(f)
        (entry,) = report["scenes"]
        self.assertEqual((entry["width"], entry["height"]), combined.shape[1::-1])
        methods = {m["method"]: m for m in entry["methods"]}
        self.assertEqual(set(methods), {"BRUTE", "FULL", "MULTIRES:2@0.01"})
        self.assertEqual((methods["MULTIRES:2@0.01"]["levels"], methods["MULTIRES:2@0.01"]["splat_levels"]), (1, 2),
                         "an entry's own level count (and epsilon) override the saved settings")
        full = methods["FULL"]
        self.assertEqual((full["levels"], full["splat_levels"]), (stats["levels"], stats["splat_levels"]))
        self.assertEqual(full["splat_count"], stats["splat_count"])
        self.assertEqual(full["fragment_invocations"]["total"], stats["fragment_invocations"]["total"])
        self.assertEqual(sum(full["splat_level_fragments"]) + full["accumulation_fragments"],
                         full["fragment_invocations"]["splatting"])
        for m in methods.values():
            self.assertGreater(m["relative_rmse"], 0.0)
            self.assertLess(m["relative_rmse"], 0.2)

    def test_unwritable_scene_file_fails_the_render_with_the_path(self):
        # As a farm would run it: the message names the path, and blender -b exits 1.
        scene = accuracy.open_example("marble_pieces", 5)
        scene.subsplat.scene_file = "/nonexistent/dir/scene.ssscene"
        status, output = helpers.failed_batch_render("unwritable_scene_file")
        self.assertEqual(status, 1, output[-3000:])
        self.assertIn("cannot write /nonexistent/dir/scene.ssscene", output)

    def test_replay_rejects_bad_input_without_crashing(self):
        bogus = os.path.join(helpers.OUTPUT, "bogus.ssscene")
        with open(bogus, "wb") as f:
            f.write(b"SSSCENE\0\x01\0\0\0")  # a header and half of the next field
        run = subprocess.run([REPLAY, bogus], capture_output=True, text=True)
        self.assertEqual(run.returncode, 1)
        self.assertIn("truncated", run.stderr)
        run = subprocess.run([REPLAY, "--methods", "NOPE", bogus], capture_output=True, text=True)
        self.assertEqual(run.returncode, 2)
        self.assertIn("unknown method NOPE", run.stderr)


if __name__ == "__main__":
    helpers.run_tests()
