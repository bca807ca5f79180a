"""Renders every example scene with every real-time method (and REFERENCE, few samples) into
linear float EXR files, for golden-image and before/after comparisons.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        --python tests/golden/render_examples.py -- --out DIR [--percentage 10] [--methods FULL,BRUTE] \
        [--depth 16]

Names: DIR/<example>_<method>_f<frame>.exr. The animated examples render frame 1 and a deformed
frame; the others frame 1. Exits 1 if a render fails.
"""
import argparse
import glob
import os
import sys

import bpy

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
METHODS = ["FULL", "MULTIRES", "ADAPTIVE", "BRUTE", "REFERENCE"]
ANIMATED = {"candle_twist": (1, 12), "finger_pose": (1, 12)}


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", required=True)
    parser.add_argument("--percentage", type=int, default=10)
    parser.add_argument("--methods", default=",".join(METHODS))
    parser.add_argument("--examples", default="", help="comma-separated names; all by default")
    parser.add_argument("--reference-samples", type=int, default=20000)
    parser.add_argument("--depth", choices=("16", "32"), default="32", help="EXR float bits (16: the golden images)")
    return parser.parse_args(argv)


def main():
    args = arguments()
    os.makedirs(args.out, exist_ok=True)
    import addon_utils
    addon_utils.enable("subsplat", default_set=True)
    wanted = [name for name in args.examples.split(",") if name]
    failed = []
    for path in sorted(glob.glob(os.path.join(SOURCE, "example_blends", "*.blend"))):
        name = os.path.splitext(os.path.basename(path))[0]
        if wanted and name not in wanted:
            continue
        for method in args.methods.split(","):
            for frame in ANIMATED.get(name, (1,)):
                bpy.ops.wm.open_mainfile(filepath=path)
                scene = bpy.context.scene
                scene.render.engine = "SUBSPLAT"
                scene.render.resolution_percentage = args.percentage
                scene.subsplat.method = method
                scene.subsplat.samples = 1  # the golden images are of one sample per pixel
                scene.subsplat.reference_samples = args.reference_samples
                scene.frame_set(frame)
                scene.render.image_settings.file_format = "OPEN_EXR"
                scene.render.image_settings.color_depth = args.depth
                scene.render.image_settings.exr_codec = "ZIP"
                out = os.path.join(args.out, f"{name}_{method}_f{frame}.exr")
                scene.render.filepath = out
                try:
                    bpy.ops.render.render(write_still=True)
                except RuntimeError as error:
                    failed.append(f"{out}: {error}")
                    continue
                print(f"GOLDEN wrote {out}")
    if failed:
        print("\n".join(failed))
        sys.exit(1)


main()
