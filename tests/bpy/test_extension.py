"""The extension package (Blender 4.2 and later; docs/VERSIONS.md, "The extension"): `cmake --build
build --target dist` writes build/extension/subsplat-<version>-linux-x64.zip; its manifest is valid
(the fields Blender requires, the add-on's own version, this platform), it holds the whole add-on and
its native library, and the newest pinned `bpy` module installs it as Get Extensions > Install from
Disk does (bpy.ops.extensions.package_install_files), enables it and renders with it.

Run in the module: build/bpy-<version>/bin/python tests/bpy/test_extension.py (CTest
bpy_extension_<version>, with BLENDER_USER_RESOURCES and BLENDER_USER_CONFIG in the test's own
output folder, so that nothing is installed for the user)."""
import glob
import os
import shutil
import subprocess
import sys
import tomllib
import unittest
import zipfile

BUILD = os.environ["SUBSPLAT_BUILD_DIR"]
SOURCE = os.environ["SUBSPLAT_SOURCE_DIR"]
RESOURCES = os.environ["BLENDER_USER_RESOURCES"]
# What an earlier run installed is removed before Blender starts (it reads its extensions then).
shutil.rmtree(os.path.join(RESOURCES, "extensions"), ignore_errors=True)

import bpy  # noqa: E402

REQUIRED = ("schema_version", "id", "version", "name", "tagline", "maintainer", "type",
            "blender_version_min", "license")


def package():
    subprocess.run(["cmake", "--build", BUILD, "--target", "dist"], check=True, capture_output=True)
    found = glob.glob(os.path.join(BUILD, "extension", "subsplat-*.zip"))
    assert len(found) == 1, found
    return found[0]


class Extension(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.path = package()
        with zipfile.ZipFile(cls.path) as z:
            cls.names = set(z.namelist())
            cls.manifest = tomllib.loads(z.read("blender_manifest.toml").decode())

    def test_manifest_is_valid_and_matches_the_add_on(self):
        m = self.manifest
        missing = [key for key in REQUIRED if key not in m]
        self.assertEqual(missing, [], "fields Blender requires")
        self.assertEqual(m["schema_version"], "1.0.0")
        self.assertEqual((m["id"], m["type"]), ("subsplat", "add-on"))
        self.assertLessEqual(len(m["tagline"]), 64, "Blender refuses a longer tagline")
        self.assertFalse(m["tagline"].endswith((".", "!", "?")), "Blender refuses a tagline ending in punctuation")
        self.assertEqual(m["platforms"], ["linux-x64"], "the native library inside is built for Linux x64")
        self.assertTrue(all(entry.startswith("SPDX:") for entry in m["license"]), m["license"])
        self.assertGreaterEqual(tuple(int(p) for p in m["blender_version_min"].split(".")), (4, 2, 0))
        with open(os.path.join(SOURCE, "addon", "subsplat", "__init__.py")) as f:
            text = f.read()
        version = text.split('"version": (', 1)[1].split(")", 1)[0]
        self.assertEqual(m["version"], ".".join(p.strip() for p in version.split(",")),
                         "the manifest's version is bl_info's")

    def test_package_holds_the_whole_add_on_at_its_root(self):
        sources = {os.path.relpath(p, os.path.join(SOURCE, "addon", "subsplat"))
                   for p in glob.glob(os.path.join(SOURCE, "addon", "subsplat", "**", "*.py"), recursive=True)}
        self.assertEqual(sources - self.names, set(), "every source file of the add-on")
        self.assertIn("libsubsplat.so", self.names)
        self.assertIn("blender_manifest.toml", self.names)
        self.assertFalse([n for n in self.names if "__pycache__" in n or n.endswith(".pyc")])

    def test_module_installs_enables_and_renders_with_it(self):
        result = bpy.ops.extensions.package_install_files(filepath=self.path, repo="user_default",
                                                          enable_on_install=True)
        self.assertEqual(result, {"FINISHED"})
        self.assertIn("bl_ext.user_default.subsplat", bpy.context.preferences.addons.keys())
        installed = os.path.join(RESOURCES, "extensions", "user_default", "subsplat")
        self.assertTrue(os.path.exists(os.path.join(installed, "libsubsplat.so")), installed)
        addon = sys.modules["bl_ext.user_default.subsplat"]
        addon.diagnostics.exit_on_error = False
        scene = bpy.context.scene
        scene.render.engine = "SUBSPLAT"
        scene.render.resolution_x, scene.render.resolution_y = 64, 48
        scene.render.resolution_percentage = 100
        material = bpy.data.objects["Cube"].active_material
        material.subsplat.enabled = True
        material.subsplat.preset = "SKIN1"
        material.subsplat.mm_per_unit = 50
        bpy.ops.render.render()
        self.assertIsNone(addon.last_render_error())
        stats = addon.last_render_stats()
        print(f"installed in {installed}; Blender {bpy.app.version_string}: "
              f"{stats['lit_translucent_pixels']} lit translucent pixels, {stats['frame_ms']:.0f} ms")
        self.assertGreater(stats["lit_translucent_pixels"], 0, stats)


if __name__ == "__main__":
    # As tests/bpy/test_versions.py: the module's exit status is Python's, given before the C
    # library's own exit (4.2.23 crashes there; docs/VERSIONS.md).
    status = 1
    try:
        program = unittest.main(exit=False, verbosity=2)
        status = 0 if program.result.wasSuccessful() else 1
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)
