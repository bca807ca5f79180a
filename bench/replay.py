#!/usr/bin/env python3
"""The methods benchmark without Blender (the paper's Tables 1 and 2): replays scene files with
build/native/subsplat_replay and writes the tables as Markdown.

    python3 bench/replay.py [--runs 3] [--levels 3] [--output docs/BENCHMARKS.md] SCENE.ssscene...

Scene files come from bench/methods.py (in Blender, which then calls this script) or from any
render with Save Scene File set. Runs anywhere the library builds and EGL works (llvmpipe; an NVIDIA
GPU through its EGL device). Every figure comes from one run: each scene renders every method in
turn, `--runs` times, then REFERENCE once for the error columns.
"""
import argparse
import datetime
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
# The paper's four configurations at the levels given, and FULL as the product ships it.
METHODS = "BRUTE,MULTIRES,ADAPTIVE,FULL,FULL:0"
STAGES = ("buffers", "splatting", "shading", "readback")


def replay(binary, scenes, runs, levels, reference_samples, methods=METHODS):
    """Runs subsplat_replay; returns its JSON report."""
    with tempfile.TemporaryDirectory() as directory:
        report = os.path.join(directory, "report.json")
        command = [binary, "--runs", str(runs), "--json", report, "--methods", methods]
        if levels is not None:
            command += ["--levels", str(levels)]
        if reference_samples:
            command += ["--reference-samples", str(reference_samples)]
        print(" ".join(command + scenes), flush=True)
        subprocess.run(command + scenes, check=True)
        with open(report) as f:
            figures = json.load(f)
    figures["revision"] = git_revision()  # what was measured, kept with the figures
    return figures


def git_revision():
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                          text=True).stdout.strip() or "unknown"


def _share(part, total):
    return f"{100.0 * part / total:.0f}" if total > 0 else "-"


def tables(report, ranges=None):
    """Markdown lines: Table 1 (time, speed-up, work, error) and Table 2 (where the time goes)."""
    ranges = ranges or {}
    one = ["| scene | R_P / bounding radius | method | levels (irradiance / splatting) | frame ms (median) | "
           "speed-up | fragments | fragment ratio | relative RMSE | exitance relative RMSE |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    two = ["| scene | method | buffers | splatting, per level (0 / 1 / ...) | accumulation | shading | read-back | "
           "fragments per splatting level (M) |",
           "|---|---|---|---|---|---|---|---|"]
    verdicts = []
    for scene in report["scenes"]:
        name = scene["scene"]
        methods = {m["method"]: m for m in scene["methods"]}
        brute = methods.get("BRUTE")
        span = ranges.get(name)
        span_text = f"{span[0]:.3f} - {span[1]:.3f}" if span else "-"
        for label, m in methods.items():
            label = label.replace(":0", " (automatic levels)")
            fragments = m["fragment_invocations"]["total"]
            counted = m.get("statistics_available", True)  # false: the driver's counts were no counts
            speed = brute["median_frame_ms"] / m["median_frame_ms"] if brute else float("nan")
            ratio_text = "-"
            if brute and counted and brute.get("statistics_available", True):
                ratio_text = f"{brute['fragment_invocations']['total'] / max(fragments, 1):.2f}x"
            rmse = f"{m['relative_rmse']:.4f}" if "relative_rmse" in m else "-"
            b_rmse = f"{m['exitance_relative_rmse']:.4f}" if "exitance_relative_rmse" in m else "-"
            fragments_text = f"{fragments / 1e6:.0f} M" if counted else "-"
            one.append(f"| {name} | {span_text} | {label} | {m['levels']} / {m['splat_levels']} | "
                       f"{m['median_frame_ms']:.0f} | {speed:.2f}x | {fragments_text} | {ratio_text} | "
                       f"{rmse} | {b_rmse} |")
            total = sum(m["stage_ms"].values()) if m.get("timers_available", True) else 0.0
            levels = " / ".join(_share(t, total) for t in m["splat_level_ms"])
            level_fragments = " / ".join(f"{f / 1e6:.0f}" for f in m["splat_level_fragments"]) if counted else "-"
            if not total:
                two.append(f"| {name} | {label} | - | - | - | - | - | {level_fragments} |")
                continue
            two.append(f"| {name} | {label} | {_share(m['stage_ms']['buffers'], total)} | {levels} | "
                       f"{_share(m['accumulation_ms'], total)} | {_share(m['stage_ms']['shading'], total)} | "
                       f"{_share(m['stage_ms']['readback'], total)} | {level_fragments} |")
        full = methods.get("FULL")
        if span and brute and full and span[1] > 0.1:
            speed = brute["median_frame_ms"] / full["median_frame_ms"]
            if brute.get("statistics_available", True) and full.get("statistics_available", True):
                ratio = brute["fragment_invocations"]["total"] / max(full["fragment_invocations"]["total"], 1)
                met = ratio >= 5.0 and speed >= 4.0
                verdicts.append(f"- {name} (longest R_P {span[1]:.2f} of the bounding radius): FULL does "
                                f"{ratio:.1f}x fewer fragment invocations and is {speed:.1f}x faster than BRUTE: "
                                f"target (5x, 4x) {'met' if met else 'missed'}.")
            else:
                verdicts.append(f"- {name} (longest R_P {span[1]:.2f} of the bounding radius): FULL is "
                                f"{speed:.1f}x faster than BRUTE; the driver's fragment counts were no counts.")
    return one, two, verdicts


def document(report, ranges, command, levels, title="Methods (the paper's Tables 1 and 2)", note=""):
    one, two, verdicts = tables(report, ranges)
    revision = report.get("revision") or git_revision()
    levels_text = "automatic levels" if levels in (None, 0) else f"{levels} levels"
    lines = [
        f"## {title}",
        "",
        f"Taken {datetime.date.today()} at revision `{revision}` on {report['cpu']}, {os.cpu_count()} cores, "
        f"OpenGL renderer `{report['renderer']}`, by",
        "",
        f"    {command}",
        "",
        f"Each scene rendered {report['runs']} times per method, the methods in turn, at the saved frame size "
        f"with the saved irradiance resolution and {levels_text}; REFERENCE once, for the error columns "
        "(relative RMSE over translucent pixels, as docs/ACCURACY.md). Frame time is the wall time of "
        "`ssRender` (median); stage times are GL timer queries and fragment counts "
        "`GL_FRAGMENT_SHADER_INVOCATIONS`, of the fastest run.",
        "",
        "Table 1: time, work and error.",
        "",
        *one,
        "",
        "Table 2: where the time goes, in % of the summed GL stage times. Splatting is split per splatting "
        "level (finest first) and eq. 17's accumulation; the last column is each level's fragment count.",
        "",
        *two,
        "",
    ]
    if verdicts:
        lines += ["Target (FULL against BRUTE where the scattering range exceeds 0.1 of the bounding radius):", "",
                  *verdicts, ""]
    if note:
        lines += [note, ""]
    return lines


def main():
    parser = argparse.ArgumentParser(prog="bench/replay.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("scenes", nargs="+", help="scene files (.ssscene)")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--levels", type=int, default=None, help="0 automatic, 1-8 forced (default: as saved)")
    parser.add_argument("--reference-samples", type=int, default=0)
    parser.add_argument("--methods", default=METHODS, help=f"subsplat_replay --methods (default {METHODS})")
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "native", "subsplat_replay"))
    parser.add_argument("--output", default=None, help="Markdown file to write (default: print)")
    parser.add_argument("--ranges", default=None, help="JSON {scene: [lo, hi]} of R_P over bounding radius")
    args = parser.parse_args()
    report = replay(args.binary, args.scenes, args.runs, args.levels, args.reference_samples, args.methods)
    ranges = {}
    if args.ranges:
        with open(args.ranges) as f:
            ranges = json.load(f)
    command = "python3 bench/replay.py " + " ".join(sys.argv[1:])
    lines = "\n".join(["# Benchmarks (native replay)", "", *document(report, ranges, command, args.levels)])
    if args.output:
        with open(args.output, "w") as f:
            f.write(lines)
        print(f"wrote {args.output}")
    else:
        print(lines)


if __name__ == "__main__":
    main()
