"""How much of the light across a sphere's terminator is scattered once (docs/TRANSPORT.md, "What is
left"): the Cycles twin of bench/physical.py's spheres (subsplat_testing.physical) rendered with one
scattering event (Cycles' volume_bounces = 0), its share of the committed truth per column of the
horizontal profile. First the check that volume_bounces = 0 is single scattering: the 60° Skin1 slab
against the closed form a E / (4 pi (mu0 + mu)).

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        --python bench/sphere_single_scattering.py -- [--samples 256] [--seeds 2]

About 5 s on 2 cores (AMD EPYC, 2026-12-03). Prints; writes nothing.
"""
import argparse
import math
import os
import sys
import tempfile

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))
from subsplat_testing import helpers, physical, twin_truth  # noqa: E402


def once_scattered(scene, samples, seeds, scratch, stem):
    twin, _warnings = twin_truth.make_twin(scene)
    twin.cycles.volume_bounces = 0
    images = [twin_truth.render_twin(scene, twin, samples, seed, os.path.join(scratch, f"{stem}_{seed}.exr"))[0]
              for seed in range(seeds)]
    return np.mean(images, axis=0)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--samples", type=int, default=256)
    parser.add_argument("--seeds", type=int, default=2)
    args = parser.parse_args(argv)
    helpers.enable_addon()
    scratch = tempfile.mkdtemp(prefix="single_scattering_")

    scene = physical.slab_case("SKIN1", 60.0, 16)
    bpy.context.window.scene = scene
    settings = next(m for m in bpy.data.materials if m.subsplat.enabled).subsplat
    image = once_scattered(scene, args.samples, args.seeds, scratch, "slab")
    mu0 = 0.5
    exact = np.array([physical.SUN * mu0 * s / (a + s) / (4 * math.pi * (mu0 + 1.0))
                      for a, s in zip(settings.sigma_a, settings.sigma_s_prime)])
    print("Skin1 slab at 60 degrees, volume_bounces = 0 against the closed-form single scattering, R / G / B: "
          + " / ".join(f"{v:.4f}" for v in image[..., :3].reshape(-1, 3).mean(axis=0) / exact), flush=True)

    for name in ("sphere_skin1", "sphere_marble"):
        scene = physical.sphere_case(name.split("_")[1].upper(), 32)
        bpy.context.window.scene = scene
        truth = twin_truth.read_exr(os.path.join(twin_truth.DIRECTORY, f"{name}.exr"))
        once = once_scattered(scene, args.samples, args.seeds, scratch, name)
        mask = truth[..., :3].sum(axis=-1) > 0
        print(f"{name}: single scattering's share of the truth per column (dark limb to lit limb), R / G / B; "
              "the truth", flush=True)
        for a, b in zip(physical.profile(once, mask), physical.profile(truth, mask)):
            if np.isnan(b).any():
                continue
            print("  " + " / ".join(f"{x / y:.2f}" if y > 0 else "-" for x, y in zip(a, b))
                  + "   " + " / ".join(f"{y:.3f}" for y in b), flush=True)


if __name__ == "__main__":
    main()
