"""Frame time of one example in this Blender (docs/VERSIONS.md), the figure compared across versions:

    build/bpy-<version>/bin/python bench/version_frame_time.py [-- --example skin_suzanne --percentage 50 --runs 3]
    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --python bench/version_frame_time.py -- ...

Renders the example with FULL `runs` times (the first also builds the shaders) and prints each
frame_ms of the library's stats and their median; exits with os._exit (docs/VERSIONS.md: the 4.2.23
module crashes at exit with the add-on registered).
"""
import argparse
import os
import statistics
import sys
import tempfile

import bpy

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--example", default="skin_suzanne")
    parser.add_argument("--percentage", type=int, default=50)
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    import addon_utils
    addon_utils.enable("subsplat", default_set=True)
    import subsplat
    bpy.ops.wm.open_mainfile(filepath=os.path.join(SOURCE, "example_blends", f"{args.example}.blend"))
    scene = bpy.context.scene
    scene.render.engine = "SUBSPLAT"
    scene.render.resolution_percentage = args.percentage
    scene.subsplat.method = "FULL"
    scene.subsplat.samples = 1  # one sample per pixel, as before anti-aliasing
    scene.render.filepath = os.path.join(tempfile.gettempdir(), "subsplat_version_frame_time.png")
    times = []
    for _ in range(args.runs):
        bpy.ops.render.render(write_still=False)
        times.append(subsplat.last_render_stats()["frame_ms"])
    stats = subsplat.last_render_stats()
    print(f"FRAME_TIME Blender {bpy.app.version_string}: {args.example} FULL at {args.percentage} % "
          f"({stats.get('width', '?')} x {stats.get('height', '?')}): "
          f"{', '.join(f'{t:.0f}' for t in times)} ms, median {statistics.median(times):.0f} ms", flush=True)
    os._exit(0)


main()
