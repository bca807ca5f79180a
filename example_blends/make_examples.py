"""Regenerates the example scenes of example_blends/ (deterministic).

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        --python example_blends/make_examples.py [-- NAME ...]

Each scene is built from Blender primitives, so nothing is downloaded.
"""
import math
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))


def reset():
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "SUBSPLAT"
    scene.render.resolution_x, scene.render.resolution_y = 800, 600
    scene.render.resolution_percentage = 100
    scene.subsplat.irradiance_resolution = 512
    world = bpy.data.worlds.new("World")
    world.color = (0.02, 0.02, 0.025)
    scene.world = world
    return scene


def translucent(name, preset, mm_per_unit, roughness=0.35, specular=0.4):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    settings = material.subsplat
    settings.enabled = True
    settings.preset = preset
    settings.mm_per_unit = mm_per_unit
    settings.roughness = roughness
    settings.specular = specular
    return material


def opaque(name, color, roughness=0.8):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Specular"].default_value = 0.2
    return material


def floor(size=12.0, z=-1.0):
    bpy.ops.mesh.primitive_plane_add(size=size, location=(0, 0, z))
    plane = bpy.context.object
    plane.name = "Floor"
    plane.data.materials.append(opaque("Floor", (0.35, 0.35, 0.38)))
    return plane


def camera(location, target, lens=50.0):
    bpy.ops.object.camera_add(location=location)
    cam = bpy.context.object
    direction = (target[0] - location[0], target[1] - location[1], target[2] - location[2])
    cam.rotation_euler = _look_rotation(direction)
    cam.data.lens = lens
    bpy.context.scene.camera = cam
    return cam


def _look_rotation(direction):
    from mathutils import Vector
    return Vector(direction).to_track_quat("-Z", "Y").to_euler()


def light(kind, location, target=(0, 0, 0), energy=100.0, color=(1, 1, 1), **extra):
    data = bpy.data.lights.new(f"{kind.title()}Light", kind)
    data.energy = energy
    data.color = color
    for key, value in extra.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(data.name, data)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = location
    direction = (target[0] - location[0], target[1] - location[1], target[2] - location[2])
    obj.rotation_euler = _look_rotation(direction)
    return obj


def skin_suzanne():
    """Suzanne in skin, lit from behind and the side: light bleeds through ears and nose."""
    scene = reset()
    bpy.ops.mesh.primitive_monkey_add(size=2.0, location=(0, 0, 0))
    head = bpy.context.object
    head.name = "Suzanne"
    modifier = head.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels = modifier.render_levels = 2
    bpy.ops.object.shade_smooth()
    head.data.materials.append(translucent("Skin", "SKIN1", mm_per_unit=50.0))
    floor()
    camera((0.0, -6.5, 1.2), (0, 0, 0.1))
    light("SPOT", (2.5, 3.0, 2.0), energy=2500.0, spot_size=math.radians(50), spot_blend=0.3,
          color=(1.0, 0.95, 0.9), shadow_soft_size=0.0)
    light("POINT", (-3.0, -3.0, 1.5), energy=300.0, color=(0.8, 0.85, 1.0), shadow_soft_size=0.0)
    return scene


def marble_pieces():
    """Marble sphere and cream cylinder lit from behind by a low sun: glowing rims, soft terminators."""
    scene = reset()
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.8, location=(-0.9, 0, -0.2), segments=64, ring_count=32)
    bpy.ops.object.shade_smooth()
    sphere = bpy.context.object
    sphere.name = "MarbleSphere"
    marble = translucent("Marble", "MARBLE", mm_per_unit=100.0, roughness=0.2, specular=0.5)
    sphere.data.materials.append(marble)
    bpy.ops.mesh.primitive_cylinder_add(radius=0.5, depth=1.8, location=(0.9, 0.3, -0.1), vertices=64)
    bpy.ops.object.shade_smooth()
    cylinder = bpy.context.object
    cylinder.data.use_auto_smooth = True  # sharp cap edges, smooth sides
    cylinder.data.auto_smooth_angle = math.radians(30)
    cylinder.name = "CreamCylinder"
    cylinder.data.materials.append(translucent("Cream", "CREAM", mm_per_unit=100.0))
    floor()
    camera((0.0, -6.0, 1.5), (0, 0, -0.2))
    light("SUN", (-2, 4, 1.5), target=(0, 0, 0), energy=5.0, color=(1.0, 0.97, 0.92), angle=0.0)
    light("POINT", (2.5, -3.0, 2.5), energy=150.0, color=(0.7, 0.8, 1.0), shadow_soft_size=0.0)
    return scene


def wax_jade():
    """A wax candle and a jade monkey, small against their scattering ranges (1 unit = 40 mm): light
    crosses whole objects, the case the paper's method is for (R_P 0.1-0.5 of the bounding radius)."""
    scene = reset()
    bpy.ops.mesh.primitive_cylinder_add(radius=0.5, depth=1.8, location=(0.75, 0.35, -0.1), vertices=64)
    bpy.ops.object.shade_smooth()
    candle = bpy.context.object
    candle.name = "WaxCandle"
    candle.data.use_auto_smooth = True
    candle.data.auto_smooth_angle = math.radians(30)
    candle.data.materials.append(translucent("Wax", "SKIMMILK", mm_per_unit=40.0, roughness=0.4, specular=0.3))
    bpy.ops.mesh.primitive_monkey_add(size=1.3, location=(-0.7, -0.2, -0.35))
    monkey = bpy.context.object
    monkey.name = "JadeMonkey"
    monkey.rotation_euler = (0.0, 0.0, math.radians(-20))
    modifier = monkey.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels = modifier.render_levels = 2
    bpy.ops.object.shade_smooth()
    jade = translucent("Jade", "MARBLE", mm_per_unit=40.0, roughness=0.15, specular=0.6)
    jade.subsplat.sigma_a = (0.25, 0.02, 0.15)  # typed by hand: the preset becomes Custom
    jade.subsplat.sigma_s_prime = (1.0, 1.3, 1.0)
    monkey.data.materials.append(jade)
    floor()
    camera((0.0, -5.5, 1.3), (0, 0, -0.2))
    light("SPOT", (1.5, 3.5, 1.8), energy=1500.0, spot_size=math.radians(45), spot_blend=0.3,
          color=(1.0, 0.9, 0.75), shadow_soft_size=0.0)
    light("POINT", (-2.5, -3.0, 2.0), energy=200.0, color=(0.75, 0.85, 1.0), shadow_soft_size=0.0)
    return scene


def subedit(name, file, mm_per_unit, roughness=0.3, specular=0.4):
    """A heterogeneous material from example_blends/materials/ (make_materials.py), by relative path."""
    material = translucent(name, "MARBLE", mm_per_unit, roughness, specular)
    material.subsplat.source = "SUBEDIT_FILE"
    material.subsplat.subedit_path = f"//materials/{file}.exr"
    return material


def heterogeneous():
    """Heterogeneous SubEdit materials (make_materials.py): a veined marble sphere, a candle of milky
    and clear wax bands (short and long scattering side by side), a cloudy jade monkey, on a
    marble chessboard slab. R_P over each object's bounding radius (half its box diagonal): marble
    0.04-0.13, wax 0.02-0.35, jade 0.08-0.32, the mix of the paper's Table 1 (0.04-0.35); the slab,
    a floor, 0.006-0.018."""
    scene = reset()
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.7, location=(-1.1, 0.4, -0.3), segments=64, ring_count=32)
    bpy.ops.object.shade_smooth()
    bpy.context.object.name = "VeinedMarble"
    bpy.context.object.data.materials.append(subedit("VeinedMarble", "veined_marble", mm_per_unit=60.0,
                                                     roughness=0.2, specular=0.5))
    bpy.ops.mesh.primitive_cylinder_add(radius=0.4, depth=1.6, location=(0.9, 0.6, -0.2), vertices=64)
    bpy.ops.object.shade_smooth()
    candle = bpy.context.object
    candle.name = "BandedWax"
    candle.data.use_auto_smooth = True
    candle.data.auto_smooth_angle = math.radians(30)
    candle.data.materials.append(subedit("BandedWax", "varying_wax", mm_per_unit=310.0, roughness=0.4))
    bpy.ops.mesh.primitive_monkey_add(size=0.9, location=(0.0, -0.6, -0.55))
    monkey = bpy.context.object
    monkey.name = "CloudyJade"
    monkey.rotation_euler = (0.0, 0.0, math.radians(-15))
    modifier = monkey.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels = modifier.render_levels = 1
    bpy.ops.object.shade_smooth()
    monkey.data.materials.append(subedit("CloudyJade", "jade", mm_per_unit=40.0, roughness=0.15, specular=0.6))
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0, 0, -1.1))
    slab = bpy.context.object
    slab.name = "ChessboardSlab"
    slab.scale = (4.0, 3.0, 0.2)
    slab.data.materials.append(subedit("MarbleChessboard", "marble_chessboard", mm_per_unit=200.0))
    camera((0.0, -5.5, 1.6), (0, 0, -0.5))
    light("SPOT", (1.5, 3.5, 2.0), energy=1800.0, spot_size=math.radians(55), spot_blend=0.3,
          color=(1.0, 0.93, 0.85), shadow_soft_size=0.0)
    light("SUN", (-3, -2, 3), energy=2.0, color=(0.8, 0.85, 1.0), angle=0.0)
    return scene


def capsule_mesh(name, radius, length, segments=48, rings=48, cap_rings=8, taper=0.0):
    """A capsule along +z from its base at z = 0 (a candle, a finger): a side of `rings` rows, so it
    bends smoothly, a flat base and a rounded tip; u runs around, v along. `taper` narrows the tip."""
    import numpy as np
    rows = []  # (z, radius, v) from the base up
    for i in range(rings + 1):
        t = i / rings
        rows.append((t * length, radius * (1.0 - taper * t), 0.1 + 0.8 * t))
    tip = radius * (1.0 - taper)
    for i in range(1, cap_rings):
        a = 0.5 * math.pi * i / cap_rings
        rows.append((length + tip * math.sin(a), tip * math.cos(a), 0.9 + 0.1 * i / cap_rings))
    vertices, uvs_by_vertex = [], []
    for z, r, v in rows:
        for j in range(segments + 1):  # the seam column is doubled for the UVs
            angle = 2.0 * math.pi * j / segments
            vertices.append((r * math.cos(angle), r * math.sin(angle), z))
            uvs_by_vertex.append((j / segments, v))
    columns = segments + 1
    faces = []
    for i in range(len(rows) - 1):
        for j in range(segments):
            a = i * columns + j
            faces.append((a, a + 1, a + 1 + columns, a + columns))
    top = len(vertices)
    vertices.append((0.0, 0.0, length + tip))
    uvs_by_vertex.append((0.5, 1.0))
    last = (len(rows) - 1) * columns
    faces += [(last + j, last + j + 1, top) for j in range(segments)]
    bottom = len(vertices)
    vertices.append((0.0, 0.0, 0.0))
    uvs_by_vertex.append((0.5, 0.0))
    faces += [(j + 1, j, bottom) for j in range(segments)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    mesh.update()
    layer = mesh.uv_layers.new(name="UVMap")
    loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    layer.data.foreach_set("uv", np.asarray(uvs_by_vertex, dtype=np.float32)[loop_vertex].ravel())
    for polygon in mesh.polygons:
        polygon.use_smooth = True
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def keyframes(owner, path, frames_values):
    for frame, value in frames_values:
        setattr(owner, path, value)
        owner.keyframe_insert(path, frame=frame)


def candle_twist():
    """A candle of milky and clear wax bands (varying_wax.exr, heterogeneous) that bends and twists
    over 48 frames (Simple Deform modifiers): a deforming mesh with nothing precomputed per frame."""
    scene = reset()
    scene.frame_start, scene.frame_end = 1, 48
    candle = capsule_mesh("TwistingCandle", radius=0.3, length=1.8, segments=64, rings=60)
    candle.location = (0.0, 0.0, -1.0)
    candle.data.materials.append(subedit("BandedWax", "varying_wax", mm_per_unit=310.0, roughness=0.4))
    twist = candle.modifiers.new("Twist", "SIMPLE_DEFORM")
    twist.deform_method, twist.deform_axis = "TWIST", "Z"
    keyframes(twist, "angle", [(1, 0.0), (48, math.radians(180))])
    bend = candle.modifiers.new("Bend", "SIMPLE_DEFORM")
    bend.deform_method, bend.deform_axis = "BEND", "Y"
    keyframes(bend, "angle", [(1, 0.0), (24, math.radians(70)), (48, math.radians(-40))])
    floor(z=-1.0)
    camera((0.0, -5.0, 0.9), (0, 0, 0.0))
    light("SPOT", (1.2, 2.8, 1.6), energy=1500.0, spot_size=math.radians(55), spot_blend=0.3,
          color=(1.0, 0.9, 0.75), shadow_soft_size=0.0)
    light("SUN", (-3, -2, 3), energy=2.0, color=(0.8, 0.85, 1.0), angle=0.0)
    return scene


def finger_pose():
    """A skin finger (three armature bones, weighted by hand) that curls from straight to bent over
    24 frames while a shape key swells its knuckles: a character-like pose change, backlit."""
    scene = reset()
    scene.frame_start, scene.frame_end = 1, 24
    finger = capsule_mesh("Finger", radius=0.22, length=2.0, segments=48, rings=72, taper=0.25)
    finger.rotation_euler = (0.0, math.radians(90), 0.0)  # along +x
    finger.location = (-1.1, 0.0, -0.6)
    finger.data.materials.append(translucent("Skin", "SKIN1", mm_per_unit=40.0))
    # Shape key: the knuckles swell as the finger bends.
    finger.shape_key_add(name="Basis")
    swell = finger.shape_key_add(name="Knuckles")
    for vertex, key in zip(finger.data.vertices, swell.data):
        z = vertex.co.z
        bump = sum(math.exp(-((z - k) / 0.12) ** 2) for k in (0.7, 1.35))
        key.co = (vertex.co.x * (1 + 0.12 * bump), vertex.co.y * (1 + 0.12 * bump), z)
    keyframes(swell, "value", [(1, 0.0), (24, 1.0)])
    # Armature: three bones along the finger's local z, weights blended across each joint.
    armature_data = bpy.data.armatures.new("FingerRig")
    rig = bpy.data.objects.new("FingerRig", armature_data)
    scene.collection.objects.link(rig)
    rig.location, rig.rotation_euler = finger.location, finger.rotation_euler
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    joints = (0.0, 0.7, 1.35, 2.2)
    bones = []
    for k in range(3):
        bone = armature_data.edit_bones.new(f"Phalanx{k}")
        bone.head, bone.tail = (0, 0, joints[k]), (0, 0, joints[k + 1])
        if bones:
            bone.parent, bone.use_connect = bones[-1], True
        bones.append(bone)
    bpy.ops.object.mode_set(mode="OBJECT")
    groups = [finger.vertex_groups.new(name=f"Phalanx{k}") for k in range(3)]
    for vertex in finger.data.vertices:
        z = vertex.co.z
        weights = [0.0, 0.0, 0.0]
        for k in range(3):
            low, high = joints[k], joints[k + 1]
            inside = min(max((z - low) / 0.15 + 0.5, 0.0), 1.0) if k > 0 else 1.0
            below = min(max((high - z) / 0.15 + 0.5, 0.0), 1.0) if k < 2 else 1.0
            weights[k] = inside * below
        total = sum(weights) or 1.0
        for k in range(3):
            if weights[k] > 0.0:
                groups[k].add([vertex.index], weights[k] / total, "REPLACE")
    finger.modifiers.new("Armature", "ARMATURE").object = rig
    for k, bend in enumerate((55, 70, 45)):
        pose = rig.pose.bones[f"Phalanx{k}"]
        pose.rotation_mode = "XYZ"
        keyframes(pose, "rotation_euler", [(1, (0.0, 0.0, 0.0)), (24, (0.0, 0.0, math.radians(bend)))])
    floor(z=-1.0)
    camera((0.0, -5.5, 1.0), (0.0, 0, -0.1))
    light("SPOT", (0.8, 2.6, 1.2), energy=1200.0, spot_size=math.radians(60), spot_blend=0.3,
          color=(1.0, 0.95, 0.9), shadow_soft_size=0.0)
    light("SUN", (-3, -2, 3), energy=2.0, color=(0.8, 0.85, 1.0), angle=0.0)
    return scene


EXAMPLES = {"skin_suzanne": skin_suzanne, "marble_pieces": marble_pieces, "wax_jade": wax_jade,
            "heterogeneous": heterogeneous, "candle_twist": candle_twist, "finger_pose": finger_pose}


def main():
    only = [a for a in sys.argv[sys.argv.index("--") + 1:]] if "--" in sys.argv else list(EXAMPLES)
    for name, build in EXAMPLES.items():
        if name not in only:
            continue
        build()
        path = os.path.join(HERE, f"{name}.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
