"""The stability suite's scenes (docs/STABILITY.md), shared by bench/stability.py, which measures
every case and writes the document, and tests/blender/test_stability.py and test_hard_cases.py,
which assert bounds on them.

A case is one or more set-ups (a scene built from an empty file) and the variants rendered on each:
every real-time method at the case's settings, plus the settings the case is about (z0, lambda_m).
Each set-up has its own REFERENCE; a variant's error is accuracy.compare's against it.

Physical truth (issue 18, item 4): a case whose media the Cycles twin can convert and whose meshes
are closed has `truth`, the committed twin image (subsplat_testing.twin_truth) of each set-up. Every
case has delta lights (suns, a point light), which reach the twin's medium only through an
index-matched boundary, so the truth is that of the set-up's eta = 1 variant (physical_variant: every
translucent material at eta = 1 and specular 0): each variant is rendered again on it and measured
against the truth, beside its error against REFERENCE on the set-up itself. `no_truth` says why a
case has none.
"""
import math
import os
import textwrap
from dataclasses import dataclass, field

import bpy
import numpy as np

from subsplat_testing import accuracy, helpers

METHODS = ("BRUTE", "MULTIRES", "ADAPTIVE", "FULL")
# What every case renders unless it says otherwise: the paper's defaults, a 512^2 irradiance buffer
# and 3 levels (the automatic levels would mostly be one, and every method BRUTE). Eq. 11 then
# selects coarse samples where the shortest range is above about a tenth of the bounding radius.
BASE = {"irradiance_resolution": 512, "levels": 3}


@dataclass
class Variant:
    label: str
    method: str
    settings: dict = field(default_factory=dict)  # scene.subsplat values over the case's


@dataclass
class Case:
    name: str
    title: str
    setups: list            # (label, build(size) -> scene)
    variants: list          # Variant
    settings: dict = field(default_factory=lambda: dict(BASE))
    truth: dict = None      # set-up label -> the name of its physical truth (twin_truth.load(truth_stem(...)))
    no_truth: str = ""      # why there is none


def methods(**settings):
    return [Variant(m, m, dict(settings)) for m in METHODS]


def translucent(name, preset, mm_per_unit, specular=0.0, profile_model="DIPOLE"):
    """A translucent material of a preset medium. The stability cases measure the image-space
    approximations (every method against REFERENCE of the same model) and are built around the
    classical dipole's ranges, so that each mechanism of the paper is exercised (docs/STABILITY.md):
    their profile model is the dipole unless asked."""
    material = bpy.data.materials.new(name)
    material.subsplat.enabled = True
    material.subsplat.preset = preset
    material.subsplat.mm_per_unit = mm_per_unit
    material.subsplat.specular = specular
    material.subsplat.profile_model = profile_model
    return material


def uv_sphere(scene, radius, material, location=(0, 0, 0), scale=(1, 1, 1), name="Sphere"):
    mesh = bpy.data.meshes.new(name)
    import bmesh
    shape = bmesh.new()
    bmesh.ops.create_uvsphere(shape, u_segments=64, v_segments=32, radius=radius, calc_uvs=True)
    shape.to_mesh(mesh)
    shape.free()
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    obj.scale = scale
    scene.collection.objects.link(obj)
    return obj


def slab(scene, size, thickness, material, name="Slab"):
    """A size x size box, top face at z = 0, with a UV map over the top (0-1)."""
    h = size / 2
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(x, y, z) for z in (-thickness, 0.0) for y in (-h, h) for x in (-h, h)], [],
                     [(0, 1, 3, 2), (4, 5, 7, 6), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)])
    mesh.uv_layers.new(name="UVMap")
    uv = mesh.uv_layers["UVMap"].data
    for polygon in mesh.polygons:
        for corner in polygon.loop_indices:
            co = mesh.vertices[mesh.loops[corner].vertex_index].co
            uv[corner].uv = (co.x / size + 0.5, co.y / size + 0.5)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def camera(scene, ortho_scale, location, rotation, clip=(0.1, 100.0)):
    data = bpy.data.cameras.new("Camera")
    data.type = "ORTHO"
    data.ortho_scale = ortho_scale
    data.clip_start, data.clip_end = clip
    obj = bpy.data.objects.new("Camera", data)
    obj.location = location
    obj.rotation_euler = rotation
    scene.collection.objects.link(obj)
    scene.camera = obj
    return obj


# --- the cases ------------------------------------------------------------------------------

def grazing(degrees):
    """A thick marble slab under a sun `degrees` from the vertical, seen from straight above: the
    light view sees the surface nearly edge-on, each texel stretched 1 / cos over it."""
    def build(size):
        scene = helpers.empty_scene(size, size)
        slab(scene, 4.0, 1.0, translucent("Marble", "MARBLE", 50.0))
        helpers.top_down_camera(scene, ortho_scale=1.5)
        helpers.add_light(scene, "SUN", rotation=(math.radians(degrees), 0, 0), energy=5.0, angle=0.0)
        return scene
    return build


def step(size, mm_per_unit=8.0):
    """One marble object: a slab and, rising from its middle, a block 0.6 units high, lit by a sun at
    40 degrees: the block's top and the slab beside it are neighbours in the light's view, far
    apart in depth. Texels of a coarse level that straddle the edge average the two surfaces."""
    scene = helpers.empty_scene(size, size)
    mesh = bpy.data.meshes.new("Step")
    low, high = 0.0, 0.6
    vertices = [(-2, -2, low), (2, -2, low), (2, 2, low), (-2, 2, low),
                (-0.5, -0.5, high), (0.5, -0.5, high), (0.5, 0.5, high), (-0.5, 0.5, high),
                (-0.5, -0.5, 0.05), (0.5, -0.5, 0.05), (0.5, 0.5, 0.05), (-0.5, 0.5, 0.05)]
    faces = [(0, 1, 2, 3), (4, 5, 6, 7), (8, 9, 5, 4), (9, 10, 6, 5), (10, 11, 7, 6), (11, 8, 4, 7)]
    mesh.from_pydata(vertices, [], faces)
    mesh.materials.append(translucent("Marble", "MARBLE", mm_per_unit))
    obj = bpy.data.objects.new("Step", mesh)
    scene.collection.objects.link(obj)
    helpers.top_down_camera(scene, ortho_scale=2.0)
    helpers.add_light(scene, "SUN", rotation=(math.radians(40), 0, math.radians(30)), energy=5.0, angle=0.0)
    return scene


def thin_ear(size):
    """A skin ear: a disc 1 unit across and 0.04 thick (4 mm at 100 mm a unit, about skin's red
    range), lit from behind by a sun 30 degrees off its axis and by a weak sun from the front, seen
    face-on: most of its light crosses the thickness."""
    scene = helpers.empty_scene(size, size)
    uv_sphere(scene, 0.5, translucent("Skin", "SKIN1", 100.0), scale=(1.0, 1.0, 0.04), name="Ear")
    helpers.top_down_camera(scene, ortho_scale=1.2)
    helpers.add_light(scene, "SUN", rotation=(math.radians(150), 0, 0), energy=5.0, angle=0.0)
    helpers.add_light(scene, "SUN", rotation=(math.radians(-45), 0, 0), energy=0.5, angle=0.0)
    return scene


def board_file(path):
    """Marble and skin squares, 8 x 8 (materials.chessboard_file's)."""
    from subsplat_testing import materials
    materials.chessboard_file(path, squares=8)


def two_ranges_file(path, ratio=20.0):
    """One medium (skim milk) whose left half has its coefficients `ratio` times larger: the same
    albedo and look, a range `ratio` times shorter."""
    import subsplat
    _label, s, a = subsplat.presets.MEASURED_MEDIA["SKIMMILK"]
    sigma_a = np.empty((4, 4, 3), dtype=np.float32)
    sigma_s = np.empty_like(sigma_a)
    for x in range(4):
        scale = ratio if x < 2 else 1.0
        sigma_a[:, x], sigma_s[:, x] = np.asarray(a) * scale, np.asarray(s) * scale
    subsplat.native.ProfileSet.from_dipoles(sigma_a, sigma_s, subsplat.presets.MEASURED_ETA).save(path)


def subedit_slab(file_maker, file_name, mm_per_unit, sun_degrees):
    def build(size):
        scene = helpers.empty_scene(size, size)
        material = translucent(file_name, "MARBLE", mm_per_unit)
        material.subsplat.source = "SUBEDIT_FILE"
        path = os.path.join(helpers.OUTPUT, f"stability_{file_name}.exr")
        file_maker(path)
        material.subsplat.subedit_path = path
        slab(scene, 4.0, 1.0, material)
        helpers.top_down_camera(scene, ortho_scale=2.0)
        helpers.add_light(scene, "SUN", rotation=(math.radians(sun_degrees), 0, 0), energy=3.0, angle=0.0)
        return scene
    return build


def marble_sphere(size, scale=1.0, point_light=True):
    """A marble sphere of radius 0.5 * scale units, its millimetres per unit divided by `scale`: the
    same physical object (and the same image) at any scale. Its shortest range (5.4 mm at 40 mm a
    unit) is a quarter of its radius, long enough for eq. 11 to select coarse samples at 512^2. Lit
    by a sun 60 degrees off the view and, with point_light, a point light below whose power grows
    with scale^2 to give the same irradiance."""
    scene = helpers.empty_scene(size, size)
    uv_sphere(scene, 0.5 * scale, translucent("Marble", "MARBLE", 40.0 / scale, specular=0.5))
    camera(scene, 1.3 * scale, (0, -5 * scale, 0), (math.radians(90), 0, 0), clip=(0.1 * scale, 100 * scale))
    helpers.add_light(scene, "SUN", rotation=(math.radians(60), 0, math.radians(40)), energy=3.0, angle=0.0)
    if point_light:
        helpers.add_light(scene, "POINT", location=(-1.2 * scale, 0.6 * scale, -0.8 * scale),
                          energy=40.0 * scale ** 2, shadow_soft_size=0.0)
    return scene


def scaled_sphere(scale):
    return lambda size: marble_sphere(size, scale)


SUBEDIT = "a SubEdit file: its media have no coefficients for the twin (docs/PHYSICAL.md)"

CASES = [
    Case("grazing", "Grazing light",
         [(f"{d} degrees", grazing(d)) for d in (0, 60, 85, 89)], methods(),
         truth={f"{d} degrees": f"grazing_{d}" for d in (0, 60, 85, 89)}),
    Case("grazing85", "Grazing light at 85 degrees: what MULTIRES's stripes depend on",
         [("85 degrees", grazing(85))],
         [Variant("BRUTE", "BRUTE"), Variant("MULTIRES", "MULTIRES")]
         + [Variant(f"MULTIRES eps {e:g}", "MULTIRES", {"epsilon": e}) for e in (0.0001, 0.01)]
         + [Variant("MULTIRES 2 levels", "MULTIRES", {"levels": 2}),
            Variant("BRUTE 1024", "BRUTE", {"irradiance_resolution": 1024}),
            Variant("MULTIRES 1024", "MULTIRES", {"irradiance_resolution": 1024})],
         truth={"85 degrees": "grazing_85"}),
    Case("depth", "Depth discontinuity and z0",
         [("step", step)],
         methods() + [Variant(f"{m} z0 {z}", m, {"z0_factor": z}) for m in ("ADAPTIVE", "FULL") for z in (0.003, 0.3)],
         no_truth="the step is an open surface (a ground plane with a block on it), with no inside for the "
                  "twin's medium"),
    Case("thin", "Thin feature, lit from behind", [("ear", thin_ear)], methods(), truth={"ear": "thin_ear"}),
    Case("material", "Material discontinuity and lambda_m",
         [("chessboard", subedit_slab(board_file, "board", 60.0, 30))],
         # At the paper's epsilon the coarse levels carry only the profiles' tails; at 0.01 they carry
         # more, and eq. 17's material weight decides what crosses the lines.
         methods() + [Variant(f"MULTIRES eps 0.01 lambda_m {v:g}", "MULTIRES", {"epsilon": 0.01, "lambda_m": v})
                      for v in (0.0, 8.0, 64.0)],
         no_truth=SUBEDIT),
    Case("ranges", "Short and long ranges in one object",
         [("1:20", subedit_slab(two_ranges_file, "two_ranges", 10.0, 20))],
         methods() + [Variant("MULTIRES lambda_m 0", "MULTIRES", {"lambda_m": 0.0})],
         no_truth=SUBEDIT),
    # One truth, the x1 sphere's: the three are the same physical object and image (test_hard_cases
    # holds every method's images at 1/1000 and 1000 to its image at 1), and Cycles' own precision at
    # 1/1000 of a unit is not what is measured here.
    Case("scale", "Tiny and huge objects",
         [(f"x{s:g}", scaled_sphere(s)) for s in (0.001, 1.0, 1000.0)], methods(),
         truth={f"x{s:g}": "scale_x1" for s in (0.001, 1.0, 1000.0)}),
]


def apply(scene, settings):
    for key, value in settings.items():
        setattr(scene.subsplat, key, value)


def coarse_share(stats):
    """Share of the finest texels covered by samples selected above level 0."""
    counts = stats.get("selected_per_level") or []
    covered = [c * 4 ** k for k, c in enumerate(counts)]
    return sum(covered[1:]) / sum(covered) if sum(covered) else 0.0


def physical_variant(scene):
    """The set-up as its physical truth is rendered: every translucent material at eta = 1 and
    specular 0, the translucent meshes' normals pointing out (the twin enters the medium by them)."""
    from subsplat_testing import physical
    for obj in scene.objects:
        materials = [slot.material for slot in obj.material_slots if slot.material and slot.material.subsplat.enabled]
        for material in materials:
            material.subsplat.eta = 1.0
            material.subsplat.specular = 0.0
        if materials and obj.type == "MESH":
            physical.outward(obj)
    return scene


def truth_stem(truth, size):
    return f"stability_{truth}_{size}"


def render_truth(case, size, samples, seeds, scratch, command):
    """Renders the case's missing truths (twin_truth.render) at `samples` x `seeds`."""
    from subsplat_testing import twin_truth
    done = set()
    for setup_label, build in case.setups:
        name = (case.truth or {}).get(setup_label)
        if name is None or name in done or os.path.exists(twin_truth.paths(truth_stem(name, size))[0]):
            continue
        if name == "scale_x1" and setup_label != "x1":
            continue  # made from the x1 set-up
        scene = physical_variant(build(size))
        twin, warnings = twin_truth.make_twin(scene)
        twin_truth.render(truth_stem(name, size), scene, twin, samples, seeds, scratch,
                          {"case": case.name, "setup": setup_label, "variant": "stability_cases.physical_variant",
                           "twin_warnings": warnings, "command": command})
        done.add(name)


def measure_physical(case, setup_label, build, size, samples, rows, keep_images):
    """The set-up's eta = 1 variant: its REFERENCE and every variant against the committed truth (a
    missing truth raises twin_truth.MissingTruth). Adds row["twin_error"] and ["twin_mean_ratio"];
    returns the set-up's figures (REFERENCE's own error against the truth, the truth's noise)."""
    from subsplat_testing import twin_truth
    scene = physical_variant(build(size))
    scene.render.engine = "SUBSPLAT"
    apply(scene, case.settings)
    reference, reference_b, _ = accuracy.render_passes(scene, "REFERENCE", samples)
    truth, record = twin_truth.load(truth_stem(case.truth[setup_label], size), reference.shape)
    mask = reference_b[..., 3] > 0.5
    error, _raw, noise, ratio = twin_truth.error(reference, truth, mask)
    figures = {"truth": case.truth[setup_label], "samples": record["samples"], "seeds": len(record["seeds"]),
               "seconds": record["seconds"], "noise": noise, "reference_twin_error": error,
               "reference_twin_mean_ratio": ratio}
    for variant, row in zip(case.variants, rows):
        apply(scene, {**case.settings, **variant.settings})
        image, _image_b, _stats = accuracy.render_passes(scene, variant.method)
        row["twin_error"], _raw, _noise, row["twin_mean_ratio"] = twin_truth.error(image, truth, mask)
        if keep_images and ("shown" not in figures or variant.label == "FULL"):  # FULL's, or the first's
            figures["shown"] = (variant.label, image)
        apply(scene, case.settings)
    if keep_images:
        figures.update(truth_image=truth[0], reference_image=reference, mask=mask)
    return figures


def measure(case, size, samples, keep_images=True, physical=False):
    """Every set-up's REFERENCE and every variant against it: a list of rows (dicts); with
    keep_images, each set-up's images are in row['image'] / setup['reference']. With `physical`, a
    case with a truth is also measured against it (measure_physical: setup["physical"])."""
    setups = []
    for setup_label, build in case.setups:
        scene = build(size)
        scene.render.engine = "SUBSPLAT"
        apply(scene, case.settings)
        reference, reference_b, _ = accuracy.render_passes(scene, "REFERENCE", samples)
        rows = []
        for variant in case.variants:
            apply(scene, {**case.settings, **variant.settings})
            image, image_b, stats = accuracy.render_passes(scene, variant.method)
            error = accuracy.compare(image, image_b, reference, reference_b)
            row = {"case": case.name, "setup": setup_label, "variant": variant.label, "method": variant.method,
                   "relative_rmse": error["relative_rmse"], "robust_relative_rmse": error["robust_relative_rmse"],
                   "exitance_relative_rmse": error["exitance_relative_rmse"], "mean_ratio": error["mean_ratio"],
                   "nonfinite": int(stats["nonfinite_pixels"]), "splats": int(stats["splat_count"]),
                   "coarse_share": coarse_share(stats), "frame_ms": float(stats["frame_ms"])}
            if keep_images:
                row["image"] = image
            rows.append(row)
            apply(scene, case.settings)
        setups.append({"label": setup_label, "rows": rows,
                       "reference": reference if keep_images else None,
                       "mask": (reference_b[..., 3] > 0.5)})
        if physical and case.truth:
            setups[-1]["physical"] = measure_physical(case, setup_label, build, size, samples, rows, keep_images)
    return setups


def picture(path, title, setup):
    """One PNG per set-up: REFERENCE and every variant on top, each variant's error x10 below."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = setup["rows"]
    reference, mask = setup["reference"], setup["mask"]
    columns = len(rows) + 1
    figure, axes = plt.subplots(2, columns, figsize=(1.6 * columns, 3.8), dpi=100, squeeze=False)
    display = accuracy.srgb(reference[..., :3])
    axes[0][0].imshow(display[::-1], interpolation="nearest")
    axes[0][0].set_title("REFERENCE", fontsize=7)
    axes[1][0].axis("off")
    for column, row in enumerate(rows, start=1):
        axes[0][column].imshow(accuracy.srgb(row["image"][..., :3])[::-1], interpolation="nearest")
        axes[0][column].set_title(textwrap.fill(row["variant"], 16), fontsize=7)
        axes[1][column].imshow(accuracy.error_colours(row["image"], reference, mask)[::-1], interpolation="nearest")
        axes[1][column].set_title(f"{100 * row['relative_rmse']:.2f} %", fontsize=7)
    for axis in axes.ravel():
        axis.set_xticks([])
        axis.set_yticks([])
    figure.suptitle(f"{title}: {setup['label']} (error x10 below)", fontsize=8)
    figure.tight_layout()
    figure.savefig(path)
    plt.close(figure)
    return path


# --- flicker under a slowly moving light ----------------------------------------------------

FRAMES, DEGREES_PER_FRAME = 60, 0.5


def coarse_sphere(size):
    """The flicker case with coarse samples: the marble sphere under its sun alone, irradiance 512^2
    and the paper's 3 levels: eq. 11 selects samples above the finest level over much of the lit
    side and finest ones towards the terminator, and the border between them moves with the light."""
    scene = marble_sphere(size, point_light=False)
    scene.render.engine = "SUBSPLAT"
    apply(scene, {"irradiance_resolution": 512, "levels": 3})
    return scene


def moving_light(scene, methods, samples, frames=FRAMES, degrees=DEGREES_PER_FRAME):
    """Turns every light `degrees` a frame about the vertical and renders each frame with each method.
    Returns ({method: [image]}, mask of pixels translucent in every REFERENCE frame, {method: [stats]})."""
    import mathutils
    bpy.context.view_layer.update()  # matrix_world of objects made from Python is set on update
    lights = [(o, o.matrix_world.copy()) for o in scene.objects if o.type == "LIGHT"]
    images = {m: [] for m in methods}
    stats = {m: [] for m in methods}
    masks = []
    for t in range(frames):
        turn = mathutils.Matrix.Rotation(math.radians(degrees * t), 4, "Z")
        for light, rest in lights:
            light.matrix_world = turn @ rest
        for method in methods:
            image, exitance, frame_stats = accuracy.render_passes(scene, method, samples)
            images[method].append(image)
            stats[method].append(frame_stats)
            if method == "REFERENCE":
                masks.append(exitance[..., 3] > 0.5)
    return images, np.logical_and.reduce(masks), stats


def frame_changes(frames, mask):
    """Mean |I(t+1) - I(t)| over the mask, for each frame pair."""
    return [float(np.abs(b[mask][:, :3] - a[mask][:, :3]).mean()) for a, b in zip(frames, frames[1:])]


def flicker(images, mask):
    """{method: mean frame-to-frame change / mean REFERENCE radiance}, {method: that minus REFERENCE's}."""
    scale = float(np.mean([f[mask][:, :3].mean() for f in images["REFERENCE"]]))
    figures = {m: float(np.mean(frame_changes(frames, mask))) / scale for m, frames in images.items()}
    return figures, {m: f - figures["REFERENCE"] for m, f in figures.items()}, scale


def plot_changes(path, title, images, mask, scale):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(7.5, 4.0), dpi=100)
    for method, frames in images.items():
        values = np.asarray(frame_changes(frames, mask)) / scale
        axes.plot(np.arange(1, len(values) + 1), values, label=method,
                  lw=2.0 if method == "REFERENCE" else 1.0, color="black" if method == "REFERENCE" else None)
    axes.set_xlabel("frame")
    axes.set_ylabel("mean |I(t) - I(t-1)| / mean REFERENCE")
    axes.set_title(title, fontsize=9)
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path)
    plt.close(figure)
    return path
