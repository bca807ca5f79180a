"""Writes tests/bpy/principled_3_4.blend with Blender 3.4 (docs/PRINCIPLED.md, "Principled v1 and v2"):
four Principled BSDFs (v1) that tests/bpy/test_versions.py opens in every version, where Blender
4.x converts them to v2.

    blender -b --factory-startup --python tests/bpy/make_principled_3_4.py
"""
import os

import bpy

# name: Subsurface, Base Color, Subsurface Color, Subsurface Radius, IOR, Specular
MATERIALS = {"A": (1.0, (0.2, 0.3, 0.4), (0.8, 0.5, 0.3), (1.0, 0.5, 0.25), 1.45, 0.5),
             "B": (0.1, (0.2, 0.3, 0.4), (0.8, 0.5, 0.3), (1.0, 0.5, 0.25), 1.45, 0.5),
             "C": (0.0, (0.2, 0.3, 0.4), (0.8, 0.5, 0.3), (1.0, 0.5, 0.25), 1.45, 0.2),
             "D": (0.5, (0.8, 0.5, 0.3), (0.8, 0.5, 0.3), (1.0, 0.5, 0.25), 1.3, 0.8)}

assert bpy.app.version[:2] == (3, 4), "the file is Blender 3.4's"
bpy.ops.wm.read_homefile(use_empty=True)
for name, (subsurface, base, colour, radius, ior, specular) in MATERIALS.items():
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    material.use_fake_user = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Subsurface"].default_value = subsurface
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    bsdf.inputs["Subsurface Color"].default_value = (*colour, 1.0)
    bsdf.inputs["Subsurface Radius"].default_value = radius
    bsdf.inputs["IOR"].default_value = ior
    bsdf.inputs["Specular"].default_value = specular
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(os.path.dirname(os.path.abspath(__file__)), "principled_3_4.blend"),
                            compress=True)
