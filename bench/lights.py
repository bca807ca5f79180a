"""What soft shadows and area lights cost (issue 20: "frame time of each new feature against the
same scene without it"): examples rendered with FULL at their own settings, as they are (hard
lights), with every light soft (points and spots of radius 0.25, suns of 5 degrees), and with
every point light an area light (a 1 x 1 square of the same power). Each configuration's frame time
is the median of --runs renders, taken in one run so that they compare as ratios; the fragment
invocations are the library's own counts. Prints a table and writes bench/results/lights.json.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \\
        --python bench/lights.py [-- --examples skin_suzanne marble_pieces --percentage 30 --runs 3]
"""
import argparse
import json
import math
import os
import platform
import statistics
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)
CONFIGURATIONS = ["hard", "soft", "area"]


def measure(example, percentage, runs, configuration):
    import subsplat
    bpy.ops.wm.open_mainfile(filepath=os.path.join(SOURCE, "example_blends", f"{example}.blend"))
    scene = bpy.context.scene
    scene.render.engine = "SUBSPLAT"
    scene.render.resolution_percentage = percentage
    scene.subsplat.method = "FULL"
    for obj in scene.objects:
        if obj.type != "LIGHT":
            continue
        light = obj.data
        if configuration == "soft":
            if light.type == "SUN":
                light.angle = math.radians(5.0)
            else:
                light.shadow_soft_size = 0.25
        elif configuration == "area" and light.type == "POINT":
            light.type = "AREA"
            light = obj.data  # the same datablock, now of the area light's type
            light.shape, light.size = "SQUARE", 1.0
    times = []
    for _ in range(runs):
        bpy.ops.render.render(write_still=False)
        times.append(subsplat.last_render_stats()["frame_ms"])
    stats = subsplat.last_render_stats()
    return {"frame_ms": statistics.median(times), "frame_ms_runs": times, "light_views": stats["light_views"],
            "fragments": stats["fragment_invocations"]["total"], "width": stats["width"], "height": stats["height"]}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--examples", nargs="+", default=["skin_suzanne", "marble_pieces"])
    parser.add_argument("--percentage", type=int, default=30)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", default=os.path.join(HERE, "results", "lights.json"))
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    rows = []
    for example in args.examples:
        base = None
        for configuration in CONFIGURATIONS:
            row = {"example": example, "lights": configuration,
                   **measure(example, args.percentage, args.runs, configuration)}
            base = base or row
            row["time_ratio"] = row["frame_ms"] / base["frame_ms"]
            row["fragment_ratio"] = row["fragments"] / base["fragments"]
            rows.append(row)
            print(f"LIGHTS {example:14s} {configuration:5s} {row['width']} x {row['height']}: {row['frame_ms']:8.0f} ms "
                  f"({row['time_ratio']:.2f}x), {row['light_views']:3d} light views, {row['fragments']:11d} fragments "
                  f"({row['fragment_ratio']:.2f}x)", flush=True)
    result = {"command": "blender -b --factory-startup --addons subsplat --python bench/lights.py -- "
                         + " ".join(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []),
              "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
              "blender": bpy.app.version_string, "percentage": args.percentage, "runs": args.runs, "rows": rows}
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    print(f"wrote {args.out}")
    os._exit(0)


main()
