"""What bench/world.py, bench/lights.py, bench/antialiasing.py and bench/textures.py share: examples rendered with FULL at their own
settings under several configurations, in one run (so that they compare as ratios), each the median
frame time of some renders, with the library's light views and fragment invocations, printed as a
table and written as JSON."""
import argparse
import json
import os
import platform
import statistics
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)


def arguments(results_name):
    """The benches' options: --examples, --percentage, --runs, --out (bench/results/RESULTS_NAME)."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--examples", nargs="+", default=["skin_suzanne", "marble_pieces"])
    parser.add_argument("--percentage", type=int, default=30)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", default=os.path.join(HERE, "results", results_name))
    return parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])


def measure(example, percentage, runs, configure):
    """Opens the example, configure(scene), renders it runs times with FULL."""
    import subsplat
    bpy.ops.wm.open_mainfile(filepath=os.path.join(SOURCE, "example_blends", f"{example}.blend"))
    scene = bpy.context.scene
    scene.render.engine = "SUBSPLAT"
    scene.render.resolution_percentage = percentage
    scene.subsplat.method = "FULL"
    scene.subsplat.samples = 1  # one sample per pixel unless configure() asks for more
    configure(scene)
    times = []
    for _ in range(runs):
        bpy.ops.render.render(write_still=False)
        times.append(subsplat.last_render_stats()["frame_ms"])
    stats = subsplat.last_render_stats()
    return {"frame_ms": statistics.median(times), "frame_ms_runs": times, "light_views": stats["light_views"],
            "fragments": stats["fragment_invocations"]["total"], "width": stats["width"], "height": stats["height"],
            "irradiance_resolution": stats["irradiance_resolution"]}


def run(name, script, key, configurations, args):
    """Every example under every (label, configure) of configurations, the first the base of the
    ratios; prints NAME lines and writes args.out."""
    rows = []
    for example in args.examples:
        base = None
        for label, configure in configurations:
            row = {"example": example, key: label, **measure(example, args.percentage, args.runs, configure)}
            base = base or row
            row["time_ratio"] = row["frame_ms"] / base["frame_ms"]
            row["fragment_ratio"] = row["fragments"] / base["fragments"]
            rows.append(row)
            print(f"{name} {example:14s} {label:14s} {row['width']} x {row['height']}: {row['frame_ms']:8.0f} ms "
                  f"({row['time_ratio']:.2f}x), {row['light_views']:3d} light views, {row['fragments']:11d} fragments "
                  f"({row['fragment_ratio']:.2f}x)", flush=True)
    arguments = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    result = {"command": f"blender -b --factory-startup --addons subsplat --python bench/{script} -- "
                         + " ".join(arguments),
              "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
              "blender": bpy.app.version_string, "percentage": args.percentage, "runs": args.runs, "rows": rows}
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    print(f"wrote {args.out}")
