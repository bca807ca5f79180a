"""Time to export a Principled BSDF whose Subsurface Color is a 2048 x 2048 image (issue 20: "a
textured Subsurface Color exports a 2048^2 image in under a second"), under each profile model:
the add-on's reading and conversion of the image (principled.read: pixels, sampling down to
MAX_SIDE, sRGB to linear, the per-texel inversion to coefficients) and the library's profile set
from the per-texel coefficients (ssNewProfileSetFromDipoles), each the median of 3 runs. The image
is value noise (seed 7) of a warm skin colour, so it holds many distinct media, as a painted texture
does. Prints a table and writes bench/results/principled_export.json.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \\
        --python bench/principled_export.py [-- --side 2048]
"""
import argparse
import json
import os
import platform
import statistics
import sys
import time

import bpy
import numpy as np

from subsplat import native, principled
from subsplat.export import materials

HERE = os.path.dirname(os.path.abspath(__file__))


def noise_image(side, seed):
    """A side x side image of smooth value noise around a skin colour, 8-bit sRGB like a painted map."""
    rng = np.random.default_rng(seed)
    coarse = rng.random((side // 64 + 2, side // 64 + 2, 3))
    rows = np.linspace(0, coarse.shape[0] - 1.001, side)
    i, f = rows.astype(int), (rows % 1.0)[:, None]
    smooth = coarse[i] * (1 - f[..., None]) + coarse[i + 1] * f[..., None]
    smooth = smooth[:, i] * (1 - f[None, :, :]) + smooth[:, i + 1] * f[None, :, :]
    colour = np.array([0.85, 0.55, 0.45]) * (0.6 + 0.4 * smooth) + 0.02 * rng.random((side, side, 3))
    pixels = np.ones((side, side, 4), dtype=np.float32)
    pixels[..., :3] = np.round(np.clip(colour, 0, 1) * 255) / 255
    image = bpy.data.images.new("SkinNoise", side, side)
    image.pixels.foreach_set(pixels.ravel())
    return image


def material_with(image, model):
    material = bpy.data.materials.new(f"Painted{model}")
    material.use_nodes = True
    material.subsplat.enabled = True
    material.subsplat.source = "PRINCIPLED"
    material.subsplat.profile_model = model
    material.subsplat.mm_per_unit = 30.0
    nodes = material.node_tree.nodes
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    bsdf = nodes["Principled BSDF"]
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs[principled.COLOR_INPUT])
    bsdf.inputs[principled.SCALE_INPUT].default_value = 0.1  # radius (1, 0.2, 0.1) x 0.1 x 30 mm per unit
    if principled.WEIGHT_INPUT:
        bsdf.inputs[principled.WEIGHT_INPUT].default_value = 1.0
    return material


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--side", type=int, default=2048)
    args = parser.parse_args(argv)
    image = noise_image(args.side, 7)
    rows = []
    for model in ("DIPOLE", "TABULATED"):
        material = material_with(image, model)
        node = materials.principled_node(material)
        settings = material.subsplat
        reads, builds = [], []
        for _ in range(3):
            principled._inverses.clear()  # the inversion's nodes are made once per (eta, model): count them
            start = time.perf_counter()
            sigma_a, sigma_s, _, _ = principled.read(material, node, settings.mm_per_unit, settings.eta, model)
            reads.append(time.perf_counter() - start)
            start = time.perf_counter()
            built = native.ProfileSet.from_dipoles(sigma_a, sigma_s, settings.eta, settings.fit_tolerance, model)
            builds.append(time.perf_counter() - start)
        info = built.info()
        media = len(np.unique(np.concatenate([sigma_a, sigma_s], axis=-1).reshape(-1, 6), axis=0))
        rows.append({"model": model, "texels_read": int(sigma_a.shape[0] * sigma_a.shape[1]),
                     "distinct_media": media, "read_s": statistics.median(reads),
                     "profile_set_s": statistics.median(builds), "palette_profiles": info['profiles'],
                     "fit_error": info['fit_error'], "max_fit_error": info['max_fit_error']})
        r = rows[-1]
        print(f"{model}: {args.side}^2 image -> {r['texels_read']} texels, {media} media; read and convert "
              f"{r['read_s']:.3f} s, profile set {r['profile_set_s']:.3f} s, total "
              f"{r['read_s'] + r['profile_set_s']:.3f} s; {info['profiles']} profiles, fit error {info['fit_error']:.4f} "
              f"(largest {info['max_fit_error']:.4f})", flush=True)
    result = {"side": args.side, "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
              "blender": bpy.app.version_string, "rows": rows}
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "principled_export.json"), "w") as f:
        json.dump(result, f, indent=1)


main()
