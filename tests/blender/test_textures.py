"""Image textures (docs/TEXTURES.md): an Image Texture into an opaque Principled BSDF's Base Color,
through UVs and Mapping nodes, renders as Cycles renders it; into a translucent material's Base Color
it tints the light where it enters and leaves; a Normal Map of an image tilts the shading normal;
set-ups SubSplat does not read are named in warnings. Small renders (64 x 64, Cycles 64 samples, no
bounces), all in one run; every render is also written as a PNG beside its EXR to look at."""
import math
import os
import time
import unittest

import bpy
import numpy as np

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat import export  # noqa: E402
from subsplat.export import materials, textures  # noqa: E402

SIZE = 64          # pixels; the plane fills the frame: 16 pixels a unit
PLANE = 4.0        # units, = the camera's ortho scale
SUN = 2.0          # W/m^2, straight down: radiance = albedo x SUN / pi on a Lambertian plane
A, B = (0.8, 0.3, 0.1), (0.2, 0.5, 0.7)  # the checker's two linear colours


def linear_to_srgb(values):
    values = np.asarray(values, dtype=np.float64)
    return np.where(values <= 0.0031308, values * 12.92, 1.055 * values ** (1 / 2.4) - 0.055)


def render(scene, name, engine="SUBSPLAT"):
    scene.render.engine = engine
    if engine == "CYCLES":
        scene.cycles.device, scene.cycles.samples, scene.cycles.use_denoising = "CPU", 64, False
        scene.cycles.max_bounces, scene.cycles.seed = 0, 1
        scene.cycles.filter_width = 0.01  # each pixel seen at its centre, as SubSplat's one sample sees it
    pixels = helpers.render(scene, name)
    helpers.write_png(name, pixels)
    if engine == "SUBSPLAT":
        assert subsplat.last_render_error() is None, subsplat.last_render_error()
    return pixels


def checker_image(name, cells, first, second, float_buffer=False, texels_per_cell=1):
    """A cells x cells checker of two linear colours; a byte image stores them sRGB-encoded (as a
    painted or loaded 8-bit image does), a float image as they are."""
    side = cells * texels_per_cell
    index = (np.arange(side) // texels_per_cell)
    pattern = ((index[:, None] + index[None, :]) % 2 == 0)
    rgb = np.where(pattern[..., None], np.array(first), np.array(second))
    if not float_buffer:
        rgb = np.round(linear_to_srgb(rgb) * 255.0) / 255.0
    image = bpy.data.images.new(name, side, side, float_buffer=float_buffer)
    image.pixels.foreach_set(np.concatenate([rgb, np.ones((side, side, 1))], axis=-1).astype(np.float32).ravel())
    return image


def stored_linear(colour):
    """What a byte sRGB image holds of a linear colour, back in linear (its 1/255 steps)."""
    stored = np.round(linear_to_srgb(colour) * 255.0) / 255.0
    return subsplat.principled.srgb_to_linear(stored)


def uv_plane(scene, material, name="Plane", layers=("UVMap",)):
    """The PLANE-wide plane at z = 0 with UV maps: the first (u, v) = (x, y) / PLANE + 0.5, each other
    one that flipped in u."""
    obj = helpers.plane(scene, PLANE, material)
    obj.name = name
    mesh = obj.data
    corners = np.array([mesh.vertices[loop.vertex_index].co[:2] for loop in mesh.loops]) / PLANE + 0.5
    for i, layer_name in enumerate(layers):
        layer = mesh.uv_layers.new(name=layer_name)
        uvs = corners if i == 0 else np.stack([1.0 - corners[:, 0], corners[:, 1]], axis=1)
        layer.data.foreach_set("uv", uvs.astype(np.float32).ravel())
    return obj


def lit_scene():
    """A new file (bpy.data emptied: make materials after it): the camera above, a sun straight down."""
    scene = helpers.empty_scene(SIZE, SIZE)
    helpers.top_down_camera(scene, ortho_scale=PLANE)
    helpers.add_light(scene, "SUN", energy=SUN, angle=0.0)
    return scene


def lambertian(name):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs[subsplat.version.PRINCIPLED_SPECULAR].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 1.0
    return material


def texture_into(material, image, socket="Base Color", interpolation="Closest", extension="REPEAT"):
    tree = material.node_tree
    node = tree.nodes.new("ShaderNodeTexImage")
    node.image, node.interpolation, node.extension = image, interpolation, extension
    tree.links.new(node.outputs["Color"], tree.nodes["Principled BSDF"].inputs[socket])
    return node


def mapping_before(material, texture, vector_type="POINT", location=(0, 0, 0), rotation=(0, 0, 0),
                   scale=(1, 1, 1), uv_map=None):
    """A Mapping node into the texture's Vector, fed by a UV Map node (uv_map) or a Texture
    Coordinate node's UV (None)."""
    tree = material.node_tree
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.vector_type = vector_type
    for name, value in (("Location", location), ("Rotation", rotation), ("Scale", scale)):
        mapping.inputs[name].default_value = value
    if uv_map is None:
        source = tree.nodes.new("ShaderNodeTexCoord").outputs["UV"]
    else:
        node = tree.nodes.new("ShaderNodeUVMap")
        node.uv_map = uv_map
        source = node.outputs["UV"]
    tree.links.new(source, mapping.inputs["Vector"])
    tree.links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    return mapping


def cell_masks(cells):
    """Boolean (SIZE, SIZE) masks of the pixels inside the checker's first and second colour's cells
    (the plane's UVs: cell (i, j) covers SIZE / cells pixels a side), one pixel in from each edge."""
    per = SIZE // cells
    index = np.arange(SIZE) // per
    inside = (np.arange(SIZE) % per > 0) & (np.arange(SIZE) % per < per - 1)
    first = ((index[:, None] + index[None, :]) % 2 == 0)
    interior = inside[:, None] & inside[None, :]
    return first & interior, ~first & interior


def close_share(ours, reference, tolerance=0.05):
    """The share of pixels whose rgb is within tolerance (relative to the reference's brightest) of it."""
    scale = max(float(reference[..., :3].max()), 1e-9)
    return float((np.abs(ours[..., :3] - reference[..., :3]).max(axis=-1) / scale < tolerance).mean())


class OpaqueTexture(unittest.TestCase):
    def test_a_checker_renders_as_in_cycles_and_shows_its_pattern(self):
        """An 8 x 8 checker, byte sRGB, into Base Color of a Lambertian plane under a sun: the mean
        radiance per channel within 3 % of Cycles', and the cells of each colour at the colour's
        albedo x E / pi: their ratio is the texture's within 2 %."""
        scene = lit_scene()
        material = lambertian("Checker")
        texture_into(material, checker_image("Checker8", 8, A, B))
        uv_plane(scene, material)
        ours = render(scene, "textures_checker_subsplat")
        cycles = render(scene, "textures_checker_cycles", "CYCLES")
        ours_mean = ours[..., :3].reshape(-1, 3).mean(axis=0)
        cycles_mean = cycles[..., :3].reshape(-1, 3).mean(axis=0)
        ratio = ours_mean / cycles_mean
        print(f"checker: subsplat {np.round(ours_mean, 5)} cycles {np.round(cycles_mean, 5)} "
              f"ratio {np.round(ratio, 4)}")
        if np.any(np.abs(ratio - 1) > 0.03):
            helpers.write_difference("textures_checker", ours, cycles)
        for c in range(3):
            self.assertAlmostEqual(ratio[c], 1.0, delta=0.03, msg=f"channel {'RGB'[c]}: SubSplat/Cycles {ratio}")
        first, second = cell_masks(8)
        a, b = stored_linear(A), stored_linear(B)
        mean_a, mean_b = ours[first, :3].mean(axis=0), ours[second, :3].mean(axis=0)
        print(f"checker cells: first {np.round(mean_a, 5)} (expected {np.round(a * SUN / math.pi, 5)}), "
              f"second {np.round(mean_b, 5)} (expected {np.round(b * SUN / math.pi, 5)})")
        for c in range(3):
            self.assertAlmostEqual((mean_a[c] / mean_b[c]) / (a[c] / b[c]), 1.0, delta=0.02, msg=f"channel {'RGB'[c]}")
            self.assertAlmostEqual(mean_a[c] / (a[c] * SUN / math.pi), 1.0, delta=0.03, msg=f"channel {'RGB'[c]}")


class Mapping(unittest.TestCase):
    def test_a_scale_of_two_repeats_the_pattern_twice(self):
        """Mapping Point with scale 2 (through a Texture Coordinate's UV) and Mapping Texture with
        scale 1/2 (through a UV Map node) on an 8 x 8 checker render the 16 x 16 checker's image."""
        renders = {}
        for case in ("reference", "point", "texture"):
            scene = lit_scene()
            material = lambertian(f"Mapped {case}")
            image = checker_image(f"Checker {case}", 16 if case == "reference" else 8, A, B)
            texture = texture_into(material, image)
            if case == "point":
                mapping_before(material, texture, "POINT", scale=(2, 2, 1))
            elif case == "texture":
                mapping_before(material, texture, "TEXTURE", scale=(0.5, 0.5, 1), uv_map="UVMap")
            uv_plane(scene, material)
            renders[case] = render(scene, f"textures_mapping_{case}")
        for case in ("point", "texture"):
            share = close_share(renders[case], renders["reference"], 0.01)
            print(f"mapping {case}: {share:.4f} of pixels within 1 % of the 16 x 16 checker's")
            self.assertGreater(share, 0.98, case)

    def test_rotated_scaled_and_moved_uvs_render_as_in_cycles(self):
        """A 4 x 4 texture of 16 colours through Mapping nodes that rotate (about z), scale unevenly
        and move, of type Point and Texture, with each extension and interpolation: the pixels as Cycles' (Cycles' pixel
        filter narrowed to the pixel's centre: 95 % of them within 5 %, the mean difference within 2 %)."""
        rng = np.random.default_rng(7)
        colours = rng.uniform(0.05, 0.9, size=(4, 4, 3))
        for vector_type, extension, interpolation in (("POINT", "REPEAT", "Closest"), ("TEXTURE", "CLIP", "Closest"),
                                                      ("POINT", "EXTEND", "Closest"), ("TEXTURE", "REPEAT", "Linear")):
            with self.subTest(vector_type=vector_type, extension=extension, interpolation=interpolation):
                scene = lit_scene()
                material = lambertian(f"{vector_type} {extension}")
                image = bpy.data.images.new("Sixteen", 4, 4, float_buffer=True)
                image.pixels.foreach_set(np.concatenate([colours, np.ones((4, 4, 1))], axis=-1)
                                         .astype(np.float32).ravel())
                texture = texture_into(material, image, interpolation=interpolation, extension=extension)
                if vector_type == "POINT":
                    mapping_before(material, texture, "POINT", location=(0.1, -0.2, 0),
                                   rotation=(0, 0, math.radians(30)), scale=(1.6, 0.7, 1))
                else:
                    mapping_before(material, texture, "TEXTURE", location=(-0.15, 0.1, 0),
                                   rotation=(0, 0, math.radians(-20)), scale=(0.8, 1.3, 1))
                uv_plane(scene, material)
                name = f"textures_transform_{vector_type.lower()}_{extension.lower()}_{interpolation.lower()}"
                ours = render(scene, name + "_subsplat")
                cycles = render(scene, name + "_cycles", "CYCLES")
                share = close_share(ours, cycles, 0.05)
                mean = float(np.abs(ours[..., :3] - cycles[..., :3]).mean() / cycles[..., :3].mean())
                print(f"transform {vector_type} {extension} {interpolation}: {share:.3f} of pixels within 5 % "
                      f"of Cycles', mean difference {mean:.4f}")
                if share < 0.95 or mean > 0.02:
                    helpers.write_difference(name, ours, cycles)
                self.assertGreater(share, 0.95)
                self.assertLess(mean, 0.02)


class TranslucentTint(unittest.TestCase):
    TINT = (1.0, 0.3, 0.3)

    def translucent(self, name):
        material = bpy.data.materials.new(name)
        material.use_nodes = True
        material.subsplat.enabled = True
        material.subsplat.preset = "SKIN1"
        material.subsplat.source = "DIPOLE"
        material.subsplat.profile_model = "DIPOLE"
        material.subsplat.mm_per_unit = 100.0
        material.subsplat.specular = 0.0
        return material

    def render_tinted(self, name, tint=None):
        scene = lit_scene()
        material = self.translucent(name)
        if tint is not None:
            texture_into(material, checker_image(name, 2, tint, (1, 1, 1), float_buffer=True))
        uv_plane(scene, material)
        scene.subsplat.irradiance_resolution = 256
        return render(scene, f"textures_tint_{name}")

    def test_a_tint_scales_the_light_and_white_changes_nothing(self):
        """Skin under a sun through a 2 x 2 checker tint of red (1, 0.3, 0.3) and white: in the
        middle of the cells (0.5 units from their edges), the tinted render over the untinted one
        is the tint, per channel, within 4 %; a white image leaves the render within 1 %."""
        plain = self.render_tinted("plain", None)
        white = self.render_tinted("white", (1, 1, 1))
        tinted = self.render_tinted("checker", self.TINT)
        white_change = float(np.abs(white[..., :3] - plain[..., :3]).mean() / plain[..., :3].mean())
        print(f"tint: white texture changes the render by {white_change:.5f}")
        self.assertLess(white_change, 0.01)
        # Cell (0, 0) (bottom left) is the tint, (0, 1) white; their middle quarter of a unit each side.
        middle = slice(SIZE // 4 - 4, SIZE // 4 + 4)
        other = slice(3 * SIZE // 4 - 4, 3 * SIZE // 4 + 4)
        def ratio(rows, columns):
            return tinted[rows, columns, :3].reshape(-1, 3).mean(axis=0) / plain[rows, columns, :3].reshape(-1, 3).mean(axis=0)
        red, clear = ratio(middle, middle), ratio(middle, other)
        print(f"tint: red cell / untinted {np.round(red, 4)} (tint {self.TINT}), white cell {np.round(clear, 4)}")
        for c in range(3):
            self.assertAlmostEqual(red[c] / self.TINT[c], 1.0, delta=0.04, msg=f"red cell, channel {'RGB'[c]}")
            self.assertAlmostEqual(clear[c], 1.0, delta=0.04, msg=f"white cell, channel {'RGB'[c]}")


class NormalMap(unittest.TestCase):
    def test_a_tilted_normal_dims_the_plane_by_the_cosine(self):
        """A Normal Map (Tangent Space, Strength 1) of a constant Non-Color image tilting the normal
        by 35 degrees along the UVs' u: under a sun at normal incidence, the radiance is cos(35 deg)
        times the flat plane's, within 3 % (Cycles printed)."""
        angle = math.radians(35)
        colour = (0.5 + 0.5 * math.sin(angle), 0.5, 0.5 + 0.5 * math.cos(angle))
        scene = lit_scene()
        flat_material = lambertian("Flat")
        flat_material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.5, 0.5, 0.5, 1)
        uv_plane(scene, flat_material)
        flat = render(scene, "textures_normal_flat")
        scene = lit_scene()
        material = lambertian("Tilted")
        tree = material.node_tree
        tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.5, 0.5, 0.5, 1)
        image = bpy.data.images.new("Tilt", 4, 4)
        image.colorspace_settings.name = "Non-Color"
        image.pixels.foreach_set(np.tile([*colour, 1.0], 16).astype(np.float32))
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = image
        normal = tree.nodes.new("ShaderNodeNormalMap")
        tree.links.new(texture.outputs["Color"], normal.inputs["Color"])
        tree.links.new(normal.outputs["Normal"], tree.nodes["Principled BSDF"].inputs["Normal"])
        uv_plane(scene, material)
        tilted = render(scene, "textures_normal_tilted")
        cycles = render(scene, "textures_normal_tilted_cycles", "CYCLES")
        # The byte image holds the colour in 1/255 steps: the cosine of the normal it stores.
        stored = np.round(np.array(colour) * 255.0) / 255.0 * 2.0 - 1.0
        expected = stored[2] / np.linalg.norm(stored)
        ratio = helpers.centre(tilted, 0.8)[..., :3].mean() / helpers.centre(flat, 0.8)[..., :3].mean()
        cycles_ratio = helpers.centre(cycles, 0.8)[..., :3].mean() / helpers.centre(flat, 0.8)[..., :3].mean()
        print(f"normal map: tilted / flat {ratio:.4f}, cos {expected:.4f}; Cycles' tilted / SubSplat's flat "
              f"{cycles_ratio:.4f}")
        self.assertAlmostEqual(ratio / expected, 1.0, delta=0.03)


class Warnings(unittest.TestCase):
    def describe(self, material):
        warnings = []
        data = materials.material_data(material, warnings)
        return data, warnings

    def test_set_ups_that_are_not_read_are_named(self):
        """A Noise Texture into Base Color and a Normal Map in Object Space: the one-line warning each,
        and nothing read; an Image Texture through a Mapping that rotates about x: read, and warned."""
        helpers.empty_scene(8, 8)
        material = lambertian("Noisy")
        tree = material.node_tree
        noise = tree.nodes.new("ShaderNodeTexNoise")
        tree.links.new(noise.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
        normal = tree.nodes.new("ShaderNodeNormalMap")
        normal.space = "OBJECT"
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = checker_image("Bumps", 2, (0.5, 0.5, 1.0), (0.5, 0.5, 1.0))
        tree.links.new(texture.outputs["Color"], normal.inputs["Color"])
        tree.links.new(normal.outputs["Normal"], tree.nodes["Principled BSDF"].inputs["Normal"])
        data, warnings = self.describe(material)
        print("\n".join(warnings))
        self.assertIsNone(data.color_texture)
        self.assertIsNone(data.normal_texture)
        self.assertTrue(any("material 'Noisy': Base Color is connected to a Noise Texture node, which SubSplat does "
                            "not read" in w for w in warnings), warnings)
        self.assertTrue(any("material 'Noisy': Normal is connected to a Normal Map node, which SubSplat does not read"
                            in w and "Object Space" in w for w in warnings), warnings)
        rotated = lambertian("Rotated")
        texture = texture_into(rotated, checker_image("Rotated", 2, A, B), interpolation="Cubic")
        mapping_before(rotated, texture, rotation=(math.radians(10), 0, math.radians(45)))
        data, warnings = self.describe(rotated)
        self.assertIsNotNone(data.color_texture)
        self.assertEqual(data.base_color, (1.0, 1.0, 1.0))
        c, s = math.cos(math.radians(45)), math.sin(math.radians(45))
        np.testing.assert_allclose(data.color_texture.transform, (c, -s, 0, s, c, 0), atol=1e-6)
        self.assertTrue(any("rotates about x or y" in w for w in warnings), warnings)
        self.assertEqual(data.color_texture.interpolation, "LINEAR")
        self.assertTrue(any("interpolates Cubic, which SubSplat renders as Linear" in w for w in warnings), warnings)

    def test_a_base_color_the_principled_source_does_not_read_is_named(self):
        """Blender 3.x: a translucent material whose source is the Principled BSDF takes its colour
        from Subsurface Color, so an image into Base Color is not read, and the warning says so
        (4.x reads Base Color as the albedo: no warning)."""
        helpers.empty_scene(8, 8)
        material = lambertian("Sourced")
        material.subsplat.enabled, material.subsplat.source = True, "PRINCIPLED"
        bsdf = material.node_tree.nodes["Principled BSDF"]
        bsdf.inputs[subsplat.version.PRINCIPLED_SUBSURFACE_SCALE].default_value = 1.0  # a radius to convert
        texture_into(material, checker_image("Unread", 2, A, B))
        _data, warnings = self.describe(material)
        named = any("material 'Sourced': Base Color is connected to a Image Texture node, which SubSplat does not "
                    "read: its Principled BSDF source takes the colour from Subsurface Color" in w for w in warnings)
        self.assertEqual(named, subsplat.principled.COLOR_INPUT != "Base Color", warnings)

    def test_a_missing_image_fails_naming_the_material_and_the_image(self):
        helpers.empty_scene(8, 8)
        material = lambertian("Missing")
        image = bpy.data.images.new("missing_texture.png", 4, 4)  # as a file whose file is gone
        image.source = "FILE"
        image.filepath = os.path.join(helpers.OUTPUT, "nonexistent", "missing_texture.png")
        image.reload()
        texture_into(material, image)
        with self.assertRaises(export.ExportError) as caught:
            materials.material_data(material, [])
        self.assertIn("material 'Missing'", str(caught.exception))
        self.assertIn("image 'missing_texture.png'", str(caught.exception))

    def test_a_uv_map_node_sends_its_uv_map_and_two_different_ones_warn(self):
        """A UV Map node naming the second UV map: the mesh sends that one (flipped in u); a second
        material on the same mesh reading the first: warned, the first material's is sent."""
        scene = helpers.empty_scene(8, 8)
        material = lambertian("Second")
        texture = texture_into(material, checker_image("Second", 2, A, B))
        mapping_before(material, texture, uv_map="Flipped")
        obj = uv_plane(scene, material, layers=("UVMap", "Flipped"))
        helpers.top_down_camera(scene, ortho_scale=PLANE)
        frame = export.export_frame(bpy.context.evaluated_depsgraph_get(), 8, 8)
        uvs = frame.meshes[0].uvs
        flipped = np.empty(len(obj.data.loops) * 2, dtype=np.float32)
        obj.data.uv_layers["Flipped"].data.foreach_get("uv", flipped)
        np.testing.assert_array_equal(uvs.ravel(), flipped)
        self.assertFalse(any("UV map" in w for w in frame.warnings), frame.warnings)
        other = lambertian("First")
        texture_into(other, checker_image("First", 2, A, B))  # the render UV map, "UVMap"
        obj.data.materials.append(other)
        obj.data.polygons[0].material_index = 0
        frame = export.export_frame(bpy.context.evaluated_depsgraph_get(), 8, 8)
        np.testing.assert_array_equal(frame.meshes[0].uvs.ravel(), flipped)
        self.assertTrue(any("object 'Plane'" in w and "'Flipped' for all" in w for w in frame.warnings), frame.warnings)


class ImageConversion(unittest.TestCase):
    def timed(self, material, what):
        start = time.perf_counter()
        image = materials.material_data(material, []).color_texture.image
        print(f"image conversion: {what} in {(time.perf_counter() - start) * 1e3:.1f} ms")
        return image

    def test_images_are_converted_once_and_again_when_changed(self):
        """A 2048^2 byte sRGB image: converted as the sRGB formula says, not again while unchanged,
        again once painted and once saved; a generated float image likewise. Each time is printed
        (docs/TEXTURES.md), with no bound on it here."""
        helpers.empty_scene(8, 8)
        side = 2048
        rng = np.random.default_rng(3)
        stored = (rng.integers(0, 256, size=(side, side, 4)) / 255.0).astype(np.float32)
        image = bpy.data.images.new("Big", side, side)
        image.pixels.foreach_set(stored.ravel())
        material = lambertian("Big")
        texture_into(material, image)
        print(f"image conversion: {helpers.machine()}, Blender {bpy.app.version_string}")
        first = self.timed(material, f"a painted {side}^2 byte sRGB image (read, digest, convert, send)")
        rgb = subsplat.principled.image_rgb(image, True)
        expected = subsplat.principled.srgb_to_linear(stored[..., :3])
        np.testing.assert_allclose(rgb[::97, ::89], expected[::97, ::89], rtol=1e-6, atol=1e-7)
        self.assertIs(self.timed(material, "the same painted image again (read, digest)"), first)
        stored[:16, :16, :3] = 1.0
        image.pixels.foreach_set(stored.ravel())
        painted = self.timed(material, "the image painted again")
        self.assertIsNot(painted, first)
        image.filepath_raw = os.path.join(helpers.OUTPUT, "textures_big.png")
        image.file_format = "PNG"
        image.save()  # now a clean image of a file: known by its settings and the file's time
        self.assertFalse(image.is_dirty)
        saved = self.timed(material, f"a {side}^2 byte sRGB image of a file (read, convert, send)")
        self.assertIsNot(saved, painted)
        self.assertIs(self.timed(material, "the same file's image again (its settings)"), saved)
        clean = bpy.data.images.new("Clean", side, side, float_buffer=True)
        material = lambertian("Clean")
        texture_into(material, clean)
        first = self.timed(material, f"a generated {side}^2 float image (read, check, send)")
        self.assertIs(self.timed(material, "the same float image again (its settings)"), first)
        self.assertLessEqual(textures.cached_images(), textures.MAX_IMAGES)


if __name__ == "__main__":
    helpers.run_tests()
