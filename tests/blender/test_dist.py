"""The installable zip: `cmake --build build --target dist`, then Blender's own add-on installer
(Edit > Preferences > Add-ons > Install) into an empty user folder, enable, and render."""
import glob
import os
import subprocess
import sys
import tempfile
import unittest

from subsplat_testing import helpers

INSTALL_AND_RENDER = """
import bpy, glob, os, sys
zip_path = sys.argv[sys.argv.index('--') + 1]
bpy.ops.preferences.addon_install(filepath=zip_path)
bpy.ops.preferences.addon_enable(module='subsplat')
import subsplat
scene = bpy.context.scene
scene.render.engine = 'SUBSPLAT'
scene.render.resolution_x, scene.render.resolution_y = 64, 48
material = bpy.data.objects['Cube'].active_material
material.subsplat.enabled = True
material.subsplat.preset = 'SKIN1'
material.subsplat.mm_per_unit = 50
bpy.ops.render.render()
stats = subsplat.last_render_stats()
assert stats['lit_translucent_pixels'] > 0, stats
print('INSTALLED_FROM', os.path.dirname(subsplat.__file__))
"""


class DistZipInstalls(unittest.TestCase):
    def test_zip_installs_and_renders(self):
        build = os.environ["SUBSPLAT_BUILD_DIR"]
        subprocess.run(["cmake", "--build", build, "--target", "dist"], check=True, capture_output=True)
        zips = glob.glob(os.path.join(build, "subsplat-*.zip"))
        self.assertEqual(len(zips), 1, zips)
        with tempfile.TemporaryDirectory() as user_scripts:
            env = dict(os.environ, BLENDER_USER_SCRIPTS=user_scripts)
            script = os.path.join(user_scripts, "install_and_render.py")
            with open(script, "w") as f:
                f.write(INSTALL_AND_RENDER)
            result = subprocess.run([os.environ.get("BLENDER", "blender"), "-b", "--factory-startup",
                                     "--python-exit-code", "1", "--python", script, "--", zips[0]],
                                    env=env, capture_output=True, text=True, timeout=600)
            self.assertEqual(result.returncode, 0, result.stdout[-3000:] + result.stderr[-3000:])
            self.assertIn("INSTALLED_FROM " + os.path.join(user_scripts, "addons", "subsplat"), result.stdout)


if __name__ == "__main__":
    helpers.run_tests()
