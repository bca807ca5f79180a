"""Materials and scenes shared by the tests of SubEdit files, Principled and artist materials, and
the hard cases: a translucent material, a lit UV sphere, baking, a chessboard SubEdit file."""
import math

import bpy
import numpy as np

from subsplat_testing import helpers


def translucent(name, preset="SKIN1", mm_per_unit=100.0, profile_model="DIPOLE"):
    """A translucent material of a preset medium. Its profile model is the classical dipole unless
    asked: these tests compare a material with its baked SubEdit file, which holds radial profiles
    alone, and the dipole is the model that is nothing more (the TABULATED model's angular and
    thin-part factors are a homogeneous material's: docs/TRANSPORT.md)."""
    material = bpy.data.materials.new(name)
    material.subsplat.enabled = True
    material.subsplat.preset = preset
    material.subsplat.mm_per_unit = mm_per_unit
    material.subsplat.profile_model = profile_model
    return material


def sphere_scene(make_material, size=64):
    """A UV sphere of radius 0.3 (with its UV map) lit by a sun from the side and a spot light
    from behind, seen from above, with the material make_material() creates (after the new file).
    Irradiance buffers of 128^2 texels: enough for images this small, and quick."""
    scene = helpers.empty_scene(size, size)
    scene.render.engine = "SUBSPLAT"
    scene.subsplat.method = "FULL"
    scene.subsplat.irradiance_resolution = 128
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=0.3)
    obj = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    material = make_material()
    obj.data.materials.append(material)
    helpers.top_down_camera(scene, ortho_scale=0.8)
    helpers.add_light(scene, "SUN", rotation=(math.radians(60), 0, 0), energy=3.0, angle=0.0)
    helpers.add_light(scene, "SPOT", location=(-0.3, 0, -0.9), energy=30.0, shadow_soft_size=0.0,
                      spot_size=math.radians(60))
    return scene, obj, material


def bake(material, path):
    with bpy.context.temp_override(material=material):
        result = bpy.ops.subsplat.bake_subedit(filepath=path)
    assert result == {"FINISHED"}, result
    return path


def relative_difference(a, b):
    """Sum of |a - b| over the sum of |a| on pixels where either shows the object."""
    mask = (a[..., 3] > 0) | (b[..., 3] > 0)
    return float(np.abs(a[mask, :3] - b[mask, :3]).sum() / max(np.abs(a[mask, :3]).sum(), 1e-30))


def chessboard_file(path, squares=4):
    """Marble and skin squares (the add-on's presets), written with the library's own writer."""
    import subsplat
    media = subsplat.presets.MEASURED_MEDIA
    sigma_a = np.empty((squares, squares, 3), dtype=np.float32)
    sigma_s = np.empty_like(sigma_a)
    for y in range(squares):
        for x in range(squares):
            _label, s, a = media["MARBLE" if (x + y) % 2 == 0 else "SKIN1"]
            sigma_a[y, x], sigma_s[y, x] = a, s
    profiles = subsplat.native.ProfileSet.from_dipoles(sigma_a, sigma_s, subsplat.presets.MEASURED_ETA)
    profiles.save(path)
    return profiles.info()
