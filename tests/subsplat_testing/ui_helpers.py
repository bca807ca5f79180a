"""Shared by the tests that run Blender with its UI under Xvfb (tests/blender_ui/test_*.py).

A test is a generator of timer intervals (run_steps): Blender draws its windows between the steps,
so a step can change the scene, wait for the viewport to draw, and take a screenshot.
"""
import os
import sys
import time
import traceback

import bpy
import numpy as np

OUTPUT = os.environ.get("SUBSPLAT_TEST_OUTPUT", os.path.join(os.getcwd(), "test_output"))
os.makedirs(OUTPUT, exist_ok=True)
failures = []
STARTED = time.monotonic()


def check(condition, message):
    print(f"[{time.monotonic() - STARTED:6.1f} s] " + ("ok: " if condition else "FAILED: ") + message, flush=True)
    if not condition:
        failures.append(message)


def areas():
    window = bpy.context.window_manager.windows[0]
    by_type = {area.type: area for area in window.screen.areas}
    return window, by_type


def screenshot(name, prefix="viewport"):
    """The whole window as float RGB (rows bottom first), also saved as a PNG."""
    window, by_type = areas()
    path = os.path.join(OUTPUT, f"{prefix}_{name}.png")
    with bpy.context.temp_override(window=window, area=by_type["VIEW_3D"]):
        bpy.ops.screen.screenshot(filepath=path)
    image = bpy.data.images.load(path)
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(image.size[1], image.size[0], 4)[..., :3]
    bpy.data.images.remove(image)
    return pixels


def crop(pixels, area):
    """The pixels of one area (window coordinates, bottom-left origin)."""
    return pixels[area.y:area.y + area.height, area.x:area.x + area.width]


def region(area, kind):
    return next(r for r in area.regions if r.type == kind)


def crop_region(pixels, r):
    return pixels[r.y:r.y + r.height, r.x:r.x + r.width]


def redraw():
    for area in bpy.context.window_manager.windows[0].screen.areas:
        area.tag_redraw()


def drawn(subsplat, draws, timeout=120.0, settle=1.0):
    """Yields timer intervals until the viewport has drawn more than `draws` times (and then waits
    `settle` seconds more, for the window to show it)."""
    waited = 0.0
    while subsplat.last_viewport().get("draws", 0) <= draws and waited < timeout:
        redraw()
        yield 0.05 if settle == 0.0 else 0.5
        waited += 0.05 if settle == 0.0 else 0.5
    redraw()
    if settle > 0.0:
        yield settle


def close_splash(name):
    """Opening a file closes the splash screen that --factory-startup shows."""
    path = os.path.join(OUTPUT, f"{name}.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)


def enable_addon():
    import addon_utils
    addon_utils.enable("subsplat", default_set=True)
    import subsplat
    subsplat.diagnostics.exit_on_error = False
    from . import one_sample
    one_sample.pin()
    return subsplat


def run_steps(steps):
    """Runs the generator `steps` from a timer, then exits Blender: 0 when every check passed."""
    def tick():
        try:
            return next(steps)
        except StopIteration:
            finish()
        except Exception:  # a broken test must fail, not hang the UI
            traceback.print_exc()
            failures.append("exception")
            finish()
        return None

    bpy.app.timers.register(tick, first_interval=1.0, persistent=True)


def finish():
    print(f"{len(failures)} failed" if failures else "all checks passed", flush=True)
    sys.stdout.flush()
    os._exit(1 if failures else 0)
