"""The README's pictures of the examples lit by an environment (issue 20: "a picture of each example
lit by an environment, beside Cycles"): each example with its lights and world replaced by a
generated sky (an equirectangular map: a blue gradient, a dim ground and a sun disk of 2 degrees,
made here with numpy, seed-free), rendered by SubSplat (FULL, 8 samples) and by Cycles as the scene's
Cycles twin (docs/PHYSICAL.md: every translucent material as the volume it describes, the physical
answer; 128 samples, no denoiser: this machine's Blender has none, so it is noisy), side by side in
docs/images/environment/<example>.png, with the render times in docs/images/environment/times.json.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \\
        --python bench/environment_pictures.py [-- --examples skin_suzanne --percentage 40]
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)
OUT = os.path.join(SOURCE, "docs", "images", "environment")
EXAMPLES = ("skin_suzanne", "marble_pieces", "wax_jade", "finger_pose", "candle_twist", "heterogeneous")


def sky_map(width=512, height=256, sun_azimuth=math.radians(60), sun_elevation=math.radians(35)):
    """(height, width, 4) float RGBA, row 0 at the nadir, in Blender's equirectangular convention
    (u = 0.5 - atan2(y, x) / 2 pi, v = atan2(z, hypot(x, y)) / pi + 0.5)."""
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    azimuth = (0.5 - u)[None, :] * 2.0 * math.pi
    elevation = (v - 0.5)[:, None] * math.pi
    d = np.stack(np.broadcast_arrays(np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth),
                                     np.sin(elevation)), axis=-1)
    up = np.clip(d[..., 2], 0.0, 1.0)[..., None]
    sky = (1.0 - up) * np.array([0.75, 0.85, 1.0]) + up * np.array([0.25, 0.45, 0.9])
    ground = np.array([0.12, 0.10, 0.08])
    rgb = np.where(d[..., 2:3] >= 0.0, sky, ground) * 0.6
    sun = np.array([math.cos(sun_elevation) * math.cos(sun_azimuth), math.cos(sun_elevation) * math.sin(sun_azimuth),
                    math.sin(sun_elevation)])
    disc = (d @ sun) >= math.cos(math.radians(1.0))
    rgb[disc] = np.array([1.0, 0.95, 0.85]) * 4000.0
    return np.concatenate([rgb, np.ones((height, width, 1))], axis=-1).astype(np.float32)


def light_with_sky(scene):
    for obj in list(scene.objects):
        if obj.type == "LIGHT":
            bpy.data.objects.remove(obj)
    pixels = sky_map()
    image = bpy.data.images.new("Sky", pixels.shape[1], pixels.shape[0], float_buffer=True)
    image.pixels.foreach_set(pixels.ravel())
    world = bpy.data.worlds.new("Sky")
    world.use_nodes = True
    texture = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = image
    world.node_tree.links.new(texture.outputs["Color"], world.node_tree.nodes["Background"].inputs["Color"])
    scene.world = world


def render(scene, engine, path):
    scene.render.engine = engine
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = path
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True, scene=scene.name)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--examples", nargs="+", default=list(EXAMPLES))
    parser.add_argument("--percentage", type=int, default=40)
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    os.makedirs(OUT, exist_ok=True)
    times = {}
    for example in args.examples:
        bpy.ops.wm.open_mainfile(filepath=os.path.join(SOURCE, "example_blends", f"{example}.blend"))
        scene = bpy.context.scene
        light_with_sky(scene)
        scene.render.resolution_percentage = args.percentage
        scene.subsplat.method, scene.subsplat.samples = "FULL", 8
        scene.view_settings.view_transform = "Standard"
        ours, cycles = (os.path.join(OUT, f"{example}_{name}.png") for name in ("subsplat", "cycles"))
        times[example] = {"subsplat_s": render(scene, "SUBSPLAT", ours)}
        import subsplat
        twin, _reports = subsplat.twin.make_cycles_twin(scene)
        twin.cycles.device, twin.cycles.samples, twin.cycles.use_denoising = "CPU", 128, False
        twin.render.resolution_percentage = args.percentage
        twin.view_settings.view_transform = "Standard"
        times[example]["cycles_twin_s"] = render(twin, "CYCLES", cycles)
        subprocess.run(["oiiotool", ours, cycles, "--mosaic", "2x1", "-o", os.path.join(OUT, f"{example}.png")],
                       check=True)
        os.remove(ours), os.remove(cycles)
        print(f"ENVIRONMENT {example}: SubSplat {times[example]['subsplat_s']:.1f} s, "
              f"Cycles twin {times[example]['cycles_twin_s']:.1f} s", flush=True)
    with open(os.path.join(OUT, "times.json"), "w") as f:
        json.dump({"command": "blender -b --factory-startup --addons subsplat --python bench/environment_pictures.py",
                   "percentage": args.percentage, "blender": bpy.app.version_string, "times": times}, f, indent=1)
    os._exit(0)


main()
