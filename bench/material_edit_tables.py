"""docs/MATERIAL_EDIT.md's tables, from bench/material_edit.sh's results.

    python3 bench/material_edit_tables.py bench/results/material_edit

Per scene: the precomputation against FULL of the same material (time and fragments), the
precomputed image's error against FULL's, and per edit whether the transport was reused, its time
and fragments against FULL of the edited material, and its error against that image.
"""
import argparse
import json
import os


def table(scenes):
    rows = ["| scene | precompute / FULL (time, fragments) | as precomputed | edit | reused | edit / FULL (time, fragments) | error |",
            "|---|---|---|---|---|---|---|"]
    for s in scenes:
        first = True
        for e in s["edits"]:
            head = (f"| {s['index']}: {s['scene']} | {s['precompute_ms'] / s['full_ms']:.1f}x, "
                    f"{s['precompute_fragments'] / s['full_fragments']:.1f}x | {100 * s['error']:.2f} % "
                    if first else "| | | ")
            first = False
            ratio = (f"1/{e['full_ms'] / e['edit_ms']:.0f}, 1/{e['full_fragments'] / max(e['edit_fragments'], 1):.0f}"
                     if e["reused"] else "(precomputed again)")
            rows.append(head + f"| {e['edit']} | {'yes' if e['reused'] else 'no'} | {ratio} | {100 * e['error']:.2f} % |")
    return "\n".join(rows)


def summary(scenes):
    reused = [e for s in scenes for e in s["edits"] if e["reused"]]
    within = sum(1 for e in reused if e["error"] < 0.01)
    pre_time = sorted(s["precompute_ms"] / s["full_ms"] for s in scenes)
    speed = sorted(e["full_ms"] / e["edit_ms"] for e in reused)
    frags = sorted(e["full_fragments"] / max(e["edit_fragments"], 1) for e in reused)
    return (f"{len(reused)} of {sum(len(s['edits']) for s in scenes)} edits reused the transport; {within} of them "
            f"within 1 % of FULL. Precomputation {pre_time[0]:.1f}-{pre_time[-1]:.1f}x a FULL frame's time; an edit "
            f"{speed[0]:.0f}-{speed[-1]:.0f}x faster than FULL and {frags[0]:.0f}-{frags[-1]:.0f}x fewer fragments.")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    args = parser.parse_args()
    for name in ("calibration_256", "test_256", "test_auto"):
        path = os.path.join(args.folder, name + ".json")
        if not os.path.exists(path):
            continue
        with open(path) as f:
            scenes = json.load(f)
        print(f"### {name}\n\n{summary(scenes)}\n\n{table(scenes)}\n")


if __name__ == "__main__":
    main()
