"""Shared by the tests that run inside `blender -b` (see tests/CMakeLists.txt)."""
import math
import os
import subprocess
import sys
import tempfile

import bpy
import numpy as np

OUTPUT = os.environ.get("SUBSPLAT_TEST_OUTPUT", os.path.join(tempfile.gettempdir(), "subsplat_tests"))
SOURCE = os.environ.get("SUBSPLAT_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(__file__))))
os.makedirs(OUTPUT, exist_ok=True)
# The test's CTest timeout in seconds (tests/CMakeLists.txt): Blender processes a test starts end within it.
TIMEOUT = float(os.environ.get("SUBSPLAT_TEST_TIMEOUT", "900"))
# The slow tier (bench/slow.sh, CTest label slow): the full-size runs of the tests CI runs reduced.
SLOW = os.environ.get("SUBSPLAT_SLOW") == "1"


def machine():
    """CPU model and core count, for the figures benchmarks write."""
    import platform
    cpu = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{cpu}, {os.cpu_count()} cores"


def enable_addon():
    import addon_utils
    addon_utils.enable("subsplat", default_set=True)
    import subsplat
    subsplat.diagnostics.exit_on_error = False
    from . import one_sample
    one_sample.pin()
    return subsplat


def empty_scene(width, height):
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    world = bpy.data.worlds.new("World")
    set_world_colour(world, (0.0, 0.0, 0.0))
    scene.world = world
    scene.view_settings.view_transform = "Standard"
    return scene


def set_world_colour(world, colour):
    """A plain world colour: world.color without nodes (3.x, 4.x); in 5.0, where every world renders
    its node tree, its Background node's colour too."""
    world.color = colour
    if bpy.app.version >= (5, 0, 0):
        world.node_tree.nodes["Background"].inputs["Color"].default_value = (*colour, 1.0)
    else:
        world.use_nodes = False


def top_down_camera(scene, ortho_scale, height=5.0):
    data = bpy.data.cameras.new("Camera")
    data.type = "ORTHO"
    data.ortho_scale = ortho_scale
    data.clip_start, data.clip_end = 0.1, 100.0
    camera = bpy.data.objects.new("Camera", data)
    camera.location = (0, 0, height)
    scene.collection.objects.link(camera)
    scene.camera = camera
    return camera


def plane(scene, size, material):
    mesh = bpy.data.meshes.new("Plane")
    h = size / 2
    mesh.from_pydata([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [], [(0, 1, 2, 3)])
    mesh.materials.append(material)
    obj = bpy.data.objects.new("Plane", mesh)
    scene.collection.objects.link(obj)
    return obj


def unit_box(scene, material):
    """A 1 x 1 x 1 box standing on z = 0, centred on the z axis (the shadow tests' blocker)."""
    mesh = bpy.data.meshes.new("Box")
    corners = [(x, y, z) for z in (0.0, 1.0) for y in (-0.5, 0.5) for x in (-0.5, 0.5)]
    mesh.from_pydata(corners, [], [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)])
    mesh.materials.append(material)
    box = bpy.data.objects.new("Box", mesh)
    scene.collection.objects.link(box)
    return box


def add_light(scene, kind, location=(0, 0, 0), rotation=(0, 0, 0), energy=1.0, **extra):
    data = bpy.data.lights.new(kind.title(), kind)
    data.energy = energy
    for key, value in extra.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(data.name, data)
    obj.location = location
    obj.rotation_euler = rotation
    scene.collection.objects.link(obj)
    return obj


def look_camera(scene, pitch, yaw, lens=20.0):
    """A perspective camera at the origin turned by (pitch, 0, yaw) degrees (pitch 90: level), the
    scene's camera."""
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.lens = lens
    camera.rotation_euler = (math.radians(pitch), 0.0, math.radians(yaw))
    scene.collection.objects.link(camera)
    scene.camera = camera
    return camera


def render_beside_cycles(scene, name, samples):
    """{engine: RGB array} of SubSplat and Cycles (CPU, `samples`, no denoiser), each pixel at its
    centre (Filter Size 0.01, as SubSplat's one sample), written as <name>_<engine>.exr."""
    images = {}
    for engine in ("SUBSPLAT", "CYCLES"):
        scene.render.engine = engine
        scene.cycles.device, scene.cycles.samples, scene.cycles.use_denoising = "CPU", samples, False
        scene.render.filter_size = 0.01
        images[engine] = render(scene, f"{name}_{engine.lower()}")[..., :3]
    return images


def render(scene, name):
    """Renders with the scene's engine; linear RGBA float array (height, width, 4), bottom row first."""
    return render_to(scene, os.path.join(OUTPUT, name + ".exr"))


def render_to(scene, path):
    """render(), written to the EXR file `path`."""
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path, check_existing=False)
    pixels = np.empty(image.size[0] * image.size[1] * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    pixels = pixels.reshape(image.size[1], image.size[0], 4)
    bpy.data.images.remove(image)
    return pixels


def centre(pixels, fraction):
    h, w = pixels.shape[:2]
    y0, x0 = int(h * (1 - fraction) / 2), int(w * (1 - fraction) / 2)
    return pixels[y0:h - y0, x0:w - x0]


def fresnel_transmittance(eta, cos_theta):
    cos_theta = min(max(cos_theta, 0.0), 1.0)
    sin2 = (1 - cos_theta ** 2) / eta ** 2
    if sin2 >= 1:
        return 0.0
    cos_t = math.sqrt(1 - sin2)
    rs = (cos_theta - eta * cos_t) / (cos_theta + eta * cos_t)
    rp = (eta * cos_theta - cos_t) / (eta * cos_theta + cos_t)
    return 1 - 0.5 * (rs * rs + rp * rp)


def dipole_total_reflectance(sigma_a, sigma_s_prime, eta):
    """Rd_total of DESIGN.md (Jensen et al. 2001), computed here independently of the library."""
    albedo = sigma_s_prime / (sigma_a + sigma_s_prime)
    fdr = -1.440 / eta ** 2 + 0.710 / eta + 0.668 + 0.0636 * eta
    big_a = (1 + fdr) / (1 - fdr)
    root = math.sqrt(3 * (1 - albedo))
    return albedo / 2 * (1 + math.exp(-4 / 3 * big_a * root)) * math.exp(-root)


def read_exr(path):
    """An image file (the EXRs a `blender -a` run writes) as float32 RGBA, bottom row first."""
    image = bpy.data.images.load(path, check_existing=False)
    pixels = np.empty(image.size[0] * image.size[1] * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    shape = (image.size[1], image.size[0], 4)
    bpy.data.images.remove(image)
    return pixels.reshape(shape)


def _save_png(rgba, path):
    image = bpy.data.images.new(os.path.basename(path), rgba.shape[1], rgba.shape[0], float_buffer=False)
    image.pixels.foreach_set(np.ascontiguousarray(rgba, dtype=np.float32).ravel())
    image.filepath_raw = path
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)


def write_png(name, pixels):
    """A render (linear RGBA) as <name>.png in the output folder (Standard view: sRGB, clipped), to
    look at beside Cycles'."""
    rgb = np.clip(pixels[..., :3], 0.0, 1.0)
    srgb = np.where(rgb <= 0.0031308, rgb * 12.92, 1.055 * rgb ** (1 / 2.4) - 0.055)
    _save_png(np.concatenate([srgb, np.ones_like(srgb[..., :1])], axis=-1), os.path.join(OUTPUT, name + ".png"))


def write_difference(name, ours, reference):
    """A false-colour |ours - reference| / reference image a person can look at (PNG)."""
    diff = np.abs(ours[..., :3] - reference[..., :3]).mean(axis=-1) / max(float(np.abs(reference[..., :3]).mean()), 1e-12)
    t = np.clip(diff * 10.0, 0.0, 1.0)  # x10: 10 % difference is full red
    rgba = np.stack([t, 1 - np.abs(2 * t - 1), 1 - t, np.ones_like(t)], axis=-1)
    path = os.path.join(OUTPUT, name + "_difference.png")
    _save_png(rgba, path)
    return path


def blender_command(*args, one_sample=True):
    """Another Blender process with the add-on staged by the build; one_sample: scenes that do not
    set their samples render one (one_sample.py)."""
    from . import one_sample as pin
    executable = os.environ.get("BLENDER", bpy.app.binary_path)
    return [executable, "-b", "--factory-startup", "--addons", "subsplat",
            *(["--python-expr", pin.EXPRESSION] if one_sample else []), *args]


def run_blender(*args, timeout=600, env=None, one_sample=True):
    return subprocess.run(blender_command(*args, one_sample=one_sample), capture_output=True, text=True,
                          timeout=timeout, env=env)


def failed_batch_render(name):
    """Saves the current file as <name>.blend and renders frame 1 with `blender -b` as a farm would.
    Returns (exit status, output): 1 is a reported failure; a crash is a signal (negative) or
    128 + signal."""
    path = os.path.join(OUTPUT, f"{name}.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    result = run_blender(path, "-E", "SUBSPLAT", "-o", os.path.join(OUTPUT, f"{name}_"), "-f", "1")
    return result.returncode, result.stdout + result.stderr


def assert_batch_render_fails(test, name, *expected):
    """Renders the current file with `blender -b` (failed_batch_render) and checks it exits with
    status 1 (a reported failure, not a crash) and prints every expected text."""
    status, output = failed_batch_render(name)
    test.assertEqual(status, 1, output[-3000:])
    for text in expected:
        test.assertIn(text, output)


def one_of_two(image, first, second, tolerance=0.05):
    """Of the lit pixels of `image`, (the share within `tolerance` of `first` or of `second`, the share
    closer to `first`): how far an image is a patchwork of two others (lit: above 5 % of first's peak)."""
    lit = (image[..., 3] > 0) & (first[..., :3].max(axis=-1) > 0.05 * first[..., :3].max())

    def off(other):
        return np.abs(image - other)[..., :3].max(axis=-1)[lit] / np.maximum(other[..., :3].max(axis=-1)[lit], 1e-9)
    off_first, off_second = off(first), off(second)
    return float((np.minimum(off_first, off_second) < tolerance).mean()), float((off_first < off_second).mean())


def run_tests(test_case_module_name="__main__"):
    import time
    import unittest

    class Timed(unittest.TextTestResult):
        """Each test's wall time (with its class's setUpClass, counted in its first test), printed at
        the end: where CI's time goes (docs/CI.md)."""
        durations = []

        def startTest(self, test):
            self._started = time.perf_counter()
            super().startTest(test)

        def stopTest(self, test):
            super().stopTest(test)
            self.durations.append((time.perf_counter() - self._started, test.id().split(".", 1)[-1]))

    suite = unittest.defaultTestLoader.loadTestsFromModule(sys.modules[test_case_module_name])
    result = unittest.TextTestRunner(verbosity=2, resultclass=Timed).run(suite)
    print("durations: " + "; ".join(f"{name} {seconds:.1f} s" for seconds, name in sorted(Timed.durations, reverse=True)))
    passed = result.testsRun - len(result.failures) - len(result.errors)
    print(f"{passed} passed, {len(result.failures) + len(result.errors)} failed")
    if not result.wasSuccessful():
        sys.exit(1)
