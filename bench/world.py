"""What the world light costs (issue 20: "frame time of each new feature against the same scene
without it"): examples rendered with FULL at their own settings, with a black world (no world
light), and with a uniform world drawn unshadowed, in 8 and in 16 shadowed directions
(scene.subsplat.world_directions; docs/WORLD.md). Each configuration's frame time is the median of
--runs renders, taken in one run so that they compare as ratios; the fragment invocations and light
views are the library's own counts. Prints a table and writes bench/results/world.json.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \\
        --python bench/world.py [-- --examples skin_suzanne marble_pieces --percentage 30 --runs 3]
"""
import argparse
import json
import os
import platform
import statistics
import sys
import tempfile

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)
CONFIGURATIONS = [("no world", None), ("unshadowed", -1), ("8 directions", 8), ("16 directions", 16)]


def measure(example, percentage, runs, directions):
    import subsplat
    bpy.ops.wm.open_mainfile(filepath=os.path.join(SOURCE, "example_blends", f"{example}.blend"))
    scene = bpy.context.scene
    scene.render.engine = "SUBSPLAT"
    scene.render.resolution_percentage = percentage
    scene.subsplat.method = "FULL"
    world = scene.world
    world.use_nodes = False
    if directions is None:
        world.color = (0.0, 0.0, 0.0)
    else:
        scene.subsplat.world_directions = directions
    scene.render.filepath = os.path.join(tempfile.gettempdir(), "subsplat_bench_world.png")
    times = []
    for _ in range(runs):
        bpy.ops.render.render(write_still=False)
        times.append(subsplat.last_render_stats()["frame_ms"])
    stats = subsplat.last_render_stats()
    return {"frame_ms": statistics.median(times), "frame_ms_runs": times, "light_views": stats["light_views"],
            "fragments": stats["fragment_invocations"]["total"], "width": stats["width"], "height": stats["height"],
            "irradiance_resolution": stats["irradiance_resolution"]}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--examples", nargs="+", default=["skin_suzanne", "marble_pieces"])
    parser.add_argument("--percentage", type=int, default=30)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", default=os.path.join(HERE, "results", "world.json"))
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    rows = []
    for example in args.examples:
        base = None
        for label, directions in CONFIGURATIONS:
            row = {"example": example, "world": label, **measure(example, args.percentage, args.runs, directions)}
            base = base or row
            row["time_ratio"] = row["frame_ms"] / base["frame_ms"]
            row["fragment_ratio"] = row["fragments"] / base["fragments"]
            rows.append(row)
            print(f"WORLD {example:14s} {label:14s} {row['width']} x {row['height']}: {row['frame_ms']:8.0f} ms "
                  f"({row['time_ratio']:.2f}x), {row['light_views']:3d} light views, {row['fragments']:11d} fragments "
                  f"({row['fragment_ratio']:.2f}x)", flush=True)
    result = {"command": "blender -b --factory-startup --addons subsplat --python bench/world.py -- "
                         + " ".join(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []),
              "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
              "blender": bpy.app.version_string, "percentage": args.percentage, "runs": args.runs, "rows": rows}
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    print(f"wrote {args.out}")
    os._exit(0)


main()
