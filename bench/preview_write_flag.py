"""How often a material preview leaves Blender's "Python may not write to ID data" flag set
(docs/DECISIONS.md, "The GIL"): in Blender with its UI, under Xvfb, the default cube's material is
switched between presets EDITS times; after each edit's preview icon is rendered, a timer tries to
write to the material. Prints one line per edit and a summary line
`stuck after edit K of EDITS` or `never stuck in EDITS edits`; exits 0 either way.

    PYTHONPATH=tests BLENDER_USER_SCRIPTS=build/scripts xvfb-run -a -s "-screen 0 1280x800x24" \
        blender --factory-startup --python bench/preview_write_flag.py -- --edits 12

Run it several times (the race depends on thread timing); a flag once stuck stays stuck.
"""
import argparse
import os
import sys

import bpy
import numpy as np

from subsplat_testing.ui_helpers import areas, close_splash, enable_addon, redraw, run_steps
import subsplat_testing.ui_helpers as ui_helpers

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--edits", type=int, default=12)
args = parser.parse_args(argv)


def icon(material):
    preview = material.preview
    if preview is None or preview.icon_size[0] == 0:
        return None
    width, height = preview.icon_size
    pixels = np.array(preview.icon_pixels_float[:], dtype=np.float32).reshape(height, width, 4)
    return pixels if pixels[..., :3].max() > 0.0 else None


def writable(material):
    try:
        material.diffuse_color = material.diffuse_color[:]
        return True
    except AttributeError:
        return False


def steps():
    enable_addon()
    close_splash("preview_write_flag")
    yield 1.0
    bpy.context.scene.render.engine = "SUBSPLAT"
    cube = bpy.data.objects["Cube"]
    material = bpy.data.materials.new("Flag")
    material.subsplat.enabled = True
    material.subsplat.mm_per_unit = 20.0
    cube.data.materials.clear()
    cube.data.materials.append(material)
    bpy.context.view_layer.objects.active = cube
    _, by_type = areas()
    by_type["PROPERTIES"].spaces.active.context = "MATERIAL"
    presets = ["SKIN1", "MARBLE", "KETCHUP", "APPLE"]
    previous = None
    for edit in range(args.edits):
        material.subsplat.preset = presets[edit % len(presets)]
        waited = 0.0
        while waited < 60.0:
            redraw()
            yield 0.25
            waited += 0.25
            pixels = icon(material)
            if pixels is not None and (previous is None or np.abs(pixels - previous).max() > 0.02):
                break
        yield 1.0
        previous = icon(material)
        ok = writable(material)
        print(f"edit {edit + 1}: preview rendered {waited < 60.0}, writable {ok}", flush=True)
        if not ok:
            print(f"stuck after edit {edit + 1} of {args.edits}", flush=True)
            return
    print(f"never stuck in {args.edits} edits", flush=True)


ui_helpers.failures.clear()
run_steps(steps())
