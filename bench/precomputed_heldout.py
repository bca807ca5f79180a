#!/usr/bin/env python3
"""The table of bench/precomputed_heldout.sh: PRECOMPUTED and FULL against REFERENCE on the
procedural test set (docs/PRECOMPUTED.md, "Held-out scenes").

    python3 bench/precomputed_heldout.py OUT

OUT holds scenes.txt (subsplat_auto_sets --save's list: index and description) and, per scene,
<set>_<i>.json (subsplat_replay --json; <set> test or calibration) or, where the render failed,
<set>_<i>.log.
"""
import json
import os
import re
import sys


def main():
    out = sys.argv[1]
    descriptions = {}
    prefix = "test"
    with open(os.path.join(out, "scenes.txt")) as f:
        for line in f:
            if line.startswith("# calibration set"):
                prefix = "calibration"
            m = re.match(r"\s*(\d+)\s+(.*\S)", line)
            if m:
                descriptions[int(m.group(1))] = m.group(2)
    print("| scene | description | FULL | PRECOMPUTED | exitance: FULL, PRECOMPUTED | FULL ms | relit ms | MiB |")
    print("|---|---|---|---|---|---|---|---|")
    within = measured = failed = 0
    for i in sorted(descriptions):
        path = os.path.join(out, f"{prefix}_{i}.json")
        if not os.path.exists(path):
            log = os.path.join(out, f"{prefix}_{i}.log")
            reason = ""
            if os.path.exists(log):
                with open(log) as f:
                    lines = [l.strip() for l in f if "ssRender" in l or "rror" in l]
                reason = lines[0] if lines else "no report"
            print(f"| {i} | {descriptions[i]} | failed: {reason} | | | | | |")
            failed += 1
            continue
        with open(path) as f:
            methods = {m["method"]: m for m in json.load(f)["scenes"][0]["methods"]}
        full, pre = methods["FULL"], methods["PRECOMPUTED"]
        measured += 1
        ok = pre["relative_rmse"] <= full["relative_rmse"]
        within += ok
        print(f"| {i} | {descriptions[i]} | {100 * full['relative_rmse']:.2f} % | "
              f"{100 * pre['relative_rmse']:.2f} %{'' if ok else ' (over)'} | "
              f"{100 * full['exitance_relative_rmse']:.1f} %, {100 * pre['exitance_relative_rmse']:.1f} % | "
              f"{full['median_frame_ms']:.0f} | {pre['median_frame_ms']:.0f} | "
              f"{pre['precomputed_bytes'] / 2**20:.0f} |")
    print(f"\nPRECOMPUTED within FULL's error against REFERENCE (image) on {within} of {measured} measured scenes; "
          f"{failed} failed.")


if __name__ == "__main__":
    main()
