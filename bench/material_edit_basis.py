"""The edit basis against its number of coefficients (docs/MATERIAL_EDIT.md, "The basis"; the
paper's Figures 1 and 2 on our profiles).

    python3 bench/material_edit_basis.py [--tool build/native/subsplat_basis]

Builds and runs subsplat_basis (about 15 s on 2 cores), saves its results to
bench/results/material_edit_basis.json, draws docs/images/material_edit_basis.png and prints the
Markdown table of docs/MATERIAL_EDIT.md. The knots are fitted on the calibration media
(kCalibrationSeed); the presets (as precomputed and edited) and the test media (kEditTestSeed) are
never fitted on.
"""
import argparse
import json
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tool", default=os.path.join(ROOT, "build", "native", "subsplat_basis"))
    parser.add_argument("--results", default=os.path.join(ROOT, "bench", "results", "material_edit_basis.json"))
    parser.add_argument("--image", default=os.path.join(ROOT, "docs", "images", "material_edit_basis.png"))
    args = parser.parse_args()
    build = os.path.dirname(os.path.dirname(args.tool))
    subprocess.run(["cmake", "--build", build, "--target", "subsplat_basis"], check=True, capture_output=True)
    out = subprocess.run([args.tool, "--intervals", "2,3,4,6,8,12,16,24,32,48"], check=True,
                         capture_output=True, text=True).stdout
    data = json.loads(out)
    with open(args.results, "w") as f:
        json.dump(data, f, indent=1)
        f.write("\n")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    styles = {(1, "fitted"): ("C0", "-"), (2, "fitted"): ("C1", "-"),
              (1, "uniform"): ("C0", ":"), (2, "uniform"): ("C1", ":")}
    for ax, family, title in ((axes[0], "presets", "presets, as precomputed and edited"),
                              (axes[1], "test_media", "random test media")):
        for (degree, knots), (colour, line) in styles.items():
            rows = [r for r in data["rows"] if r["degree"] == degree and r["knots"] == knots]
            xs = [r["coefficients"] for r in rows]
            name = "linear" if degree == 1 else "quadratic"
            ax.plot(xs, [r[family]["mean_cumulative"] * 100 for r in rows], color=colour, linestyle=line,
                    marker="o", markersize=3, label=f"{name}, {knots} knots, mean")
            if knots == "fitted":
                ax.plot(xs, [r[family]["max_cumulative"] * 100 for r in rows], color=colour, linestyle="--",
                        linewidth=0.8, label=f"{name}, {knots} knots, largest")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("coefficients per channel")
        ax.set_ylabel("error of the energy within a radius (%)")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(args.image, dpi=110)

    print("| coefficients | basis | knots | calibration mean / max | presets mean / max | test media mean / max | presets' relative L1, mean |")
    print("|---|---|---|---|---|---|---|")
    for r in data["rows"]:
        cells = [f"{r[k]['mean_cumulative'] * 100:.2f} % / {r[k]['max_cumulative'] * 100:.2f} %"
                 for k in ("calibration", "presets", "test_media")]
        name = "linear" if r["degree"] == 1 else "quadratic"
        print(f"| {r['coefficients']} | {name} | {r['knots']} | " + " | ".join(cells) +
              f" | {r['presets']['mean_l1'] * 100:.1f} % |")
    beyond = data["rows"][0]["presets"]["beyond_reach"]
    print(f"\n{data['preset_profiles']} preset profiles, {beyond} of them beyond the reach (left out); "
          f"{data['calibration_media']} calibration media, {data['test_media']} test media.")


if __name__ == "__main__":
    main()
