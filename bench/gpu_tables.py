"""The GPU section of docs/BENCHMARKS.md ("On a GPU") from bench/gpu_replay.sh's results.

    /usr/bin/python3 bench/gpu_tables.py bench/results/gpu_h200 [--images GPU_DIR LLVMPIPE_DIR --figure PNG]
    /usr/bin/python3 bench/gpu_tables.py --budget bench/results/gpu_h200_budget . (the viewport's budget)

Reads the per-scene reports (hd_*.json at the large size, small.json at llvmpipe's size,
hd_wax_jade_epsilon.json) and prints Tables 1 and 2 as bench/replay.py writes them. With --images,
compares FULL's images from the GPU (gpu_replay.sh's images.tar.gz, unpacked) with the same
command's on this machine (subsplat_replay --runs 1 --size 400x300 --no-reference --methods FULL
--images LLVMPIPE_DIR build/bench/{skin_suzanne,wax_jade,heterogeneous}.ssscene) and draws them
side by side with their difference.
"""
import argparse
import glob
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import replay  # noqa: E402

ORDER = ["marble_pieces", "skin_suzanne", "finger_pose", "candle_twist", "heterogeneous", "wax_jade"]


def load(path):
    with open(path) as f:
        return json.load(f)


def checked(report):
    """Marks the counts and times a driver returned that are none (reports written before
    subsplat_replay wrote timers_available and statistics_available), by the library's own rule
    (native/src/pipeline/stage_profiler.h): more fragments than 1e12 per second of the frame, or no
    stage time at all."""
    for scene in report["scenes"]:
        for m in scene["methods"]:
            if "statistics_available" not in m:
                limit = 1e12 * min(m["frame_ms"]) * 1e-3 + 1e9
                m["statistics_available"] = all(v <= limit for v in m["fragment_invocations"].values())
            if "timers_available" not in m:
                m["timers_available"] = sum(m["stage_ms"].values()) > 0
    return report


def merged(folder, pattern):
    """One report of every scene in the files matching pattern, in ORDER."""
    reports = [checked(load(p)) for p in sorted(glob.glob(os.path.join(folder, pattern)))
               if "epsilon" not in p or "epsilon" in pattern]
    scenes = {s["scene"]: s for r in reports for s in r["scenes"]}
    first = reports[0]
    return {"renderer": first["renderer"], "cpu": first["cpu"], "runs": first["runs"],
            "scenes": [scenes[n] for n in ORDER if n in scenes]}


def read_pfm(path):
    import numpy as np
    with open(path, "rb") as f:
        f.readline()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(height, width, -1)[::-1]


def compare_images(gpu, llvmpipe, figure):
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = ["skin_suzanne", "wax_jade", "heterogeneous"]
    fig, axes = plt.subplots(len(names), 3, figsize=(12, 3 * len(names)))
    lines = ["| scene | pass | relative RMSE | mean (GPU / llvmpipe) | pixels off by more than 1 % |",
             "|---|---|---|---|---|"]
    for row, name in enumerate(names):
        for suffix, label in (("", "image"), ("_exitance", "exitance")):
            a = read_pfm(os.path.join(gpu, f"{name}_FULL{suffix}.pfm"))
            b = read_pfm(os.path.join(llvmpipe, f"{name}_FULL{suffix}.pfm"))
            mask = (a.sum(-1) > 0) | (b.sum(-1) > 0)
            rel = np.sqrt(((a - b) ** 2)[mask].mean()) / np.sqrt((b ** 2)[mask].mean())
            off = (np.abs(a - b) > 0.01 * np.maximum(np.abs(b), 1e-3)).any(-1)[mask].mean()
            lines.append(f"| {name} | {label} | {rel:.4f} | {a[mask].mean():.4f} / {b[mask].mean():.4f} | "
                         f"{100 * off:.1f} % |")
            if suffix:
                continue
            axes[row, 0].imshow(np.clip(a, 0, 1) ** (1 / 2.2))
            axes[row, 0].set_title(f"{name}: NVIDIA H200")
            axes[row, 1].imshow(np.clip(b, 0, 1) ** (1 / 2.2))
            axes[row, 1].set_title("llvmpipe")
            shown = axes[row, 2].imshow(np.abs(a - b).sum(-1), cmap="magma", vmin=0, vmax=0.1)
            axes[row, 2].set_title("|difference|, RGB summed (0 to 0.1)")
            fig.colorbar(shown, ax=axes[row, 2])
    for axis in axes.flat:
        axis.axis("off")
    fig.tight_layout()
    fig.savefig(figure, dpi=60)
    return lines


def budget_table(folder):
    """Markdown lines: each example's frame under the viewport's splatting budget (budget_*.json,
    subsplat_replay --budget) beside the same frame in one render (oneshot.json), same call."""
    oneshot = {s["scene"]: s["methods"][0] for s in load(os.path.join(folder, "oneshot.json"))["scenes"]}
    lines = ["| scene | one render: ms | its splatting fragments | budgeted: renders | first ms | longest ms | "
             "all renders ms | most splatting fragments in one |", "|---|---|---|---|---|---|---|---|"]
    for name in ORDER:
        path = os.path.join(folder, f"budget_{name}.json")
        if not os.path.exists(path):
            continue
        m = load(path)["scenes"][0]["methods"][0]
        runs = m["budget_runs"]
        whole = oneshot[name]
        splat = sum(whole["splat_level_fragments"])
        lines.append(f"| {name} | {whole['median_frame_ms']:.0f} | {splat / 1e6:.0f} M | {runs[0]['renders']} | "
                     f"{max(r['first_ms'] for r in runs):.0f} | {max(r['longest_ms'] for r in runs):.0f} | "
                     f"{m['median_frame_ms']:.0f} | {max(r['most_splat_fragments'] for r in runs) / 1e6:.0f} M |")
    return lines


def main():
    parser = argparse.ArgumentParser(prog="bench/gpu_tables.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("folder")
    parser.add_argument("--ranges", default=None, help="build/bench/ranges.json (bench/methods.py)")
    parser.add_argument("--images", nargs=2, metavar=("GPU_DIR", "LLVMPIPE_DIR"))
    parser.add_argument("--figure", default="docs/images/gpu_vs_llvmpipe.png")
    parser.add_argument("--budget", metavar="FOLDER", help="print the budget table of this folder only")
    args = parser.parse_args()
    if args.budget:
        print("\n".join(budget_table(args.budget)))
        return
    ranges = load(args.ranges) if args.ranges else None
    for title, pattern in (("1920 x 1080", "hd_[a-z]*[a-z].json"), ("800 x 600", "small.json"),
                           ("wax_jade, eq. 14's epsilon, 1920 x 1080", "hd_wax_jade_epsilon.json")):
        report = merged(args.folder, pattern)
        if "epsilon" in pattern:  # no BRUTE in this report: its ratios against the main run's BRUTE
            brute = next(m for m in merged(args.folder, "hd_wax_jade.json")["scenes"][0]["methods"]
                         if m["method"] == "BRUTE")
            report["scenes"][0]["methods"].insert(0, brute)
        one, two, verdicts = replay.tables(report, ranges)
        print(f"### {title} ({report['renderer']}, {report['runs']} runs)\n")
        print("\n".join(one) + "\n")
        print("\n".join(two) + "\n")
        if verdicts:
            print("\n".join(verdicts) + "\n")
    if args.images:
        print("\n".join(compare_images(*args.images, args.figure)))


if __name__ == "__main__":
    main()
