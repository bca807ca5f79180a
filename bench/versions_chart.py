"""EEVEE's and Cycles' points of the chart (docs/TRADEOFF.md) in the Blender that runs this script:
the four DIPOLE examples as their physical variants at 10 % (`physical.example_case(name, 10,
bounce=False)`), each translucent material given its Principled equivalent
(`accuracy.principled_equivalent`, Principled v1 or v2 by version), EEVEE and Cycles at the chart's
sample counts, each against the committed Cycles-twin truth (bench/results/truth/tradeoff_<scene>_10,
its noise taken out: twin_truth.error) and against REFERENCE (mask: REFERENCE's translucent pixels).
Writes bench/results/versions_chart_<version>.json; docs/VERSIONS.md, "The chart's EEVEE and Cycles
points in 5.0". Runs in Debian's Blender and in a `bpy` module alike:

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --python bench/versions_chart.py
    BLENDER_USER_SCRIPTS=build/scripts build/bpy-5.0.1/bin/python bench/versions_chart.py
"""
import json
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))

import bpy  # noqa: E402

from subsplat_testing import accuracy, helpers, physical, twin_truth  # noqa: E402

SCENES = ("skin_suzanne", "marble_pieces", "wax_jade", "finger_pose")
EEVEE_SAMPLES = (1, 4, 16, 64)
CYCLES_SAMPLES = (4, 16, 64, 256)


def eevee_engine():
    items = bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items.keys()
    return "BLENDER_EEVEE_NEXT" if "BLENDER_EEVEE_NEXT" in items else "BLENDER_EEVEE"


def main():
    helpers.enable_addon()
    scratch = tempfile.mkdtemp(prefix="versions_chart_")
    results = {"blender": bpy.app.version_string, "machine": helpers.machine(), "scenes": {}}
    for name in SCENES:
        scene, _notes = physical.example_case(name, 10, bounce=False)
        for material in bpy.data.materials:
            if material.subsplat.enabled and material.subsplat.source == "DIPOLE":
                accuracy.principled_equivalent(material)
        reference, exitance, _stats = accuracy.render_passes(scene, "REFERENCE", 50000)
        mask = exitance[..., 3] > 0.5
        truth, _record = twin_truth.load(f"tradeoff_{name}_10", shape=reference.shape)
        points = []
        for engine, counts in (("EEVEE", EEVEE_SAMPLES), ("Cycles", CYCLES_SAMPLES)):
            if engine == "EEVEE":
                scene.render.engine = eevee_engine()
                scene.eevee.taa_render_samples = 1
                helpers.render_to(scene, os.path.join(scratch, f"{name}_warmup.exr"))
            for samples in counts:
                if engine == "EEVEE":
                    scene.eevee.taa_render_samples = samples
                else:
                    accuracy.use_cycles(scene, samples)
                start = time.perf_counter()
                image = helpers.render_to(scene, os.path.join(scratch, f"{name}_{engine}_{samples}.exr"))
                ms = 1e3 * (time.perf_counter() - start)
                error, uncorrected, noise, ratio = twin_truth.error(image, truth, mask)
                ours, theirs = image[mask][:, :3].astype(float), reference[mask][:, :3].astype(float)
                against_reference = float(((ours - theirs) ** 2).mean() ** 0.5 / (theirs ** 2).mean() ** 0.5)
                points.append({"engine": engine, "samples": samples, "ms": ms, "truth_error": error,
                               "truth_error_uncorrected": uncorrected, "mean_over_truth": ratio,
                               "reference_error": against_reference})
                print(f"{bpy.app.version_string} {name} {engine} {samples}: against the truth {error:.3f} "
                      f"(mean {ratio:.2f} x), against REFERENCE {against_reference:.3f}, {ms:.0f} ms", flush=True)
        results["scenes"][name] = points
    version = ".".join(str(v) for v in bpy.app.version)
    path = os.path.join(HERE, "results", f"versions_chart_{version}.json")
    with open(path, "w") as f:
        json.dump(results, f, indent=1)
        f.write("\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    status = 1
    try:
        main()
        status = 0
    finally:
        if not bpy.app.binary_path:  # the bpy module: its status before the C library's exit
            sys.stdout.flush()
            os._exit(status)
