"""Tests render one sample per pixel unless they set `samples` (or `viewport_samples`) themselves:
the pixel comparisons, golden images and CI's time were made for one sample, and anti-aliasing has
tests of its own (tests/blender/test_antialiasing.py, docs/ANTIALIASING.md). A scene whose property
is unset (Blender's default, 8) is pinned when a file loads and before each render; a test that
sets it keeps its value."""
import bpy

# The same, for another Blender process (helpers.blender_command puts it before the file is read).
EXPRESSION = (
    "import bpy\n"
    "@bpy.app.handlers.persistent\n"
    "def subsplat_one_sample(*_):\n"
    "    for scene in bpy.data.scenes:\n"
    "        for name in ('samples', 'viewport_samples'):\n"
    "            if hasattr(scene, 'subsplat') and not scene.subsplat.is_property_set(name):\n"
    "                setattr(scene.subsplat, name, 1)\n"
    "bpy.app.handlers.load_post.append(subsplat_one_sample)\n"
    "bpy.app.handlers.render_pre.append(subsplat_one_sample)\n"
    "subsplat_one_sample()\n")


def pin():
    """Installs the pin in this Blender process (once)."""
    if any(getattr(h, "__name__", "") == "subsplat_one_sample" for h in bpy.app.handlers.load_post):
        return
    exec(compile(EXPRESSION, "one_sample", "exec"), {"bpy": bpy})
