"""What differs between the Blender versions the add-on runs on, in one place."""
import bpy

BLENDER_4 = bpy.app.version >= (4, 0, 0)
# 5.0: every material and world has a node tree; use_nodes is always True and deprecated.
BLENDER_5 = bpy.app.version >= (5, 0, 0)

# Principled BSDF inputs that were renamed or changed meaning in 4.0 (docs/PRINCIPLED.md).
PRINCIPLED_SPECULAR = "Specular IOR Level" if BLENDER_4 else "Specular"
# The subsurface colour: 3.x has its own input, 4.x uses the base colour.
PRINCIPLED_SUBSURFACE_COLOR = "Base Color" if BLENDER_4 else "Subsurface Color"
PRINCIPLED_SUBSURFACE_RADIUS = "Subsurface Radius"
# What scales the radius: 3.x the Subsurface weight (as Cycles 3.x), 4.x Subsurface Scale.
PRINCIPLED_SUBSURFACE_SCALE = "Subsurface Scale" if BLENDER_4 else "Subsurface"
# 4.x's mix of diffuse and subsurface, which SubSplat does not make (3.x has no such input: its
# Subsurface is the scale above).
PRINCIPLED_SUBSURFACE_WEIGHT = "Subsurface Weight" if BLENDER_4 else None


def needs_blender_corner_normals(mesh):
    """Whether a mesh's corner normals must be Blender's own (4.x, custom split normals, auto
    smooth) rather than the add-on's deterministic smooth normals."""
    return BLENDER_4 or mesh.has_custom_normals or mesh.use_auto_smooth


def blender_corner_normals(mesh, out):
    """Blender's corner normals into a float32 array of 3 per loop: mesh.corner_normals in 4.x,
    calc_normals_split and the loops' normals in 3.x."""
    if BLENDER_4:
        mesh.corner_normals.foreach_get("vector", out)
    else:
        mesh.calc_normals_split()
        mesh.loops.foreach_get("normal", out)
    return out


def uses_nodes(idblock):
    """Whether a material or world renders through its node tree (always from 5.0 on, where reading
    use_nodes is deprecated)."""
    return idblock.node_tree is not None and (BLENDER_5 or idblock.use_nodes)


def light_strength(light):
    """A light's power as Cycles renders it: its energy times 2 ** exposure (4.5 and 5.0 have an
    exposure; 3.x and 4.2 do not)."""
    return light.energy * 2.0 ** getattr(light, "exposure", 0.0)
