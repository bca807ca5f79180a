"""Material previews are rendered by SubSplat (bl_use_preview): in Blender with its UI (under Xvfb),
the material slot icon of a skin material shows a warm translucent sphere, and it turns into a
paler, bluer one when the material becomes marble; after each, Python may still write to ID data.
A preview rendered between two F12 renders with Material Edit leaves their kept context be.

Run as CTest's blender_ui_test_preview does. The icons go to $SUBSPLAT_TEST_OUTPUT/preview_*.png.
"""
import os

import bpy
import numpy as np

from subsplat_testing.ui_helpers import OUTPUT, areas, check, close_splash, enable_addon, redraw, run_steps


def icon(material):
    """The material's preview icon as float RGBA (rows bottom first), or None before one is rendered."""
    preview = material.preview
    if preview is None or preview.icon_size[0] == 0:
        return None
    width, height = preview.icon_size
    pixels = np.array(preview.icon_pixels_float[:], dtype=np.float32).reshape(height, width, 4)
    return pixels if pixels[..., :3].max() > 0.0 else None


def save(name, pixels):
    image = bpy.data.images.new(name, pixels.shape[1], pixels.shape[0])
    image.pixels.foreach_set(pixels.ravel())
    image.filepath_raw = os.path.join(OUTPUT, f"preview_{name}.png")
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)


def writable(material):
    """Whether a timer may still write to ID data. Blender's "Python may not write" flag is global,
    and a preview render thread interleaving with the main thread's panel draws can leave it set
    (subsplat.native.library explains how, and what the add-on does against it)."""
    try:
        material.diffuse_color = material.diffuse_color[:]
        return True
    except AttributeError as error:
        print(error, flush=True)
        return False


def rendered_icon(material, previous=None, timeout=60.0):
    """Yields until the icon is rendered (and differs from `previous`); the icon is in holder[0]."""
    waited = 0.0
    while waited < timeout:
        redraw()
        yield 0.5
        waited += 0.5
        pixels = icon(material)
        if pixels is not None and (previous is None or np.abs(pixels - previous).max() > 0.02):
            yield 1.0  # a progressive preview may still be finishing
            holder.append(icon(material))
            return
    holder.append(None)


holder = []


def steps():
    subsplat = enable_addon()
    close_splash("preview_test")
    yield 1.0
    scene = bpy.context.scene
    scene.render.engine = "SUBSPLAT"
    cube = bpy.data.objects["Cube"]
    material = bpy.data.materials.new("Skin")
    material.subsplat.enabled = True
    material.subsplat.preset = "SKIN1"
    material.subsplat.mm_per_unit = 20.0
    cube.data.materials.clear()
    cube.data.materials.append(material)
    bpy.context.view_layer.objects.active = cube
    _, by_type = areas()
    by_type["PROPERTIES"].spaces.active.context = "MATERIAL"
    yield from rendered_icon(material)
    skin = holder.pop()
    check(skin is not None, "the skin material's preview icon is rendered")
    if skin is None:
        return
    check(writable(material), "after the preview, a timer may still write to ID data")
    save("skin", skin)
    stats = subsplat.last_render_stats()
    check(stats.get("preview") is True and stats.get("nonfinite_pixels") == 0,
          f"SubSplat rendered it as a preview, finite ({stats.get('preview')}, {stats.get('nonfinite_pixels')})")
    h, w = skin.shape[:2]
    middle = skin[h // 4: 3 * h // 4, w // 4: 3 * w // 4, :3].reshape(-1, 3).mean(axis=0)
    # Warm: red over green over blue, red at least 1.2 x blue (the preview scene's world and area
    # lights, which SubSplat renders since issue 20, light it paler than its lamps alone did: 1.30).
    check(middle[0] > middle[1] > middle[2] and middle[0] > 1.2 * middle[2],
          f"the skin preview is warm (mean rgb {middle})")

    material.subsplat.preset = "MARBLE"
    yield from rendered_icon(material, previous=skin)
    marble = holder.pop()
    check(marble is not None, "editing the material renders its icon again")
    if marble is None:
        return
    check(writable(material), "after the second preview too")
    save("marble", marble)
    middle_marble = marble[h // 4: 3 * h // 4, w // 4: 3 * w // 4, :3].reshape(-1, 3).mean(axis=0)
    check(middle_marble[2] / middle_marble[0] > middle[2] / middle[0] + 0.1,
          f"the marble preview is paler and bluer than skin (rgb {middle_marble} against {middle})")

    # A preview between two F12 renders with Material Edit leaves the kept context be (an artist
    # edits with the Material panel open): the second F12 recombines (docs/MATERIAL_EDIT.md, "Final
    # renders").
    scene.render.resolution_x, scene.render.resolution_y = 64, 48
    scene.subsplat.method = "MATERIAL_EDIT"
    bpy.ops.render.render()
    first = subsplat.last_render_stats()
    check(subsplat.last_render_error() is None and first.get("precompute_ms", 0) > 0, "the first F12 precomputes")
    material.subsplat.preset = "SKIN1"
    yield from rendered_icon(material, previous=marble)
    holder.pop()
    check(subsplat.last_render_stats().get("preview") is True, "a preview rendered between the two F12 renders")
    bpy.ops.render.render()
    second = subsplat.last_render_stats()
    check(subsplat.last_render_error() is None and second.get("context_kept") and second.get("transport_reused"),
          f"after the preview, the second F12 recombines (kept {second.get('context_kept')}, "
          f"reused {second.get('transport_reused')})")


run_steps(steps())
