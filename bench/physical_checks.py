"""Two follow-up measurements docs/PHYSICAL.md ("What it shows") quotes, on the thin back-lit Marble
slabs of subsplat_testing.physical (32 x 32 pixels):

- every SubSplat method at its defaults against REFERENCE, and BRUTE with a 2048² irradiance
  buffer: the automatic resolution's miss on thin parts;
- Cycles' Principled subsurface (the Principled equivalent of the medium, `accuracy.use_cycles`, 64
  samples, 16 x 16 pixels) with each of its subsurface methods, and Blender's default bounces.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        --python bench/physical_checks.py
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))

import bpy  # noqa: E402

from subsplat_testing import accuracy, helpers, physical  # noqa: E402


def mean(image):
    return " / ".join(f"{v:.3f}" for v in image[..., :3].reshape(-1, 3).mean(axis=0))


def methods_on_thin_slabs():
    for mfp in (1.0, 5.0):
        scene = physical.thin_case("MARBLE", mfp, 32)
        reference = None
        for method in ("REFERENCE", "BRUTE", "MULTIRES", "ADAPTIVE", "FULL"):
            image, _exitance, stats = accuracy.render_passes(scene, method, 200000)
            reference = image if method == "REFERENCE" else reference
            ratio = image[..., :3].mean() / reference[..., :3].mean()
            print(f"thin Marble {mfp:g} mfp, {method} at its defaults: mean R / G / B {mean(image)}, "
                  f"{ratio:.3f} x REFERENCE (irradiance {stats.get('irradiance_resolution')}², "
                  f"{stats.get('splat_levels')} levels)", flush=True)
        scene.subsplat.irradiance_resolution = 2048
        image, _exitance, stats = accuracy.render_passes(scene, "BRUTE", None)
        print(f"thin Marble {mfp:g} mfp, BRUTE at 2048²: mean R / G / B {mean(image)}, "
              f"{image[..., :3].mean() / reference[..., :3].mean():.3f} x REFERENCE "
              f"(irradiance {stats.get('irradiance_resolution')}²)", flush=True)


def cycles_methods_on_thin_slabs():
    for method in ("RANDOM_WALK", "RANDOM_WALK_FIXED_RADIUS", "BURLEY"):
        for mfp in (0.5, 2.0):
            scene = physical.thin_case("MARBLE", mfp, 16)
            accuracy.use_cycles(scene, 64)
            for material in bpy.data.materials:
                for node in (material.node_tree.nodes if material.node_tree else []):
                    if node.type == "BSDF_PRINCIPLED":
                        node.subsurface_method = method
            image = helpers.render(scene, f"physical_checks_{method}_{mfp:g}")
            print(f"thin Marble {mfp:g} mfp, Cycles Principled {method}: mean R / G / B {mean(image)}", flush=True)
    scene = physical.thin_case("MARBLE", 2.0, 16)
    scene.render.engine = "CYCLES"
    scene.cycles.device, scene.cycles.samples, scene.cycles.use_denoising = "CPU", 64, False
    image = helpers.render(scene, "physical_checks_default_bounces")
    print(f"thin Marble 2 mfp, Cycles Principled RANDOM_WALK, Blender's default bounces: mean R / G / B "
          f"{mean(image)}", flush=True)


if __name__ == "__main__":
    helpers.enable_addon()
    methods_on_thin_slabs()
    cycles_methods_on_thin_slabs()
