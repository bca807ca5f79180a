"""The artist model (source 'ARTIST'): a translucency image shaped like a dipole's profile, with the
dipole's albedo and its range as the radius, renders the dipole's image; an albedo image varies it
per texel; missing or unusable settings fail `blender -b` with a message."""
import unittest

import bpy
import numpy as np

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat_testing import materials  # noqa: E402

SKIN_A, SKIN_S = (0.032, 0.17, 0.48), (0.74, 0.88, 1.01)
ETA = 1.3
MM_PER_UNIT = 100.0
KNOTS = 513


def dipole_profile(sigma_a, sigma_s_prime, eta, r):
    """R_d(r) of Jensen et al. 2001 per channel, r in mm, computed here independently of the library."""
    sigma_a, sigma_s_prime = np.asarray(sigma_a, float), np.asarray(sigma_s_prime, float)
    sigma_t = sigma_a + sigma_s_prime
    albedo = sigma_s_prime / sigma_t
    sigma_tr = np.sqrt(3 * sigma_a * sigma_t)
    fdr = -1.440 / eta ** 2 + 0.710 / eta + 0.668 + 0.0636 * eta
    zr = 1 / sigma_t
    zv = zr * (1 + 4 / 3 * (1 + fdr) / (1 - fdr))
    r = np.asarray(r, float)[:, None]
    dr, dv = np.sqrt(r ** 2 + zr ** 2), np.sqrt(r ** 2 + zv ** 2)
    return albedo / (4 * np.pi) * (zr * (sigma_tr + 1 / dr) * np.exp(-sigma_tr * dr) / dr ** 2 +
                                   zv * (sigma_tr + 1 / dv) * np.exp(-sigma_tr * dv) / dv ** 2)


def artist_skin(name):
    """Skin1 in the artist model: T = its R_d shape over [0, R] (R: 40 mm, past 99.9 % of its energy)
    and albedo = its Rd_total."""
    radius_mm = 40.0
    curve = dipole_profile(SKIN_A, SKIN_S, ETA, np.linspace(0.0, radius_mm, KNOTS))
    curve /= curve.max()
    image = bpy.data.images.new(f"{name}Translucency", KNOTS, 1, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(np.concatenate([curve, np.ones((KNOTS, 1))], axis=1).astype(np.float32).ravel())
    material = materials.translucent(name, mm_per_unit=MM_PER_UNIT)
    settings = material.subsplat
    settings.source = "ARTIST"
    settings.artist_radius = radius_mm / MM_PER_UNIT
    settings.translucency_image = image
    settings.albedo_color = tuple(subsplat.principled.albedo_and_path(SKIN_A, SKIN_S, ETA)[0])
    return material


class Artist(unittest.TestCase):
    def test_a_dipole_shaped_translucency_renders_the_dipole(self):
        scene, _, material = materials.sphere_scene(lambda: artist_skin("ArtistSkin"))
        artist_image = helpers.render(scene, "artist_skin")
        material.subsplat.source = "DIPOLE"
        material.subsplat.preset = "SKIN1"
        dipole = helpers.render(scene, "artist_dipole")
        difference = materials.relative_difference(dipole, artist_image)
        print(f"DIPOLE against the artist model: relative difference {difference:.5f}")
        if difference >= 0.01:
            helpers.write_difference("artist_skin", artist_image, dipole)
        self.assertLess(difference, 0.01)

    def test_an_albedo_image_varies_it_per_texel(self):
        scene, _, material = materials.sphere_scene(lambda: artist_skin("ArtistHalves"))
        image = bpy.data.images.new("AlbedoHalves", 2, 1, float_buffer=True)
        image.colorspace_settings.name = "Non-Color"
        image.pixels.foreach_set(np.array([0.1, 0.05, 0.05, 1.0, 0.9, 0.8, 0.7, 1.0], dtype=np.float32))
        material.subsplat.albedo_image = image
        info = subsplat.export.materials.source_profiles(material).info()
        self.assertEqual((info["profiles"], info["width"], info["height"]), (2, 2, 1))
        halves = helpers.render(scene, "artist_halves")
        material.subsplat.albedo_image = None
        material.subsplat.albedo_color = (0.1, 0.05, 0.05)
        dark = helpers.render(scene, "artist_dark")
        material.subsplat.albedo_color = (0.9, 0.8, 0.7)
        light = helpers.render(scene, "artist_light")
        share, light_share = helpers.one_of_two(halves, light, dark)
        dark_share = 1.0 - light_share
        print(f"albedo halves: {share:.3f} of lit pixels within 5 % of all dark or all light; {dark_share:.3f} dark")
        self.assertGreater(share, 0.6)
        self.assertTrue(0.1 < dark_share < 0.9, dark_share)

    def test_unusable_settings_fail_with_a_message(self):
        def black(material):
            material.subsplat.translucency_image.pixels.foreach_set(
                np.tile([0.0, 0.0, 0.0, 1.0], KNOTS).astype(np.float32))
        cases = [("no image", lambda m: setattr(m.subsplat, "translucency_image", None), "needs a translucency image"),
                 ("radius", lambda m: setattr(m.subsplat, "artist_radius", 0.0), "must be positive"),
                 ("black", black, "is black in channel R")]
        for name, spoil, expected in cases:
            with self.subTest(case=name):
                _, _, material = materials.sphere_scene(lambda: artist_skin("Spoilt"), size=16)
                spoil(material)
                material.subsplat.translucency_image and material.subsplat.translucency_image.pack()
                helpers.assert_batch_render_fails(self, f"artist_bad_{name.replace(' ', '_')}", expected,
                                                  "material 'Spoilt'")


if __name__ == "__main__":
    helpers.run_tests()
