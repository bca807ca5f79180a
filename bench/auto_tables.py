"""docs/AUTO.md's tables of the held-out scenes, from bench/auto_sets.sh's results.

    python3 bench/auto_tables.py bench/results/auto_sets [--energy 0.25 --pixels 1 --error 0.5148 --power 2]

Prints, as Markdown: the calibration set (the error each rung adds over its converged reference),
and the test set under AUTO (the resolution it chose, the error it adds, the calibrated model's
bound at it: A t^-p, t the coarsest light texels across max(R_f, c pixels)). The model's constants
default to native/src/testing/procedural.h's kModel*.
"""
import argparse
import json
import os


def model_texels(scene, texel, energies, energy, pixels):
    radius = scene["radii"][energies.index(energy)]
    return max(radius, pixels * scene["pixel"]) / texel if texel > 0 else 0.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("--energy", type=float, default=0.25)
    parser.add_argument("--pixels", type=float, default=1.0)
    parser.add_argument("--error", type=float, default=0.5148)
    parser.add_argument("--power", type=float, default=2.0)
    args = parser.parse_args()
    with open(os.path.join(args.folder, "calibration.json")) as f:
        calibration = json.load(f)
    with open(os.path.join(args.folder, "test.json")) as f:
        test = json.load(f)

    rungs = sorted({p["resolution"] for s in calibration["scenes"] for p in s["points"]})
    print(f"Calibration set ({len(calibration['scenes'])} scenes, {calibration['width']}x{calibration['height']}): "
          "the error each rung adds over its reference (MULTIRES, relative RMSE)\n")
    print("| scene | reference | t at 128 | " + " | ".join(f"{r}²" for r in rungs) + " |")
    print("|---|---|---|" + "---|" * len(rungs))
    for s in calibration["scenes"]:
        first = s["points"][0]
        t = model_texels(s, first["texel"], calibration["energies"], args.energy, args.pixels)
        added = {p["resolution"]: p["added"] for p in s["points"]}
        cells = [f"{added[r]:.4f}" if r in added else "" for r in rungs]
        print(f"| {s['index']}: {s['description']} | {s['reference']}² | {t:.2f} | " + " | ".join(cells) + " |")

    print(f"\nTest set ({len(test['scenes'])} scenes, {test['width']}x{test['height']}), AUTO at "
          f"{100 * test['target']:.0f} %: model {args.error} t^-{args.power:g}, t across max(R_{args.energy:g}, "
          f"{args.pixels:g} pixel)\n")
    print("| scene | AUTO | reference | adds | within the target | model t | model's bound | within the model |")
    print("|---|---|---|---|---|---|---|---|")
    within_target = within_model = measured = unreachable = 0
    for s in test["scenes"]:
        if not s["reachable"]:
            unreachable += 1
        if s["reference"] <= s["resolution"]:  # AUTO at the largest buffer: nothing finer to measure against
            print(f"| {s['index']}: {s['description']} | {s['resolution']}²"
                  f"{'' if s['reachable'] else ', said unreachable'} | - | not measured (no finer buffer) | | | | |")
            continue
        measured += 1
        t = model_texels(s, s["texel"], test["energies"], args.energy, args.pixels)
        bound = args.error * t ** -args.power if t > 0 else float("inf")
        ok_target, ok_model = s["added"] <= test["target"], s["added"] <= bound
        within_target += ok_target
        within_model += ok_model
        print(f"| {s['index']}: {s['description']} | {s['resolution']}²{'' if s['reachable'] else ', said unreachable'}"
              f" | {s['reference']}² | {s['added']:.4f} | {'yes' if ok_target else 'no'} | {t:.2f} | {bound:.4g} |"
              f" {'yes' if ok_model else 'no'} |")
    print(f"\nMeasured {measured} of {len(test['scenes'])} ({unreachable} said unreachable): {within_target} within the "
          f"target, {within_model} within the calibrated model's bound.")


if __name__ == "__main__":
    main()
