"""Physical truth in Cycles: a homogeneous medium as a volume inside a mesh, and the half-space scenes
of the truth harness's own check (bench/truth_halfspace.py, tests/blender/test_truth.py).

The medium is the same physics the Cycles twin uses (issue 18): Volume Scatter (anisotropy 0) +
Volume Absorption inside a Transparent BSDF boundary (eta = 1). In Blender 3.4 Cycles,
sigma_s = colour x density (Volume Scatter) and sigma_a = (1 - colour) x density (Volume Absorption),
per Blender unit: with colour = albedo a and density = sigma_t for both, sigma_s = a sigma_t and
sigma_a = (1 - a) sigma_t. Cycles is set to converge to the transport equation's answer: 1024 bounces
of every kind, no clamping, no denoising, no adaptive sampling, Standard view transform, exposure 0.
"""
import math

import bpy

from subsplat_testing import helpers

BOUNCES = 1024  # Blender's maximum


def volume_material(name, albedo, sigma_t):
    """Transparent boundary (eta = 1) around Volume Scatter (g = 0) + Volume Absorption.
    albedo: a float or an RGB triple; sigma_t: extinction per Blender unit (a float or an RGB triple)."""
    def rgb(v):
        return tuple(v) if isinstance(v, (tuple, list)) else (v, v, v)
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    tree = material.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    transparent = tree.nodes.new("ShaderNodeBsdfTransparent")
    transparent.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    tree.links.new(transparent.outputs["BSDF"], out.inputs["Surface"])
    a, s = rgb(albedo), rgb(sigma_t)
    if len(set(s)) > 1:
        raise ValueError("one density per node: use a grey sigma_t (or one material per channel)")
    scatter = tree.nodes.new("ShaderNodeVolumeScatter")
    scatter.inputs["Color"].default_value = (*a, 1.0)
    scatter.inputs["Density"].default_value = s[0]
    scatter.inputs["Anisotropy"].default_value = 0.0
    absorption = tree.nodes.new("ShaderNodeVolumeAbsorption")
    absorption.inputs["Color"].default_value = (*a, 1.0)  # sigma_a = (1 - colour) x density
    absorption.inputs["Density"].default_value = s[0]
    add = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(scatter.outputs["Volume"], add.inputs[0])
    tree.links.new(absorption.outputs["Volume"], add.inputs[1])
    tree.links.new(add.outputs["Shader"], out.inputs["Volume"])
    if hasattr(material.cycles, "homogeneous_volume"):  # 5.0 has no such setting
        material.cycles.homogeneous_volume = True
    material.cycles.volume_interpolation = "LINEAR"
    return material


def box(scene, name, size, top, material):
    """An axis-aligned box, size (x, y, z), its top face at z = top, centred on the z axis."""
    sx, sy, sz = (v / 2 for v in size)
    z0, z1 = top - 2 * sz, top
    verts = [(-sx, -sy, z0), (sx, -sy, z0), (sx, sy, z0), (-sx, sy, z0),
             (-sx, -sy, z1), (sx, -sy, z1), (sx, sy, z1), (-sx, sy, z1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def converge_settings(scene, samples, seed=0):
    """Cycles set to converge to the transport equation (no bias of its own beyond the bounce cap)."""
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.seed = seed
    c.use_animated_seed = False
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = BOUNCES
    c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = BOUNCES
    c.volume_bounces = c.transparent_max_bounces = BOUNCES
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    c.light_sampling_threshold = 0.0
    c.min_light_bounces = 0
    c.min_transparent_bounces = 0
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.use_persistent_data = True


def orthographic_camera(scene, mu, azimuth=0.0, ortho_scale=1.0, distance=5.0, target=(0.0, 0.0, 0.0)):
    """An orthographic camera looking at `target` from direction cosine mu (to +z), in the plane at
    `azimuth` (radians from +x)."""
    data = bpy.data.cameras.new("TruthCamera")
    data.type = "ORTHO"
    data.ortho_scale = ortho_scale
    data.clip_start, data.clip_end = 0.01, 1.0e4
    cam = bpy.data.objects.new("TruthCamera", data)
    theta = math.acos(max(-1.0, min(1.0, mu)))
    d = (math.sin(theta) * math.cos(azimuth), math.sin(theta) * math.sin(azimuth), math.cos(theta))
    cam.location = tuple(t + distance * v for t, v in zip(target, d))
    # Blender cameras look down their local -z: rotate +z onto d (about the axis z x d).
    cam.rotation_mode = "XYZ"
    import mathutils
    cam.rotation_euler = mathutils.Vector(d).to_track_quat("Z", "Y").to_euler()
    scene.collection.objects.link(cam)
    scene.camera = cam
    return cam


def sun(scene, mu0, strength, azimuth=math.pi):
    """A delta sun (angle 0) of `strength` (irradiance on a plane facing it) shining from direction
    cosine mu0, its direction in the plane at `azimuth` (radians from +x; pi: opposite a camera at 0)."""
    data = bpy.data.lights.new("TruthSun", "SUN")
    data.energy = strength
    data.angle = 0.0
    obj = bpy.data.objects.new("TruthSun", data)
    theta = math.acos(mu0)
    d = (math.sin(theta) * math.cos(azimuth), math.sin(theta) * math.sin(azimuth), math.cos(theta))
    import mathutils
    # A sun shines down its local -z: point its +z at the direction it comes from.
    obj.rotation_euler = mathutils.Vector(d).to_track_quat("Z", "Y").to_euler()
    scene.collection.objects.link(obj)
    return obj


def halfspace_scene(albedo, sigma_t, mu0, mu, strength=1.0, size_px=8, samples=64, seed=0,
                    depth_mfp=100.0, width_mfp=400.0, patch_mfp=10.0):
    """A box of the medium `depth_mfp` mean free paths deep and `width_mfp` wide (a half-space for
    light that enters far from its sides), top face at z = 0, lit by a sun at mu0 and seen by an
    orthographic camera at mu over a central patch `patch_mfp` wide. Empty black world."""
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = size_px
    scene.render.resolution_percentage = 100
    world = bpy.data.worlds.new("World")
    helpers.set_world_colour(world, (0.0, 0.0, 0.0))
    scene.world = world
    mfp = 1.0 / sigma_t
    box(scene, "HalfSpace", (width_mfp * mfp, width_mfp * mfp, depth_mfp * mfp), 0.0,
        volume_material("HalfSpaceMedium", albedo, sigma_t))
    # The patch's footprint on the surface is patch_mfp wide across and patch_mfp / mu along.
    orthographic_camera(scene, mu, ortho_scale=patch_mfp * mfp, distance=max(5.0, 2 * patch_mfp * mfp))
    sun(scene, mu0, strength)
    converge_settings(scene, samples, seed)
    return scene


# The half-space check (bench/truth_halfspace.py): two media, a sun at 0, 60 and 80 degrees seen
# from above, one oblique view, and uniform light from the sky. sigma_t = 10 per unit: 1 mean free path is
# 0.1 units; the box is 100 mfp deep and 400 mfp wide (17 and 70 diffusion lengths at a = 0.99).
SIGMA_T = 10.0
MEDIA = {"a0.99": 0.99, "a0.8": 0.8}
CASES = [  # (name, medium, light, mu0, mu); light "sun" (strength 1) or "sky" (uniform radiance 1)
    ("sun0_view0", "a0.99", "sun", 1.0, 1.0),
    ("sun60_view0", "a0.99", "sun", 0.5, 1.0),
    ("sun80_view0", "a0.99", "sun", math.cos(math.radians(80.0)), 1.0),
    ("sun0_view60", "a0.99", "sun", 1.0, 0.5),
    ("sky_view0", "a0.99", "sky", None, 1.0),
    ("sun0_view0", "a0.8", "sun", 1.0, 1.0),
    ("sun60_view0", "a0.8", "sun", 0.5, 1.0),
    ("sun80_view0", "a0.8", "sun", math.cos(math.radians(80.0)), 1.0),
    ("sun0_view60", "a0.8", "sun", 1.0, 0.5),
    ("sky_view0", "a0.8", "sky", None, 1.0),
]


def exact(albedo, light, mu0, mu):
    """The H-function radiance of a case (sun of strength 1, or sky of radiance 1)."""
    from subsplat_testing import hfunction
    if light == "sun":
        return hfunction.sun_radiance(albedo, 1.0, mu0, mu)
    return hfunction.L_uniform(albedo, 1.0, mu)


def case_scene(medium, light, mu0, mu, size_px, samples, seed):
    albedo = MEDIA[medium]
    scene = halfspace_scene(albedo, SIGMA_T, mu0 if light == "sun" else 1.0, mu, size_px=size_px,
                            samples=samples, seed=seed)
    if light == "sky":
        for obj in [o for o in scene.objects if o.type == "LIGHT"]:
            bpy.data.objects.remove(obj)
        helpers.set_world_colour(scene.world, (1.0, 1.0, 1.0))
    return scene


def twin_case_scene(medium, light, mu0, mu, size_px, samples, seed):
    """The same case through the Cycles twin (addon/subsplat/twin.py; the add-on enabled): the box
    holds a SubSplat material (DIPOLE source, eta = 1, 1 mm per unit, sigma_a = (1 - a) sigma_t and
    sigma_s' = a sigma_t per mm), and the twin scene it makes is rendered with its own settings; only
    the samples, seed and device are set here. Leaves the twin scene the window's scene."""
    import subsplat
    scene = case_scene(medium, light, mu0, mu, size_px, samples, seed)
    albedo = MEDIA[medium]
    material = bpy.data.materials.new("HalfSpaceSubSplat")
    material.subsplat.enabled = True
    material.subsplat.preset = "CUSTOM"
    material.subsplat.mm_per_unit = 1.0
    material.subsplat.sigma_a = ((1.0 - albedo) * SIGMA_T,) * 3
    material.subsplat.sigma_s_prime = (albedo * SIGMA_T,) * 3
    material.subsplat.eta = 1.0
    scene.objects["HalfSpace"].data.materials[0] = material
    twin_scene, reports = subsplat.twin.make_cycles_twin(scene)
    for level, text in reports:
        if level == "ERROR":
            raise RuntimeError(f"twin: {text}")
    twin_scene.cycles.device = "CPU"
    twin_scene.cycles.samples = samples
    twin_scene.cycles.seed = seed
    twin_scene.cycles.use_animated_seed = False
    bpy.context.window.scene = twin_scene
    return twin_scene


def render_pixels(scene, path):
    """Renders; the per-pixel radiance (mean of R, G, B: the media are grey), flattened."""
    import numpy as np
    from subsplat_testing import helpers
    pixels = helpers.render_to(scene, path)
    return pixels.reshape(-1, 4)[:, :3].astype(np.float64).mean(axis=1)


def measure(medium, light, mu0, mu, size_px, samples, seeds, path_prefix, first_seed=0, via="direct"):
    """Mean radiance over the central patch; its standard error, the larger of two estimates (the
    scatter of every pixel of every seed, taken as independent, and the scatter of the per-seed means,
    which holds whatever the pixels of one render share); the per-seed means and the render seconds.
    Seeds first_seed, first_seed + 1, ...: a render's first samples repeat those of a longer render
    with the same seed, so a check against a committed run uses other seeds. via: "direct" (the
    medium built here, volume_material) or "twin" (the same case through the Cycles twin)."""
    import time
    import numpy as np
    values, per_seed, seconds = [], [], 0.0
    for seed in range(first_seed, first_seed + seeds):
        make = {"direct": case_scene, "twin": twin_case_scene}[via]
        scene = make(medium, light, mu0, mu, size_px, samples, seed)
        start = time.perf_counter()
        pixels = render_pixels(scene, f"{path_prefix}_seed{seed}.exr")
        seconds += time.perf_counter() - start
        values.append(pixels)
        per_seed.append(float(pixels.mean()))
    values = np.concatenate(values)
    mean = float(values.mean())
    pixel_error = float(values.std(ddof=1) / np.sqrt(values.size))
    seed_error = float(np.std(per_seed, ddof=1) / np.sqrt(seeds)) if seeds > 1 else 0.0
    return mean, max(pixel_error, seed_error), per_seed, seconds
