"""Soak: 1000 final renders in one Blender process, each with a changed scene, leave nothing behind.

Every render changes the deforming candle's frame (a new mesh from its modifiers) and the sphere's
material (preset and scale, and every 7th render between a dipole and a SubEdit file); every render
moves and rescales the lights, every 10th adds or removes a second light, and every 25th adds or
removes an object whose vertex count changes each time. After each render: no error, finite
pixels, translucent pixels lit, no native context, GL object or byte of GPU memory still held; over
the run, Blender's resident memory stays flat. docs/RELIABILITY.md records the figures it prints.
CI renders 100 times (every change above recurs at least twice, the presets 9 times, the scales 11,
the SubEdit file 7) and bounds the memory's growth over the last 50 (100 renders alone here: 417.5
MiB after 50, 420.5 after 100; AMD EPYC, 2026-12-04); the slow tier (SUBSPLAT_SLOW=1, bench/slow.sh)
renders 1000 times and also bounds its slope. SUBSPLAT_SOAK_RENDERS sets any other count.
"""
import math
import os
import time
import unittest

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
import bpy  # noqa: E402
import numpy as np  # noqa: E402

RENDERS = int(os.environ.get("SUBSPLAT_SOAK_RENDERS", "1000" if helpers.SLOW else "100"))
PRESETS = [key for key in subsplat.presets.MEASURED_MEDIA]
# Renders that fill the caches (shaders, kernel tables, the SubEdit file's profiles) before memory
# must stay flat: one cycle of the presets and scales (99 renders with 11 presets and 9 scales), or
# half the run when it is shorter (CI's 100: the growth from render 50 to 100 measured 3 MiB).
SETTLE = min(100, RENDERS // 2)


def resident_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def build_scene():
    bpy.ops.wm.open_mainfile(filepath=os.path.join(helpers.SOURCE, "example_blends", "candle_twist.blend"))
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 64, 48
    scene.render.resolution_percentage = 100
    scene.subsplat.irradiance_resolution = 64
    scene.render.filepath = os.path.join(helpers.OUTPUT, "soak_")
    candle = next(o for o in scene.objects if o.type == "MESH")
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.25 * max(candle.dimensions), location=candle.location)
    sphere = bpy.context.object
    sphere.name = "SoakSphere"
    material = bpy.data.materials.new("SoakMaterial")
    material.subsplat.enabled = True
    sphere.data.materials.append(material)
    light = next(o for o in scene.objects if o.type == "LIGHT")
    return scene, candle, sphere, material, light


def change(i, scene, candle, sphere, material, light, state):
    """The i-th render's changes (see the module's docstring)."""
    scene.frame_set(1 + i % 48)
    settings = material.subsplat
    if i % 7 == 3:
        settings.source = "SUBEDIT_FILE" if settings.source == "DIPOLE" else "DIPOLE"
        settings.subedit_path = os.path.join(helpers.SOURCE, "example_blends", "materials", "varying_wax.exr")
    settings.preset = PRESETS[i % len(PRESETS)]
    # The SubEdit file at the candle's scale: at 10-50 mm per unit its kernels take ssSetMaterial
    # about 3.7 s on this machine instead of milliseconds (docs/RELIABILITY.md, "Not yet").
    settings.mm_per_unit = 10.0 + 5.0 * (i % 9) if settings.source == "DIPOLE" else 310.0
    angle = 2.0 * math.pi * i / 37.0
    light.location = (light.location.length * math.cos(angle), light.location.length * math.sin(angle),
                      light.location.z)
    light.data.energy = state["energy"] * (0.5 + (i % 5) / 4.0)
    if i % 10 == 0:
        if state["second"] is None:
            data = bpy.data.lights.new("SoakPoint", "POINT")
            data.energy = 50.0
            data.shadow_soft_size = 0.0  # churn, not soft shadows (their filter took the CI soak from 83 s to 99 s)
            state["second"] = bpy.data.objects.new("SoakPoint", data)
            state["second"].location = (0.0, -2.0, 2.0)
            scene.collection.objects.link(state["second"])
        else:
            data = state["second"].data
            bpy.data.objects.remove(state["second"])
            bpy.data.lights.remove(data)
            state["second"] = None
    if i % 25 == 0:
        if state["extra"] is None:
            segments = 8 + (i // 25) % 24
            bpy.ops.mesh.primitive_uv_sphere_add(segments=segments, ring_count=segments // 2 + 2, radius=0.1,
                                                 location=(sphere.location.x + 0.3, sphere.location.y, sphere.location.z))
            state["extra"] = bpy.context.object
            state["extra"].data.materials.append(material)
        else:
            data = state["extra"].data
            bpy.data.objects.remove(state["extra"])
            bpy.data.meshes.remove(data)
            state["extra"] = None


class ThousandRendersLeaveNothingBehind(unittest.TestCase):
    def test_renders_with_changing_meshes_materials_and_lights(self):
        scene, candle, sphere, material, light = build_scene()
        state = {"second": None, "extra": None, "energy": light.data.energy}
        # The scene's lights, and its world (a light of its own, docs/WORLD.md) when it lights.
        base_lights = sum(o.type == "LIGHT" for o in scene.objects) + (max(scene.world.color) > 0)
        memory, started = [], time.perf_counter()
        for i in range(RENDERS):
            change(i, scene, candle, sphere, material, light, state)
            bpy.ops.render.render()
            self.assertIsNone(subsplat.last_render_error(), f"render {i}")
            stats = subsplat.last_render_stats()
            self.assertEqual(stats["nonfinite_pixels"], 0, f"render {i}")
            self.assertGreater(stats["lit_translucent_pixels"], 50, f"render {i}: {stats}")
            expected_lights = base_lights + (state["second"] is not None)
            self.assertEqual(stats["lights"], expected_lights, f"render {i}")
            counts = subsplat.native.resource_counts()
            held = {k: v for k, v in counts.items() if k != "profile_sets"}  # the SubEdit file stays cached
            self.assertEqual(held, dict.fromkeys(held, 0), f"render {i}: the library still holds {counts}")
            self.assertLessEqual(counts["profile_sets"], 1, f"render {i}: {counts}")
            used, _ = subsplat.native.memory_usage()
            self.assertEqual(used, 0, f"render {i}: {used} bytes of GPU memory still held")
            memory.append(resident_bytes())
        seconds = time.perf_counter() - started
        # The first renders fill caches (shaders, kernel tables, the SubEdit file's profiles); after
        # them resident memory must stay flat: no steady slope (one frame's mesh arrays are ~150 KiB)
        # and growth over the rest below 32 MiB (the allocator has been seen to step up 13.6 MiB once).
        # The slope needs the slow tier's 900 renders after the first 100: over 200 after them, a passing
        # rise and fall of 16 MiB gave 57 KiB per render. CI asserts the growth (and, after every render,
        # that the library holds nothing).
        # Resident memory swings by up to 10 MiB from one render to the next (the allocator and the
        # driver's caches), so the growth is taken between the medians of the 10 renders up to the
        # settling point and of the last 10, not between two single renders (docs/RELIABILITY.md,
        # "Soak": from render 50 to render 100, 26 MiB at bf20b41 alone, 0.2 to 23 MiB at ee5f9a8
        # alone and 40 MiB in its CI run, beside other tests).
        settled = np.asarray(memory[SETTLE:], dtype=np.float64)
        window = min(10, SETTLE)
        growth = float(np.median(memory[-window:]) - np.median(memory[SETTLE - window:SETTLE]))
        slope = np.polyfit(np.arange(len(settled)), settled, 1)[0]
        print(f"soak: {RENDERS} renders in {seconds:.0f} s ({1e3 * seconds / RENDERS:.0f} ms each); resident memory "
              f"{memory[0] / 2**20:.1f} MiB after the first, {settled[0] / 2**20:.1f} MiB after {SETTLE}, "
              f"{settled[-1] / 2**20:.1f} MiB after {RENDERS}, largest {max(memory) / 2**20:.1f} MiB; "
              f"growth of the windows' medians {growth / 2**20:.1f} MiB; slope {slope / 1024:.2f} KiB per render",
              flush=True)
        self.assertLess(growth, 32 * 2**20)
        if RENDERS >= 1000:
            self.assertLess(slope, 16 * 1024)


if __name__ == "__main__":
    helpers.run_tests()
