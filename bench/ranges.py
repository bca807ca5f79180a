"""Scattering range against object size: R_P (95 % of a profile's energy; every colour channel and,
for a heterogeneous material, every palette profile) over the bounding radius (half the box
diagonal) of each translucent object of the open .blend. The paper's Table 1 scenes span 0.04-0.35.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        example_blends/heterogeneous.blend --python bench/ranges.py
"""
import bpy


def object_ranges(scene):
    """{object name: (shortest, longest) R_P over its bounding radius} for translucent objects."""
    from mathutils import Vector
    from subsplat import native
    from subsplat.export import materials
    result = {}
    for obj in scene.objects:
        if obj.type != "MESH":
            continue
        corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
        centre = sum(corners, Vector()) / 8
        radius = max((c - centre).length for c in corners)
        for slot in obj.material_slots:
            material = slot.material
            if material is None or not material.subsplat.enabled:
                continue
            ranges = list(native.profile_info(materials.material_data(material)).effective_range)
            profiles = materials.source_profiles(material)
            if profiles is not None:  # heterogeneous: every profile of the palette
                ranges += [r / material.subsplat.mm_per_unit for r in profiles.info()["effective_range_mm"]]
            lo, hi = result.get(obj.name, (float("inf"), 0.0))
            result[obj.name] = (min(lo, min(ranges) / radius), max(hi, max(ranges) / radius))
    return result


if __name__ == "__main__":
    for name, (lo, hi) in object_ranges(bpy.context.scene).items():
        print(f"{name}: R_P / bounding radius {lo:.3f} - {hi:.3f}")
