"""Translucency from a Principled BSDF (source 'PRINCIPLED'): a constant colour and radius that
describe a dipole render that dipole's image, as does its baked SubEdit file; image textures
connected to the colour vary the profile per texel; unread links warn; out-of-range inputs fail
`blender -b` with a message."""
import math
import os
import unittest

import bpy
import numpy as np

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat_testing import materials  # noqa: E402

principled = subsplat.principled
SKIN_A, SKIN_S = (0.032, 0.17, 0.48), (0.74, 0.88, 1.01)
MM_PER_UNIT = 100.0


def principled_translucent(name, colour, radius, profile_model="DIPOLE"):
    material = materials.translucent(name, mm_per_unit=MM_PER_UNIT, profile_model=profile_model)
    material.use_nodes = True
    material.subsplat.source = "PRINCIPLED"
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs[principled.COLOR_INPUT].default_value = (*colour, 1.0)
    bsdf.inputs[principled.RADIUS_INPUT].default_value = radius
    bsdf.inputs[principled.SCALE_INPUT].default_value = 1.0
    return material


def skin_as_principled(name, profile_model="DIPOLE"):
    """Skin1 as a Principled BSDF: its albedo (the model's total reflectance) and mean free path (in
    scene units)."""
    albedo, path_mm = principled.albedo_and_path(SKIN_A, SKIN_S, subsplat.presets.MEASURED_ETA, profile_model)
    return principled_translucent(name, tuple(albedo), tuple(path_mm / MM_PER_UNIT), profile_model)


class Principled(unittest.TestCase):
    def test_conversion_inverts_the_dipole(self):
        albedo, path = principled.albedo_and_path(SKIN_A, SKIN_S, 1.3)
        sigma_a, sigma_s = principled.coefficients(albedo, path, 1.3)
        np.testing.assert_allclose(sigma_a, SKIN_A, rtol=1e-4)
        np.testing.assert_allclose(sigma_s, SKIN_S, rtol=1e-4)

    def test_conversion_inverts_the_tabulated_total(self):
        albedo, path = principled.albedo_and_path(SKIN_A, SKIN_S, 1.3, "TABULATED")
        sigma_a, sigma_s = principled.coefficients(albedo, path, 1.3, "TABULATED")
        np.testing.assert_allclose(sigma_a, SKIN_A, rtol=1e-4)
        np.testing.assert_allclose(sigma_s, SKIN_S, rtol=1e-4)
        # The same colour is another medium under the dipole: its total is not the half-space's.
        dipole_albedo, _ = principled.albedo_and_path(SKIN_A, SKIN_S, 1.3, "DIPOLE")
        self.assertGreater(float(np.abs(albedo / dipole_albedo - 1).max()), 0.02)

    def test_tabulated_principled_renders_its_medium(self):
        """Under the TABULATED model (the default) an untextured Principled BSDF is one medium: it
        renders the image of the coefficients it stands for, angular and thin-part factors included."""
        scene, _, material = materials.sphere_scene(lambda: skin_as_principled("SkinBSDF", "TABULATED"))
        material.subsplat.source = "DIPOLE"
        material.subsplat.preset = "SKIN1"
        medium = helpers.render(scene, "principled_tabulated_medium")
        material.subsplat.source = "PRINCIPLED"
        from_bsdf = helpers.render(scene, "principled_tabulated_bsdf")
        difference = materials.relative_difference(medium, from_bsdf)
        print(f"TABULATED medium against its Principled BSDF: relative difference {difference:.5f}")
        if difference >= 0.01:
            helpers.write_difference("principled_tabulated_bsdf", from_bsdf, medium)
        self.assertLess(difference, 0.01)

    def test_a_textured_bsdf_under_tabulated_says_what_it_leaves_out(self):
        """A texture makes the medium vary per texel: under TABULATED it gets the radial profiles of
        its texels' media, not the angular and thin-part factors of one medium, and says so."""
        for model in ("TABULATED", "DIPOLE"):
            bpy.ops.wm.read_homefile(use_empty=True)
            material = skin_as_principled("Textured", model)
            image = bpy.data.images.new("Halves", 2, 1, float_buffer=True)
            image.colorspace_settings.name = "Non-Color"
            image.pixels.foreach_set(np.array([0.05, 0.02, 0.01, 1.0, 0.8, 0.6, 0.5, 1.0], dtype=np.float32))
            texture = material.node_tree.nodes.new("ShaderNodeTexImage")
            texture.image = image
            material.node_tree.links.new(texture.outputs["Color"],
                                         material.node_tree.nodes["Principled BSDF"].inputs[principled.COLOR_INPUT])
            warnings = []
            described = subsplat.export.materials.material_data(material, warnings)
            self.assertEqual(described.kind, "SUBEDIT", model)
            said = [w for w in warnings if "angular and thin-part factors" in w]
            self.assertEqual(len(said), 1 if model == "TABULATED" else 0, (model, warnings))

    def test_dipole_principled_and_baked_file_render_the_same_image(self):
        scene, _, material = materials.sphere_scene(lambda: skin_as_principled("SkinBSDF"))
        material.subsplat.source = "DIPOLE"
        material.subsplat.preset = "SKIN1"
        dipole = helpers.render(scene, "principled_dipole")
        material.subsplat.source = "PRINCIPLED"
        from_bsdf = helpers.render(scene, "principled_bsdf")
        path = materials.bake(material, os.path.join(helpers.OUTPUT, "principled_skin.exr"))
        material.subsplat.source = "SUBEDIT_FILE"
        material.subsplat.subedit_path = path
        from_file = helpers.render(scene, "principled_file")
        for name, image in (("Principled BSDF", from_bsdf), ("baked file", from_file)):
            difference = materials.relative_difference(dipole, image)
            print(f"DIPOLE against {name}: relative difference {difference:.5f}")
            if difference >= 0.01:
                helpers.write_difference(f"principled_{name.replace(' ', '_')}", image, dipole)
            self.assertLess(difference, 0.01, name)

    def test_an_image_on_the_colour_varies_the_profile_per_texel(self):
        scene, obj, material = materials.sphere_scene(lambda: skin_as_principled("Textured"))
        image = bpy.data.images.new("Halves", 2, 1, float_buffer=True)
        image.colorspace_settings.name = "Non-Color"
        dark, light = (0.05, 0.02, 0.01), (0.8, 0.6, 0.5)
        image.pixels.foreach_set(np.array([*dark, 1.0, *light, 1.0], dtype=np.float32))
        nodes, links = material.node_tree.nodes, material.node_tree.links
        texture = nodes.new("ShaderNodeTexImage")
        texture.image = image
        texture.interpolation = "Closest"
        links.new(texture.outputs["Color"], nodes["Principled BSDF"].inputs[principled.COLOR_INPUT])
        info = subsplat.export.materials.source_profiles(material).info()
        self.assertEqual((info["profiles"], info["width"], info["height"]), (2, 2, 1))
        halves = helpers.render(scene, "principled_halves")
        # Against the sphere all dark and all light: each lit pixel shows one of the two (but near
        # the seam between them), and each covers a good share.
        material.node_tree.links.remove(texture.outputs["Color"].links[0])
        bsdf = nodes["Principled BSDF"]
        bsdf.inputs[principled.COLOR_INPUT].default_value = (*dark, 1.0)
        all_dark = helpers.render(scene, "principled_all_dark")
        bsdf.inputs[principled.COLOR_INPUT].default_value = (*light, 1.0)
        all_light = helpers.render(scene, "principled_all_light")
        share, light_share = helpers.one_of_two(halves, all_light, all_dark)
        dark_share = 1.0 - light_share
        print(f"halves: {share:.3f} of lit pixels within 5 % of the dark or the light material; {dark_share:.3f} dark")
        self.assertGreater(share, 0.6)
        self.assertTrue(0.1 < dark_share < 0.9, dark_share)  # both halves are seen

    def test_an_unread_link_warns_and_renders(self):
        scene, _, material = materials.sphere_scene(lambda: skin_as_principled("Linked"), size=24)
        nodes = material.node_tree.nodes
        rgb = nodes.new("ShaderNodeRGB")
        material.node_tree.links.new(rgb.outputs[0], nodes["Principled BSDF"].inputs[principled.COLOR_INPUT])
        path = os.path.join(helpers.OUTPUT, "principled_linked.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        result = helpers.run_blender(path, "-o", os.path.join(helpers.OUTPUT, "principled_linked_"), "-f", "1")
        output = result.stdout + result.stderr
        self.assertEqual(result.returncode, 0, output[-3000:])
        self.assertIn("which SubSplat does not read", output)

    def test_out_of_range_inputs_fail_with_a_message(self):
        cases = [("colour", lambda m: m.node_tree.nodes["Principled BSDF"].inputs[principled.COLOR_INPUT]
                  .__setattr__("default_value", (1.5, 0.5, 0.5, 1.0)), "must be in [0, 1]"),
                 ("radius", lambda m: m.node_tree.nodes["Principled BSDF"].inputs[principled.RADIUS_INPUT]
                  .__setattr__("default_value", (0.0, 0.1, 0.1)), "must be positive"),
                 ("no node", lambda m: m.node_tree.nodes.remove(m.node_tree.nodes["Principled BSDF"]),
                  "needs a Principled BSDF node")]
        for name, spoil, expected in cases:
            with self.subTest(case=name):
                _, _, material = materials.sphere_scene(lambda: skin_as_principled("Spoilt"), size=16)
                spoil(material)
                helpers.assert_batch_render_fails(self, f"principled_bad_{name.replace(' ', '_')}", expected,
                                                  "material 'Spoilt'")


if __name__ == "__main__":
    helpers.run_tests()
