"""Viewport timings (docs/BENCHMARKS.md, "Viewport"): Blender with its UI under Xvfb, each example
scene in Rendered shading with SubSplat at Viewport Resolution 1/1 and 1/2, the time of a redraw
after a light move and after a deformation step (the next frame of an animated example; a moved
vertex of the first translucent object otherwise), split into view_update (the depsgraph read
into arrays: the export) and view_draw (render, read-back and display). Then a 250k-triangle
sphere deformed every frame by a Wave modifier: how much of a frame its export takes.

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup --python bench/viewport.py \
        [-- --scenes NAME ... --repeats N (redraws per change, median; default 1)]

with BLENDER_USER_SCRIPTS=build/scripts. Writes build/bench/viewport.json and the Viewport section
of docs/BENCHMARKS.md.
"""
import argparse
import datetime
import json
import math
import os
import subprocess
import sys

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "tests"))  # subsplat_testing
import sections  # noqa: E402
from subsplat_testing.ui_helpers import areas, drawn, enable_addon, redraw, run_steps  # noqa: E402

EXAMPLES = ("skin_suzanne", "marble_pieces", "wax_jade", "heterogeneous", "candle_twist", "finger_pose")
COMMAND = ('BLENDER_USER_SCRIPTS=build/scripts xvfb-run -a -s "-screen 0 1280x800x24" '
           "blender --factory-startup --python bench/viewport.py")


def arguments():
    parser = argparse.ArgumentParser(prog="bench/viewport.py")
    parser.add_argument("--scenes", nargs="*", default=list(EXAMPLES))
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--scales", nargs="*", default=["1", "2"], help="Viewport Resolution divisors (1 2 4)")
    parser.add_argument("--budget", type=float, default=None,
                        help="Viewport Budget in millions of fragments (default: as saved; 0: none)")
    parser.add_argument("--output", default="viewport.json", help="file name in build/bench/")
    parser.add_argument("--no-document", action="store_true", help="do not write docs/BENCHMARKS.md")
    return parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])


def rendered_view():
    _, by_type = areas()
    view = by_type["VIEW_3D"].spaces.active
    view.overlay.show_overlays = False
    view.region_3d.view_perspective = "CAMERA"
    view.shading.type = "RENDERED"


def first_light(scene):
    return next(obj for obj in scene.objects if obj.type == "LIGHT")


def first_translucent(scene):
    for obj in scene.objects:
        if obj.type == "MESH" and any(s.material and s.material.subsplat.enabled for s in obj.material_slots):
            return obj
    return None


def deform(scene):
    """One deformation step: the next frame of an animation, or a vertex moved by a millimetre."""
    if any(obj.animation_data for obj in scene.objects):
        scene.frame_set(scene.frame_current % scene.frame_end + 1)
        return "next frame"
    obj = first_translucent(scene)
    obj.data.vertices[0].co.z += 0.001
    obj.data.update()
    return "vertex moved"


def measure(subsplat, change, repeats):
    """Yields while `change()` is made `repeats` times, each followed by redraws until the first
    sample is complete (the viewport's budget splits it over redraws, docs/VIEWPORT.md); appends the
    medians (update ms, first draw ms, ssRender ms of the last, frame size, longest draw ms, redraws,
    all the draws' ms) to the module's `results`."""
    rows = []
    for _ in range(repeats):
        draws = subsplat.last_viewport()["draws"]
        kind = change()
        yield from drawn(subsplat, draws, timeout=900.0, settle=0.0)
        waited = 0.0
        while subsplat.last_viewport().get("sample", 0) < 1 and waited < 1800.0:
            redraw()
            yield 0.05
            waited += 0.05
        v = subsplat.last_viewport()
        if v["error"]:
            raise RuntimeError(v["error"])
        times = v["draw_times"][-(v["draws"] - draws):]
        rows.append((v["update_ms"], times[0], v["stats"]["frame_ms"], v["stats"]["width"], v["stats"]["height"],
                     max(times), len(times), sum(times)))
    median = np.median(np.asarray(rows), axis=0)
    results.append({"kind": kind, "update_ms": float(median[0]), "draw_ms": float(median[1]),
                    "render_ms": float(median[2]), "width": int(median[3]), "height": int(median[4]),
                    "longest_draw_ms": float(median[5]), "redraws": int(median[6]), "all_draws_ms": float(median[7])})


results = []


def big_deforming_sphere():
    """A skin sphere of 250k triangles that a Wave modifier moves every frame."""
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "SUBSPLAT"
    scene.frame_start, scene.frame_end = 1, 100
    import bmesh
    mesh = bpy.data.meshes.new("Sphere")
    built = bmesh.new()
    bmesh.ops.create_uvsphere(built, u_segments=500, v_segments=251, radius=1.0)
    built.to_mesh(mesh)
    built.free()
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    sphere = bpy.data.objects.new("Sphere", mesh)
    scene.collection.objects.link(sphere)
    wave = sphere.modifiers.new("Wave", "WAVE")
    wave.height, wave.width, wave.speed = 0.05, 0.6, 0.05
    material = bpy.data.materials.new("Skin")
    material.subsplat.enabled = True
    material.subsplat.preset = "SKIN1"
    material.subsplat.mm_per_unit = 40.0
    sphere.data.materials.append(material)
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = (math.radians(50), 0.0, math.radians(30))
    scene.collection.objects.link(sun)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location, camera.rotation_euler = (0.0, -5.0, 0.0), (math.radians(90), 0.0, 0.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    sphere.data.calc_loop_triangles()
    return scene, len(sphere.data.loop_triangles)


def steps(args):
    subsplat = enable_addon()
    table = []
    for name in args.scenes:
        for scale in args.scales:
            bpy.ops.wm.open_mainfile(filepath=os.path.join(ROOT, "example_blends", f"{name}.blend"))
            yield 0.5
            scene = bpy.context.scene
            scene.subsplat.viewport_scale = scale
            if args.budget is not None:
                scene.subsplat.viewport_budget = args.budget
            rendered_view()
            yield from drawn(subsplat, 0, timeout=900.0, settle=0.2)
            light = first_light(scene)

            def move_light():
                light.rotation_euler.z += math.radians(2.0)
                return "light moved"
            results.clear()
            yield from measure(subsplat, move_light, args.repeats)
            yield from measure(subsplat, lambda: deform(scene), args.repeats)
            light_row, deform_row = results
            table.append({"scene": name, "scale": f"1/{scale}", "light": light_row, "deformation": deform_row})
            print(json.dumps(table[-1]), flush=True)
            scene.render.engine = "BLENDER_WORKBENCH"  # free the viewport's context before the next file
            yield 0.5
    scene, triangles = big_deforming_sphere()
    scene.subsplat.viewport_scale = "2"
    rendered_view()
    yield from drawn(subsplat, 0, timeout=900.0, settle=0.2)
    results.clear()

    def next_frame():
        scene.frame_set(scene.frame_current + 1)
        return "next frame"
    yield from measure(subsplat, next_frame, args.repeats)
    big = {"triangles": triangles, **results[0]}
    print(json.dumps(big), flush=True)
    write(table, big, args.repeats, args.output, not args.no_document)
    sys.stdout.flush()
    os._exit(0)


def write(table, big, repeats, output="viewport.json", document=True):
    """Saves build/bench/viewport.json (rows of scenes not measured this time kept from the last
    run, so `--scenes NAME` measures one again) and writes the document section from it."""
    path = os.path.join(ROOT, "build", "bench", output)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    measured = {(row["scene"], row["scale"]) for row in table}
    if os.path.exists(path):
        with open(path) as f:
            table = [row for row in json.load(f)["scenes"] if (row["scene"], row["scale"]) not in measured] + table
    table.sort(key=lambda row: (EXAMPLES.index(row["scene"]) if row["scene"] in EXAMPLES else 99, row["scale"]))
    with open(path, "w") as f:
        json.dump({"scenes": table, "big_mesh": big}, f, indent=1)
    if not document:
        return
    from subsplat_testing import helpers
    revision = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True).stdout.strip()
    import gpu
    renderer = gpu.platform.renderer_get()
    lines = ["## Viewport", "",
             f"Taken {datetime.date.today().isoformat()} at revision `{revision}` on {helpers.machine()}, "
             f"OpenGL renderer `{renderer}`, Blender {bpy.app.version_string} with its UI under Xvfb "
             "(window 1280 x 800), by", "", f"    {COMMAND}", "",
             "Each scene in Rendered shading (FULL, the scene's settings, Viewport Budget as saved: 200 M by "
             f"default) at the Viewport Resolutions listed; the median of {repeats} change(s) of each kind. "
             "*update* is `view_update`: the changed objects read from the depsgraph into arrays (export); "
             "*first* is the first `view_draw` after the change (sending to the library, `ssRender`, the "
             "read-back and the display: the first picture); *longest* the longest of the redraws until the "
             "first sample is complete, *redraws* how many. The deformation step is the next frame of the "
             "animated examples and a vertex moved by 1 mm otherwise (the object's evaluated mesh exported again).",
             "",
             "| scene | scale | frame size | light move: update ms | first ms | longest ms | redraws | "
             "deformation: update ms | first ms | longest ms | redraws |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for row in table:
        light, step = row["light"], row["deformation"]
        cells = []
        for r in (light, step):
            cells += [f"{r['update_ms']:.1f}", f"{r['draw_ms']:.0f}",
                      f"{r['longest_draw_ms']:.0f}" if "longest_draw_ms" in r else "-",
                      str(r["redraws"]) if "redraws" in r else "-"]
        lines.append(f"| {row['scene']} | {row['scale']} | {light['width']} x {light['height']} | "
                     + " | ".join(cells) + " |")
    share = big["update_ms"] / (big["update_ms"] + big["draw_ms"])
    lines += ["", f"A sphere of {big['triangles']} triangles deformed every frame by a Wave modifier (skin, one sun, "
              f"1/2 resolution, {big['width']} x {big['height']}): exporting it takes {big['update_ms']:.0f} ms "
              f"a frame (`view_update`), drawing {big['draw_ms']:.0f} ms, of which `ssRender` {big['render_ms']:.0f} "
              f"ms: the export is {share:.0%} of the frame.", ""]
    sections.replace(os.path.join(ROOT, "docs", "BENCHMARKS.md"), "viewport", lines)
    print("wrote the Viewport section of docs/BENCHMARKS.md")


run_steps(steps(arguments()))
