"""What textures cost (issue 20: "frame time of each new feature against the same scene without
it"): examples rendered with FULL at their own settings, as they are, with a 1024 x 1024 image on
every material's colour (an opaque Base Color; a translucent material's tint, docs/TEXTURES.md),
and with a normal map as well. Each configuration's frame time is the median of --runs renders,
taken in one run so that they compare as ratios; the fragment invocations are the library's own
counts. Prints a table and writes bench/results/textures.json.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \\
        --python bench/textures.py [-- --examples skin_suzanne marble_pieces --percentage 30 --runs 3]
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import example_configurations  # noqa: E402


def plain(scene):
    pass


def _bsdfs():
    for material in bpy.data.materials:
        if not material.use_nodes:
            continue
        for node in material.node_tree.nodes:
            if node.type == "BSDF_PRINCIPLED":
                yield material, node


def coloured(scene):
    """A colour grid (Blender's generated image) into every Principled BSDF's Base Color."""
    image = bpy.data.images.new("bench_colour", 1024, 1024)
    image.generated_type = "COLOR_GRID"
    for material, node in _bsdfs():
        texture = material.node_tree.nodes.new("ShaderNodeTexImage")
        texture.image = image
        material.node_tree.links.new(texture.outputs["Color"], node.inputs["Base Color"])


def normal_mapped(scene):
    """The colour grid, and a normal map of gentle waves into every BSDF's Normal."""
    import numpy as np
    coloured(scene)
    image = bpy.data.images.new("bench_normal", 1024, 1024)
    image.colorspace_settings.name = "Non-Color"
    u = np.linspace(0.0, 8.0 * np.pi, 1024, dtype=np.float32)
    slope = 0.3 * np.cos(u)[None, :].repeat(1024, axis=0)
    n = np.stack([-slope, np.zeros_like(slope), np.ones_like(slope)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    pixels = np.concatenate([0.5 * (n + 1.0), np.ones((1024, 1024, 1), np.float32)], axis=-1)
    image.pixels.foreach_set(pixels.ravel())
    for material, node in _bsdfs():
        tree = material.node_tree
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = image
        normal_map = tree.nodes.new("ShaderNodeNormalMap")
        tree.links.new(texture.outputs["Color"], normal_map.inputs["Color"])
        tree.links.new(normal_map.outputs["Normal"], node.inputs["Normal"])


CONFIGURATIONS = [("plain", plain), ("colour", coloured), ("colour+normal", normal_mapped)]


def main():
    args = example_configurations.arguments("textures.json")
    example_configurations.run("TEXTURES", "textures.py", "textures", CONFIGURATIONS, args)
    os._exit(0)


main()
