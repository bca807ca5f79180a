"""Time spent sending materials to the library in each of three renders of one .blend, in one Blender
process: each render has a new native context, as each F12 render in Blender's UI does. Dipole
splat kernels are shared by the process (SplatKernel::forDipole), so renders after the first find
them built (docs/RELIABILITY.md, "Material kernels").

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        example_blends/skin_suzanne.blend --python bench/material_reuse.py
"""
import cProfile
import pstats

import bpy

scene = bpy.context.scene
scene.render.resolution_percentage = 10
for render in range(3):
    profile = cProfile.Profile()
    profile.enable()
    bpy.ops.render.render()
    profile.disable()
    seconds = sum(entry[3] for key, entry in pstats.Stats(profile).stats.items() if key[2] == "set_material")
    print(f"render {render + 1}: set_material {1000 * seconds:.0f} ms", flush=True)
