"""Prints bench/ab_replay.sh's comparison: per scene and method, base against after."""
import glob
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gpu_tables import read_pfm  # noqa: E402


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "build/ab"
    print("| scene | method | frame ms, base / after | splatting ms, base / after | of which selection ms, base / after "
          "| fragments (M), base / after | samples, base / after | images: largest difference, relative RMSE |")
    print("|---|---|---|---|---|---|---|---|")
    for path in sorted(glob.glob(os.path.join(out, "base", "*.json"))):
        scene = os.path.basename(path)[:-5]
        base = json.load(open(path))["scenes"][0]["methods"]
        after = json.load(open(os.path.join(out, "after", scene + ".json")))["scenes"][0]["methods"]
        for b, a in zip(base, after):
            m = b["method"]
            ib = read_pfm(os.path.join(out, "base", f"{scene}_{m}.pfm"))
            ia = read_pfm(os.path.join(out, "after", f"{scene}_{m}.pfm"))
            largest = float(np.abs(ib - ia).max())
            rel = float(np.sqrt(((ib - ia) ** 2).mean()) / max(np.sqrt((ib ** 2).mean()), 1e-30))
            fb, fa = b["fragment_invocations"]["splatting"], a["fragment_invocations"]["splatting"]
            # selection_ms: SsStats since C API 23
            sb, sa = (f"{x['selection_ms']:.0f}" if "selection_ms" in x else "-" for x in (b, a))
            print(f"| {scene} | {m} | {b['median_frame_ms']:.0f} / {a['median_frame_ms']:.0f} "
                  f"({b['median_frame_ms'] / a['median_frame_ms']:.2f}x) | {b['stage_ms']['splatting']:.0f} / "
                  f"{a['stage_ms']['splatting']:.0f} | {sb} / {sa} | {fb / 1e6:.1f} / {fa / 1e6:.1f} | {b['splat_count']} / "
                  f"{a['splat_count']} | {largest:.3g}, {rel:.2g} |")


if __name__ == "__main__":
    main()
