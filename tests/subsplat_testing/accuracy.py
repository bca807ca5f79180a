"""Accuracy measurements shared by tests/blender/test_accuracy.py and bench/accuracy.py.

Every figure compares linear radiance over the translucent pixels (those the
exitance pass of both renders marks) against REFERENCE (docs/ACCURACY.md).
"""
import math
import os

import bpy
import numpy as np

from subsplat_testing import helpers

# Principled BSDF v2 (Blender 4.0 on) renamed the inputs the equivalent material sets.
V2 = bpy.app.version >= (4, 0, 0)
SPECULAR = "Specular IOR Level" if V2 else "Specular"

EXAMPLES = ("skin_suzanne", "marble_pieces", "wax_jade")
# Methods charted against REFERENCE.
METHODS = ("BRUTE", "MULTIRES", "ADAPTIVE", "FULL")


def open_example(name, percentage):
    bpy.ops.wm.open_mainfile(filepath=os.path.join(helpers.SOURCE, "example_blends", name + ".blend"))
    scene = bpy.context.scene
    scene.render.resolution_percentage = percentage
    return scene


def render_passes(scene, method, reference_samples=None):
    """Combined and exitance pass of one SubSplat render, plus its stats."""
    import subsplat
    subsplat.diagnostics.keep_passes = True
    scene.render.engine = "SUBSPLAT"
    scene.subsplat.method = method
    if reference_samples is not None:
        scene.subsplat.reference_samples = reference_samples
    bpy.ops.render.render()
    error = subsplat.last_render_error()
    if error:
        raise RuntimeError(f"{method} render failed: {error}")
    passes = subsplat.last_render_passes()
    return passes["Combined"], passes["SubSplat Exitance"], subsplat.last_render_stats()


def _errors(ours, truth):
    rmse = math.sqrt(float(((ours - truth) ** 2).mean()))
    relative = rmse / max(math.sqrt(float((truth ** 2).mean())), 1e-30)
    peak = float(truth.max())
    psnr = 20 * math.log10(peak / rmse) if rmse > 0 else float("inf")
    return relative, psnr


def compare(image, image_exitance, reference, reference_exitance):
    """Relative RMSE and PSNR of image against reference over pixels both mark translucent.

    relative RMSE = sqrt(mean (I - R)^2) / sqrt(mean R^2), over rgb;
    PSNR = 20 log10(max R / RMSE), peak taken over the same pixels. The same for the
    exitance B(x_o) alone (exitance_*): the part the splatting computes, without the
    direct specular both share.
    """
    mask = (image_exitance[..., 3] > 0.5) & (reference_exitance[..., 3] > 0.5)
    disagree = int(((image_exitance[..., 3] > 0.5) != (reference_exitance[..., 3] > 0.5)).sum())
    ours = image[mask][:, :3].astype(np.float64)
    truth = reference[mask][:, :3].astype(np.float64)
    relative, psnr = _errors(ours, truth)
    # How much of the squared error sits in the worst 0.1 % of pixels: outliers (shadow-test
    # disagreements under a specular highlight) against error spread over the surface.
    squared = ((ours - truth) ** 2).sum(axis=1)
    worst = max(1, len(squared) // 1000)
    ordered = np.sort(squared)
    outlier_share = float(ordered[-worst:].sum() / max(squared.sum(), 1e-300))
    # The same without that worst 0.1 %, and how many pixels are off by more than three times
    # the mean reference radiance: the surface's accuracy, and the outliers counted apart.
    kept = ordered[:len(squared) - worst] if len(squared) > worst else squared
    robust = math.sqrt(float(kept.mean()) / 3.0) / max(math.sqrt(float((truth ** 2).mean())), 1e-30)
    outliers = int((np.abs(ours - truth).sum(axis=1) > 3.0 * 3.0 * float(truth.mean())).sum())
    b_relative, b_psnr = _errors(image_exitance[mask][:, :3].astype(np.float64),
                                 reference_exitance[mask][:, :3].astype(np.float64))
    return {"relative_rmse": relative, "psnr": psnr, "exitance_relative_rmse": b_relative,
            "robust_relative_rmse": robust, "outlier_pixels": outliers,
            "exitance_psnr": b_psnr, "outlier_share": outlier_share, "pixels": int(mask.sum()), "mask_disagreement": disagree,
            "mean_ratio": float(ours.mean() / max(truth.mean(), 1e-30))}


def srgb(linear):
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def error_colours(image, reference, mask):
    """|I - R| averaged over rgb, / mean R over the mask, x10 in false colour (10 % is full red)."""
    scale = max(float(reference[mask][:, :3].mean()), 1e-12) if mask.any() else 1.0
    t = np.clip(np.abs(image[..., :3] - reference[..., :3]).mean(axis=-1) / scale * 10.0, 0.0, 1.0)
    rgb = np.stack([t, 1 - np.abs(2 * t - 1), 1 - t], axis=-1)
    rgb[~mask] = 0.15
    return rgb


def write_strip(path, image, reference, mask):
    """PNG: image | reference | error x10, display-referred (sRGB, exposure 1)."""
    strip = np.concatenate([srgb(image[..., :3]), srgb(reference[..., :3]), error_colours(image, reference, mask)],
                           axis=1)
    return write_png(path, strip)


def write_png(path, rgb):
    """A display-referred picture (rows bottom first, as Blender's pixels) as PNG."""
    h, w = rgb.shape[:2]
    rgba = np.concatenate([rgb, np.ones((h, w, 1))], axis=-1).astype(np.float32)
    picture = bpy.data.images.new(os.path.basename(path), w, h, float_buffer=False)
    picture.pixels.foreach_set(rgba.ravel())
    picture.filepath_raw = path
    picture.file_format = "PNG"
    picture.save()
    bpy.data.images.remove(picture)
    return path


# --- REFERENCE against Cycles (Principled BSDF, Random Walk) on a thick slab --------------

def _cycles_alpha(albedo):
    """Single-scattering albedo Cycles derives from a surface albedo (Chiang et al. 2016 fit, g = 0,
    as Cycles 3.x's subsurface_random_walk_remap)."""
    blend = albedo ** 0.25
    return ((1 - blend) * 1.8260523782 * math.atan(5.11246790329 * albedo) ** 1.09686102424
            + blend * 0.496310210422 * math.atan(4.23501903650 * albedo) ** 2.40602999408)


def cycles_surface_albedo(reduced_albedo):
    """The Subsurface Color that makes Cycles walk with single-scattering albedo sigma_s'/sigma_t'."""
    lo, hi = 0.0, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _cycles_alpha(mid) < reduced_albedo else (lo, mid)
    return 0.5 * (lo + hi)


def principled_equivalent(material):
    """Gives a DIPOLE material's node tree the Principled BSDF that EEVEE and Cycles render as the
    same medium (docs/TRADEOFF.md, "The same materials in EEVEE and Cycles"): Random Walk
    subsurface with mean free path 1 / sigma_t' (scene units) and the Subsurface Color whose random
    walk has single-scattering albedo sigma_s' / sigma_t' (isotropic), our eta, roughness and
    specular. Returns the node."""
    settings = material.subsplat
    material.use_nodes = True
    tree = material.node_tree
    bsdf = next((n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
    if bsdf is None:
        bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled")
    output = next((n for n in tree.nodes if n.type == "OUTPUT_MATERIAL"), None) or tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
    sigma_s_prime, sigma_a = list(settings.sigma_s_prime), list(settings.sigma_a)
    sigma_t = [s + a for s, a in zip(sigma_s_prime, sigma_a)]
    colour = [cycles_surface_albedo(s / t) for s, t in zip(sigma_s_prime, sigma_t)]
    bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
    if V2:  # Principled v2 (docs/PRINCIPLED.md): the base colour is the subsurface colour
        bsdf.inputs["Subsurface Weight"].default_value = 1.0
        bsdf.inputs["Subsurface Scale"].default_value = 1.0
        # 3.x's "Random Walk" is 4.x's "Random Walk (Skin)", as Blender converts a 3.4 file (4.x's
        # RANDOM_WALK is 3.x's RANDOM_WALK_FIXED_RADIUS).
        # Not yet measured against the medium in 4.x (docs/VERSIONS.md).
        bsdf.subsurface_method = "RANDOM_WALK_SKIN"
    else:
        bsdf.inputs["Subsurface Color"].default_value = (*colour, 1.0)
        bsdf.inputs["Subsurface"].default_value = 1.0  # 3.x: also the radius scale
        bsdf.subsurface_method = "RANDOM_WALK"
    bsdf.inputs["Subsurface Radius"].default_value = [1.0 / t / settings.mm_per_unit for t in sigma_t]
    bsdf.inputs["Subsurface IOR"].default_value = settings.eta
    bsdf.inputs[SPECULAR].default_value = settings.specular
    bsdf.inputs["Roughness"].default_value = settings.roughness
    if hasattr(material, "use_sss_translucency"):  # EEVEE: light through thin parts as well
        material.use_sss_translucency = True
    return bsdf


def slab_scene(preset, mm_per_unit, size=64):
    """A 4 x 4 x 1 unit slab of a measured medium under a sun from straight above."""
    scene = helpers.empty_scene(size, size)
    material = bpy.data.materials.new(preset.title())
    material.use_nodes = True
    settings = material.subsplat
    settings.enabled = True
    settings.preset = preset
    settings.mm_per_unit = mm_per_unit
    settings.specular = 0.0
    principled_equivalent(material)
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs[SPECULAR].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 1.0
    mesh = bpy.data.meshes.new("Slab")
    mesh.from_pydata([(x, y, z) for z in (-1.0, 0.0) for y in (-2.0, 2.0) for x in (-2.0, 2.0)], [],
                     [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)])
    mesh.materials.append(material)
    slab = bpy.data.objects.new("Slab", mesh)
    scene.collection.objects.link(slab)
    helpers.top_down_camera(scene, ortho_scale=1.0)
    helpers.add_light(scene, "SUN", energy=3.0, angle=0.0)
    return scene


def use_cycles(scene, samples):
    """Cycles on the CPU as the comparisons run it: no denoising, a fixed seed, 2 diffuse bounces
    (light off other surfaces), no glossy or transmission bounces."""
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.cycles.seed = 1
    scene.cycles.max_bounces = 4
    scene.cycles.diffuse_bounces = 2
    scene.cycles.glossy_bounces = 0
    scene.cycles.transmission_bounces = 0


def reference_against_cycles(preset, mm_per_unit=100.0, cycles_samples=128, reference_samples=100000):
    """Mean radiance per channel over the centre of the slab: REFERENCE, Cycles, and their ratio."""
    scene = slab_scene(preset, mm_per_unit)
    reference, _exitance, _stats = render_passes(scene, "REFERENCE", reference_samples)
    use_cycles(scene, cycles_samples)
    cycles = helpers.render(scene, f"cycles_slab_{preset.lower()}")
    ours = helpers.centre(reference, 0.5)[..., :3].reshape(-1, 3).mean(axis=0)
    theirs = helpers.centre(cycles, 0.5)[..., :3].reshape(-1, 3).mean(axis=0)
    return ours, theirs, ours / theirs


def pareto(points, cost="ms"):
    """The points no other point beats in both cost (frame time "ms", or "fragments", the
    fragment-shader invocations of a frame) and error, cheapest first (bench/tradeoff.py's charts,
    test_tradeoff.py)."""
    front, best = [], float("inf")
    for p in sorted(points, key=lambda p: (p[cost], p["error"])):
        if p["error"] < best:
            front.append(p)
            best = p["error"]
    return front


def front_error_at(front, at, cost="ms"):
    """The Pareto front's error at a cost: the lowest error of the points no costlier."""
    return min((p["error"] for p in front if p[cost] <= at), default=float("inf"))
