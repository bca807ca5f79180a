"""The viewport's redraws with and without its budget, from two runs of bench/viewport.py at the
same revision (docs/BENCHMARKS.md, "Viewport"):

    BLENDER_USER_SCRIPTS=build/scripts xvfb-run -a -s "-screen 0 1280x800x24" blender \\
        --factory-startup --python bench/viewport.py -- --scales 1
    BLENDER_USER_SCRIPTS=build/scripts xvfb-run -a -s "-screen 0 1280x800x24" blender \\
        --factory-startup --python bench/viewport.py -- --scales 1 --budget 0 \\
        --output viewport_no_budget.json --no-document
    python3 bench/viewport_compare.py build/bench/viewport.json build/bench/viewport_no_budget.json
"""
import json
import sys


def main():
    with open(sys.argv[1]) as f:
        budget = {(r["scene"], r["scale"]): r for r in json.load(f)["scenes"]}
    with open(sys.argv[2]) as f:
        whole = {(r["scene"], r["scale"]): r for r in json.load(f)["scenes"]}
    print("| scene | scale | change | one render (no budget): ms | budgeted: first ms | longest ms | redraws | "
          "all redraws ms |")
    print("|---|---|---|---|---|---|---|---|")
    for key, row in budget.items():
        if key not in whole:
            continue
        for change in ("light", "deformation"):
            b, w = row[change], whole[key][change]
            print(f"| {key[0]} | {key[1]} | {b['kind']} | {w['draw_ms']:.0f} | {b['draw_ms']:.0f} | "
                  f"{b['longest_draw_ms']:.0f} | {b['redraws']} | {b['all_draws_ms']:.0f} |")


if __name__ == "__main__":
    main()
