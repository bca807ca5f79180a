"""Fits the automatic resolution's rule on the calibration set (docs/AUTO.md, "Held-out scenes").

    build/native/subsplat_auto_sets --set calibration --rungs --count 24 --json cal.json
    python3 bench/auto_fit.py cal.json [more.json ...] [--target 0.01]

Each calibration point is a scene at a rung: the coarsest light texel on its translucent object,
the radii holding 25, 50, 75 and 95 % of its materials' shortest profile's energy, a pixel's size
at the object, and the error MULTIRES at that rung adds over its converged reference. The rule
says a rung adds at most A t^-p, t the texels across the length L = max(R_f, c pixel): the profile's
radius R_f, or the pixel where the profile is finer than c pixels (detail the image cannot show).
For each energy fraction f, pixel factor c and power p it takes the smallest A that bounds every
point (an upper envelope), then prices the rule by the resolutions it would choose for the
calibration scenes at the target (unreachable scenes first, then the mean texel count); it prints
every candidate and the cheapest, whose constants go into native/src/pipeline/auto_quality.h.
"""
import argparse
import json
import math

RUNGS = [128, 192, 256, 384, 512, 768, 1024, 1536, 2048]
POWERS = [0.5, 0.75, 1.0, 1.25, 1.5, 2.0]
PIXEL_FACTORS = [0.0, 0.5, 1.0, 2.0]


def load(paths):
    energies, scenes = None, []
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        if data["set"] != "calibration":
            raise SystemExit(f"{path}: a {data['set']} set; the rule is fitted on the calibration set only")
        energies = data["energies"]
        scenes += data["scenes"]
    return energies, scenes


def fit(energies, scenes, target):
    results = []
    for fi, energy in enumerate(energies):
        for factor in PIXEL_FACTORS:
            for power in POWERS:
                envelope, worst = 0.0, None
                for scene in scenes:
                    length = max(scene["radii"][fi], factor * scene["pixel"])
                    for point in scene["points"]:
                        if point["texel"] <= 0:
                            continue
                        a = point["added"] * (length / point["texel"]) ** power
                        if a > envelope:
                            envelope, worst = a, (scene["index"], point["resolution"])
                needed = (envelope / target) ** (1.0 / power)  # texels across L the target needs
                cost, unreachable = 0, 0
                for scene in scenes:
                    # t grows as the resolution: t(r) = t(128) r / 128.
                    first = scene["points"][0]
                    length = max(scene["radii"][fi], factor * scene["pixel"])
                    t128 = length / first["texel"] * 128 / first["resolution"]
                    rung = next((r for r in RUNGS if t128 * r / 128 >= needed), None)
                    unreachable += rung is None
                    cost += (rung or 2048) ** 2
                results.append(dict(energy=energy, factor=factor, power=power, envelope=envelope, needed=needed,
                                    worst=worst, cost=cost, unreachable=unreachable))
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+")
    parser.add_argument("--target", type=float, default=0.01)
    args = parser.parse_args()
    energies, scenes = load(args.files)
    results = fit(energies, scenes, args.target)
    print(f"{len(scenes)} calibration scenes, target {args.target}")
    print("energy pixels power  A (envelope)  texels needed  worst (scene, rung)  unreachable  mean texels^2 (M)")
    for r in results:
        print(f"{r['energy']:6.2f} {r['factor']:6.1f} {r['power']:5.2f}  {r['envelope']:12.4g}  {r['needed']:13.3f}"
              f"  {str(r['worst']):>19}  {r['unreachable']:11d}  {r['cost'] / len(scenes) / 1e6:8.3f}")
    best = min(results, key=lambda r: (r["unreachable"], r["cost"]))
    print(f"cheapest: energy {best['energy']}, pixel factor {best['factor']}, power {best['power']}: "
          f"{best['needed']:.3f} texels across max(R_{best['energy']}, {best['factor']} pixel) at the target "
          f"{args.target}; error model {best['envelope']:.4g} t^-{best['power']}")


if __name__ == "__main__":
    main()
