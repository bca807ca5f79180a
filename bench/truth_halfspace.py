"""The truth harness's own check: Cycles (Volume Scatter g = 0 + Volume Absorption inside a
Transparent boundary, eta = 1) against the exact radiance of an index-matched, isotropically
scattering half-space (Chandrasekhar's H-function), for two media (a = 0.99 and 0.8), each made by
the Cycles twin (subsplat.twin) from a SubSplat material and built directly, lit by a sun at 0, 60
and 80 degrees seen from above, a view at 60 degrees, and a uniform sky. Writes
bench/results/truth_halfspace.json, which tests/blender/test_truth.py checks (within 1 %) and ties
to a live render. docs/PHYSICAL.md, "Checking the truth".

    BLENDER_USER_SCRIPTS=build/scripts nice -n 19 blender -b --factory-startup \
        --python bench/truth_halfspace.py -- [--via twin direct] [--samples 1024] [--seeds 16] \
        [--size 8] [--output bench/results/truth_halfspace.json]
"""
import argparse
import json
import os
import statistics
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))

from subsplat_testing import helpers, hfunction, truth  # noqa: E402


def main():
    import bpy
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--samples", type=int, default=1024, help="samples per pixel per seed")
    parser.add_argument("--seeds", type=int, default=16)
    parser.add_argument("--size", type=int, default=8, help="image width and height in pixels")
    parser.add_argument("--via", nargs="+", default=["twin", "direct"], choices=["twin", "direct"],
                        help="twin: the case through the Cycles twin (subsplat.twin); direct: the medium "
                             "built by subsplat_testing.truth")
    parser.add_argument("--output", default=os.path.join(HERE, "results", "truth_halfspace.json"))
    args = parser.parse_args(argv)
    scratch = tempfile.mkdtemp(prefix="truth_halfspace_")
    started = time.perf_counter()
    cases = []
    if "twin" in args.via:
        helpers.enable_addon()
    for via, (name, medium, light, mu0, mu) in ((v, c) for v in args.via for c in truth.CASES):
        albedo = truth.MEDIA[medium]
        mean, error, per_seed, seconds = truth.measure(medium, light, mu0, mu, args.size, args.samples,
                                                       args.seeds, os.path.join(scratch, f"{via}_{medium}_{name}"),
                                                       via=via)
        seed_error = statistics.stdev(per_seed) / args.seeds ** 0.5
        H = hfunction.h_function(albedo)
        expected = truth.exact(albedo, light, mu0, mu)
        case = {"via": via, "case": name, "medium": medium, "albedo": albedo, "sigma_t_per_unit": truth.SIGMA_T,
                "light": light, "mu0": mu0, "mu": mu, "truth_radiance": mean, "standard_error": error,
                "relative_standard_error": error / mean,
                "relative_standard_error_of_seed_means": seed_error / mean, "per_seed_means": per_seed,
                "H_mu0": H(mu0) if mu0 is not None else None, "H_mu": H(mu),
                "h_function_radiance": expected, "ratio": mean / expected,
                "samples_per_pixel": args.samples, "seeds": args.seeds, "pixels": args.size ** 2,
                "seconds": round(seconds, 2)}
        cases.append(case)
        print(f"truth {via} {medium} {name}: cycles {mean:.6f} +- {100 * error / mean:.3f} %  H-function "
              f"{expected:.6f}  ratio {mean / expected:.5f}  ({seconds:.1f} s)", flush=True)
    result = {
        "description": "Cycles (Volume Scatter g=0 + Volume Absorption in a Transparent box, eta=1, "
                       "made by the Cycles twin from a SubSplat material (via twin) or directly (via direct), "
                       "1024 bounces, no clamp/denoise/adaptive) against Chandrasekhar's H-function "
                       "radiance of an index-matched isotropic half-space. Sun strength 1 (irradiance "
                       "facing the sun) or uniform sky radiance 1. Box 100 mfp deep, 400 mfp wide; "
                       "orthographic view of a central patch 10 mfp across. standard_error: the larger "
                       "of the pixels' scatter (all pixels of all seeds) and the seed means' scatter.",
        "command": "BLENDER_USER_SCRIPTS=build/scripts nice -n 19 blender -b --factory-startup "
                   "--python bench/truth_halfspace.py -- "
                   + " ".join(argv),
        "blender": bpy.app.version_string, "machine": helpers.machine(),
        "total_seconds": round(time.perf_counter() - started, 1),
        "cases": cases}
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    with open(args.output, "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")
    worst = max(abs(c["ratio"] - 1) for c in cases)
    print(f"wrote {args.output}: worst |ratio - 1| = {100 * worst:.3f} %, "
          f"largest standard error {100 * max(c['relative_standard_error'] for c in cases):.3f} %")


if __name__ == "__main__":
    main()
