"""The model against physical truth (docs/PHYSICAL.md, "The model against the truth"): the cases,
each a scene with SubSplat materials at eta = 1, and the measures, shared by bench/physical.py (which
renders every method and the Cycles twin and writes bench/results/physical.json and the pictures)
and tests/blender/test_physical.py (which ties the committed figures to the code).

Every case is index-matched (eta = 1, specular 0): its twin's boundary is a Transparent BSDF, through
which delta lights (the sun) reach the medium, so the twin converges to the transport equation's
answer (a delta light cannot be reached through a refracting boundary: docs/PHYSICAL.md).

Kinds of case, and what is measured over which pixels:
- "slab": a box 4 x 4 x 1 units (400 x 400 x 100 mm: tens of diffusion lengths, a half-space for the
  light that reaches the centre) under a sun at 0, 60 or 80 degrees, seen from straight above over a
  1-unit patch at its centre. All pixels: the radiance is uniform, so the ratio of the means per
  channel is the measure.
- "thin": a box 4 x 4 units wide and d thick (d in reduced mean free paths, 1 / sigma_t', of the green
  channel), lit from straight below by a sun, seen from above. All pixels, as the slab.
- "sphere": a sphere lit by a sun from the side (+x), seen from +z: the terminator runs down the
  middle of the picture. Measured on the horizontal band through the centre (rows within 10 % of the
  radius), averaged over its rows: a profile across the terminator, per channel; its relative RMSE, and
  the ratio of the means over the lit (x > 0) and shadowed (x < 0) halves.
- "example": an example scene with every translucent material at eta = 1 and specular 0, its open
  meshes closed (holes filled: the inside of the medium must be defined for the twin), its world black
  (the committed truths measure the translucency under the lights; the world light, docs/WORLD.md,
  is measured on its own). Pixels that REFERENCE's exitance pass marks
  translucent. An example whose materials the twin cannot convert (SubEdit files) is not measured.
"""
import math
import os

import bpy
import numpy as np

from subsplat_testing import accuracy, helpers, stability_cases

MEDIA = ("SKIN1", "MARBLE", "KETCHUP")
SLAB_ANGLES = (0.0, 60.0, 80.0)
THIN_MFP = (0.5, 1.0, 2.0, 5.0)
THIN_MEDIA = ("SKIN1", "MARBLE")
SPHERE_MFP = 10.0  # radius in reduced mean free paths (green)
EXAMPLES = ("skin_suzanne", "marble_pieces", "wax_jade", "finger_pose", "candle_twist", "heterogeneous")
KINDS = ("slab", "thin", "sphere", "example")
SUN = 5.0  # sun strength of the built cases (irradiance on a plane facing it)


def material(name, preset, mm_per_unit):
    """A SubSplat material of a measured medium, index matched (eta = 1) and without specular. Its
    profile model is the classical dipole, as bench/physical.py measured it (bench/results/
    physical.json); bench/model.py renders every case under each model (set_profile_model)."""
    m = stability_cases.translucent(name, preset, mm_per_unit)
    m.subsplat.eta = 1.0
    m.subsplat.specular = 0.0
    accuracy.principled_equivalent(m)  # EEVEE's and Cycles' Principled set-up of the same medium
    return m


def green_mfp_mm(preset):
    """The reduced mean free path 1 / sigma_t' of the green channel, in mm."""
    from subsplat import presets
    _label, sigma_s_prime, sigma_a = presets.MEASURED_MEDIA[preset]
    return 1.0 / (sigma_s_prime[1] + sigma_a[1])


def mfp_mm(preset):
    from subsplat import presets
    _label, sigma_s_prime, sigma_a = presets.MEASURED_MEDIA[preset]
    return [1.0 / (s + a) for s, a in zip(sigma_s_prime, sigma_a)]


def sun_from(scene, degrees_from_zenith, below=False):
    """A delta sun (angle 0) of strength SUN coming from `degrees_from_zenith` off +z in the x-z plane
    (from +x), or from straight below."""
    rotation = (0.0, math.pi, 0.0) if below else (0.0, math.radians(degrees_from_zenith), 0.0)
    return helpers.add_light(scene, "SUN", rotation=rotation, energy=SUN, angle=0.0)


def outward(obj):
    """Makes the mesh's normals point out (stability_cases.slab's do not all): Cycles enters and leaves
    a volume by the normals (the twin warns of it)."""
    import bmesh
    shape = bmesh.new()
    shape.from_mesh(obj.data)
    bmesh.ops.recalc_face_normals(shape, faces=shape.faces)
    shape.to_mesh(obj.data)
    shape.free()
    obj.data.update()
    return obj


def slab_case(preset, degrees, size):
    scene = helpers.empty_scene(size, size)
    outward(stability_cases.slab(scene, 4.0, 1.0, material(preset.title(), preset, 100.0)))
    helpers.top_down_camera(scene, ortho_scale=1.0)
    sun_from(scene, degrees)
    return scene


def thin_case(preset, mfp, size):
    """A slab `mfp` reduced mean free paths (green) thick, lit from below, seen from above."""
    scene = helpers.empty_scene(size, size)
    thickness = mfp * green_mfp_mm(preset) / 100.0
    outward(stability_cases.slab(scene, 4.0, thickness, material(preset.title(), preset, 100.0)))
    helpers.top_down_camera(scene, ortho_scale=1.0)
    sun_from(scene, 0.0, below=True)
    return scene


def sphere_case(preset, size, radius_mfp=SPHERE_MFP):
    """A sphere of radius 1 unit = radius_mfp reduced mean free paths (green), lit from +x."""
    scene = helpers.empty_scene(size, size)
    mm_per_unit = radius_mfp * green_mfp_mm(preset)
    stability_cases.uv_sphere(scene, 1.0, material(preset.title(), preset, mm_per_unit))
    helpers.top_down_camera(scene, ortho_scale=2.2)
    sun_from(scene, 90.0)
    return scene


def close_holes(obj):
    """Fills the holes of a mesh (edges with one face): the twin's medium needs a closed surface."""
    import bmesh
    mesh = obj.data
    shape = bmesh.new()
    shape.from_mesh(mesh)
    boundary = [e for e in shape.edges if len(e.link_faces) == 1]
    filled = 0
    if boundary:
        result = bmesh.ops.holes_fill(shape, edges=boundary, sides=0)
        filled = len(result["faces"])
        for face in result["faces"]:
            face.smooth = True
        bmesh.ops.recalc_face_normals(shape, faces=shape.faces)
    shape.to_mesh(mesh)
    shape.free()
    mesh.update()
    return filled


def set_profile_model(model):
    """Every translucent material of the file whose source has a profile model (coefficients, a
    Principled BSDF) renders under `model`; returns the names of those that have none (SubEdit
    files, artist profiles)."""
    fixed = []
    for m in bpy.data.materials:
        if not m.subsplat.enabled:
            continue
        if m.subsplat.source in ("DIPOLE", "PRINCIPLED"):
            m.subsplat.profile_model = model
        else:
            fixed.append(m.name)
    return fixed


def example_case(name, percentage, bounce=True, profile_model="DIPOLE"):
    """The example at `percentage` %, translucent materials at eta = 1 and specular 0, open translucent
    meshes closed. bounce False: the opaque objects are seen by the camera and cast shadows but reflect
    no light onto others (Cycles' ray visibility: SubSplat, like EEVEE without probes, has no light
    bounced between objects, so this isolates the translucency model). Returns (scene, notes)."""
    scene = accuracy.open_example(name, percentage)
    notes = []
    # SubSplat lights with the scene's lights only (the world is a background colour: issue 20), so the
    # world is black here, for every renderer and the twin alike.
    world = scene.world
    if world is not None and bpy.app.version >= (5, 0, 0):  # every world renders its node tree
        world.color = (0.0, 0.0, 0.0)
        for node in (world.node_tree.nodes if world.node_tree else []):
            if node.type == "BACKGROUND":
                node.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
                node.inputs["Strength"].default_value = 0.0
        notes.append("world black")
    elif world is not None and (any(world.color) or world.use_nodes):
        world.use_nodes = False
        world.color = (0.0, 0.0, 0.0)
        notes.append("world black")
    set_profile_model(profile_model)  # the committed figures' (physical.json, TRADEOFF.md): the dipole
    for m in bpy.data.materials:
        if m.subsplat.enabled:
            m.subsplat.eta = 1.0
            m.subsplat.specular = 0.0
            if m.subsplat.source == "DIPOLE":
                accuracy.principled_equivalent(m)
    for obj in scene.objects:
        if obj.type != "MESH":
            continue
        if any(s.material and s.material.subsplat.enabled for s in obj.material_slots):
            filled = close_holes(obj)
            if filled:
                notes.append(f"{obj.name}: {filled} holes filled")
        elif not bounce:
            obj.visible_diffuse = obj.visible_glossy = obj.visible_transmission = False
            obj.visible_volume_scatter = False
            notes.append(f"{obj.name}: reflects no light onto others")
    return scene, notes


# --- the cases, by name ---------------------------------------------------------------

def cases(kinds=KINDS, size=32, percentage=10):
    """(name, kind, build() -> (scene, notes), details) of every case of the kinds asked for."""
    found = []
    if "slab" in kinds:
        for preset in MEDIA:
            for degrees in SLAB_ANGLES:
                found.append((f"slab_{preset.lower()}_{int(degrees)}", "slab",
                              lambda p=preset, d=degrees: (slab_case(p, d, size), []),
                              {"medium": preset, "sun_degrees": degrees, "thickness_mm": 100.0}))
    if "thin" in kinds:
        for preset in THIN_MEDIA:
            for mfp in THIN_MFP:
                found.append((f"thin_{preset.lower()}_{mfp:g}mfp", "thin",
                              lambda p=preset, m=mfp: (thin_case(p, m, size), []),
                              {"medium": preset, "thickness_green_mfp": mfp,
                               "thickness_mm": mfp * green_mfp_mm(preset),
                               "thickness_mfp_rgb": [mfp * green_mfp_mm(preset) / f
                                                     for f in mfp_mm(preset)]}))
    if "sphere" in kinds:
        for preset in ("SKIN1", "MARBLE"):
            found.append((f"sphere_{preset.lower()}", "sphere",
                          lambda p=preset: (sphere_case(p, size), []),
                          {"medium": preset, "radius_green_mfp": SPHERE_MFP,
                           "radius_mm": SPHERE_MFP * green_mfp_mm(preset)}))
    if "example" in kinds:
        for name in EXAMPLES:
            found.append((f"example_{name}", "example",
                          lambda n=name: example_case(n, percentage), {"percentage": percentage, "bounce": True}))
        for name in EXAMPLES:
            found.append((f"example_{name}_no_bounce", "example",
                          lambda n=name: example_case(n, percentage, bounce=False),
                          {"percentage": percentage, "bounce": False}))
    return found


# --- measures ------------------------------------------------------------------------------

def mask_for(kind, exitance):
    """Pixels measured: every pixel of a slab, REFERENCE's translucent pixels otherwise."""
    if kind in ("slab", "thin"):
        return np.ones(exitance.shape[:2], dtype=bool)
    return exitance[..., 3] > 0.5


def band_rows(height, fraction=0.1 / 1.1):
    """Rows of the horizontal band through the centre: within `fraction` of the height of it (10 % of
    the sphere's radius at ortho_scale 2.2 = 1.1 radii on each side)."""
    centre = (height - 1) / 2.0
    half = max(fraction * height, 0.5)
    return [y for y in range(height) if abs(y - centre) <= half]


def profile(image, mask):
    """The sphere's horizontal profile: per column, the mean over the band's rows that are in the
    mask, per channel; columns with no masked pixel are NaN."""
    rows = band_rows(image.shape[0])
    band, inside = image[rows, :, :3].astype(np.float64), mask[rows]
    counts = inside.sum(axis=0)
    sums = (band * inside[..., None]).sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(counts[:, None] > 0, sums / counts[:, None], np.nan)


def measure(kind, image, truth, mask):
    """Ratio of the means per channel and relative RMSE (over rgb) of `image` against `truth`; for a
    sphere also the profile's and each half's."""
    ours, theirs = image[mask][:, :3].astype(np.float64), truth[mask][:, :3].astype(np.float64)
    result = {"ratio": (ours.mean(axis=0) / np.maximum(theirs.mean(axis=0), 1e-30)).tolist(),
              "relative_rmse": float(np.sqrt(((ours - theirs) ** 2).mean()) / np.sqrt((theirs ** 2).mean()))}
    if kind == "sphere":
        p, q = profile(image, mask), profile(truth, mask)
        valid = ~np.isnan(q).any(axis=1)
        p, q = p[valid], q[valid]
        result["profile_relative_rmse"] = float(np.sqrt(((p - q) ** 2).mean()) / np.sqrt((q ** 2).mean()))
        columns = np.arange(image.shape[1])[valid]
        lit = columns > (image.shape[1] - 1) / 2.0
        for half, where in (("lit", lit), ("shadowed", ~lit)):
            result[f"{half}_ratio"] = (p[where].mean(axis=0) / np.maximum(q[where].mean(axis=0), 1e-30)).tolist()
        result["profile"] = p.tolist()
        result["truth_profile"] = q.tolist()
    return result


def truth_noise(kind, per_seed, mask):
    """The truth's noise from its seeds' renders (K arrays): the relative standard error of each
    channel's mean over the mask, and the relative RMS of the per-pixel standard error of the mean
    image (what a relative RMSE against the truth has in it from the truth's noise alone)."""
    stack = np.stack([p[..., :3].astype(np.float64) for p in per_seed])  # K, h, w, 3
    k = stack.shape[0]
    means = stack[:, mask].mean(axis=1)  # K, 3
    mean = stack.mean(axis=0)
    channel = (means.std(axis=0, ddof=1) / math.sqrt(k) / np.maximum(means.mean(axis=0), 1e-30)).tolist()
    pixel_variance = stack[:, mask].var(axis=0, ddof=1) / k  # pixels, 3
    image = float(np.sqrt(pixel_variance.mean()) / np.sqrt((mean[mask] ** 2).mean()))
    result = {"channel_relative_standard_error": channel, "image_relative_noise": image}
    if kind == "sphere":
        profiles = np.stack([profile(p, mask) for p in per_seed])
        valid = ~np.isnan(profiles).any(axis=(0, 2))
        variance = profiles[:, valid].var(axis=0, ddof=1) / k
        result["profile_relative_noise"] = float(np.sqrt(variance.mean()) /
                                                 np.sqrt((profiles[:, valid].mean(axis=0) ** 2).mean()))
    return result


def write_picture(path, image, truth, mask):
    """PNG: method | truth | error x10 (accuracy.write_strip), each tile scaled up to at least 96
    pixels high so that a small render can be seen."""
    scale = max(1, int(math.ceil(96 / image.shape[0])))
    grow = (lambda a: np.repeat(np.repeat(a, scale, axis=0), scale, axis=1))
    return accuracy.write_strip(path, grow(image), grow(truth), grow(mask))


def save_case(results, name, result, script, argv, path):
    """Stores a case's result in `results` (its "cases") and writes them all to `path` as JSON, after
    every case, so that a long run keeps what it has done; a measured case is stamped with the
    command that made it (bench/<script> and its arguments), Blender's version and the machine."""
    import json
    if "not_measured" not in result:
        result["command"] = ("BLENDER_USER_SCRIPTS=build/scripts nice -n 19 blender -b --factory-startup "
                             f"--addons subsplat --python bench/{script}" + (" -- " + " ".join(argv) if argv else ""))
        result["blender"] = bpy.app.version_string
        result["machine"] = helpers.machine()
    results["cases"][name] = result
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as f:
        json.dump(results, f, indent=1)
        f.write("\n")
