"""The Cycles twin (subsplat.make_cycles_twin, addon/subsplat/twin.py; docs/PHYSICAL.md): each example
scene's twin builds, renders a few samples, and holds every translucent object as a volume (scatter
colour x density = sigma_s', (1 - colour) x density = sigma_a, per unit) behind the right boundary,
with the Cycles settings the truth needs and the reports it owes; the original scene renders the same
afterwards; and the conventions check: Cycles' straight-through transmittance of a slab of the twin's
medium is exp(-sigma_t d), for scattering only and for absorption only."""
import glob
import math
import os
import unittest

import bpy
import bmesh  # after bpy: the `bpy` module provides bmesh only once imported (docs/VERSIONS.md)
import numpy as np

from subsplat_testing import helpers

subsplat = helpers.enable_addon()
from subsplat_testing import materials  # noqa: E402

twin = subsplat.twin
EXAMPLES = sorted(glob.glob(os.path.join(helpers.SOURCE, "example_blends", "*.blend")))
CONVERTIBLE = {"DIPOLE", "PRINCIPLED"}


def expected_medium(material):
    """sigma_a and sigma_s' per Blender unit, computed here from the material's settings."""
    settings = material.subsplat
    if settings.source == "DIPOLE":
        sigma_a, sigma_s = np.array(settings.sigma_a), np.array(settings.sigma_s_prime)
    else:
        node = material.node_tree.nodes["Principled BSDF"]
        albedo = np.array(node.inputs[subsplat.principled.COLOR_INPUT].default_value[:3])
        path = (np.array(node.inputs[subsplat.principled.RADIUS_INPUT].default_value[:3])
                * node.inputs[subsplat.principled.SCALE_INPUT].default_value * settings.mm_per_unit)
        sigma_a, sigma_s = subsplat.principled.coefficients(albedo, path, settings.eta, settings.profile_model)
    return sigma_a * settings.mm_per_unit, sigma_s * settings.mm_per_unit


def volume_nodes(test, material):
    """(scatter, absorption, boundary) nodes of a twin material, checking how they are connected."""
    tree = material.node_tree
    output = next(n for n in tree.nodes if n.type == "OUTPUT_MATERIAL" and n.is_active_output)
    test.assertTrue(output.inputs["Volume"].is_linked, material.name)
    add = output.inputs["Volume"].links[0].from_node
    test.assertEqual(add.type, "ADD_SHADER", material.name)
    kinds = {link.from_node.type: link.from_node for socket in add.inputs for link in socket.links}
    test.assertEqual(set(kinds), {"VOLUME_SCATTER", "VOLUME_ABSORPTION"}, material.name)
    test.assertTrue(output.inputs["Surface"].is_linked, material.name)
    return kinds["VOLUME_SCATTER"], kinds["VOLUME_ABSORPTION"], output.inputs["Surface"].links[0].from_node


def check_medium(test, twin_material, source):
    """The twin material of `source` holds its medium per unit and the boundary its eta calls for."""
    scatter, absorption, boundary = volume_nodes(test, twin_material)
    sigma_a, sigma_s = expected_medium(source)
    colour = np.array(scatter.inputs["Color"].default_value[:3])
    np.testing.assert_allclose(colour * scatter.inputs["Density"].default_value, sigma_s, rtol=1e-5, atol=1e-9)
    test.assertEqual(scatter.inputs["Anisotropy"].default_value, 0.0)
    colour = np.array(absorption.inputs["Color"].default_value[:3])
    np.testing.assert_allclose((1 - colour) * absorption.inputs["Density"].default_value, sigma_a,
                               rtol=1e-5, atol=1e-9)
    test.assertTrue(getattr(twin_material.cycles, "homogeneous_volume", True))  # 5.0 has no such setting
    eta = source.subsplat.eta
    if eta == 1.0:
        test.assertEqual(boundary.type, "BSDF_TRANSPARENT", twin_material.name)
    else:
        test.assertIn(boundary.type, {"BSDF_GLASS", "BSDF_REFRACTION"}, twin_material.name)
        test.assertAlmostEqual(boundary.inputs["IOR"].default_value, eta, places=5)
        test.assertAlmostEqual(boundary.inputs["Roughness"].default_value, source.subsplat.roughness, places=5)


def check_cycles_settings(test, scene):
    cycles = scene.cycles
    test.assertEqual(scene.render.engine, "CYCLES")
    for name in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces",
                 "transparent_max_bounces"):
        test.assertEqual(getattr(cycles, name), 1024, name)
    test.assertEqual((cycles.sample_clamp_direct, cycles.sample_clamp_indirect), (0.0, 0.0))
    test.assertFalse(cycles.use_denoising)
    test.assertFalse(cycles.use_adaptive_sampling)
    test.assertEqual(scene.view_settings.view_transform, "Standard")


def assignment(scene):
    """What the original scene's objects hold: name -> [(slot link, material name)], and its engine."""
    return ({obj.name: [(slot.link, slot.material.name if slot.material else None) for slot in obj.material_slots]
             for obj in scene.objects}, scene.render.engine, scene.name)


def render(scene, name):
    """helpers.render of `scene` (it renders the window's scene): a float RGBA array."""
    bpy.context.window.scene = scene
    return helpers.render(scene, name)


def tiny_cycles(scene, samples=4):
    scene.render.resolution_x, scene.render.resolution_y = 16, 12
    scene.render.resolution_percentage = 100
    scene.cycles.samples = samples
    scene.cycles.device = "CPU"


class Examples(unittest.TestCase):
    def test_each_example_twin_builds_renders_and_holds_the_media(self):
        self.assertGreaterEqual(len(EXAMPLES), 6)
        for path in EXAMPLES:
            name = os.path.splitext(os.path.basename(path))[0]
            with self.subTest(example=name):
                bpy.ops.wm.open_mainfile(filepath=path)
                scene = bpy.context.scene
                before = assignment(scene)
                result, reports = twin.make_cycles_twin(scene)
                self.assertEqual(assignment(scene), before, "the original scene was changed")
                self.assertEqual(result.name, scene.name + " Cycles Twin")
                self.assertIs(result.world, scene.world)
                self.assertIs(result.camera, scene.camera)
                check_cycles_settings(self, result)
                warnings = [text for level, text in reports if level == "WARNING"]
                twin_objects = {obj.name: obj for obj in result.collection.objects}
                refracting = False
                for obj in scene.objects:
                    translucent = [slot.material for slot in obj.material_slots
                                   if slot.material is not None and slot.material.subsplat.enabled]
                    if not translucent:
                        self.assertIn(obj.name, twin_objects, "objects without translucency are kept")
                        continue
                    self.assertNotIn(obj.name, twin_objects)
                    copy = twin_objects[obj.name + " Cycles Twin"]
                    self.assertIs(copy.data, obj.data)
                    for slot, original in zip(copy.material_slots, obj.material_slots):
                        source = original.material
                        if source is None or not source.subsplat.enabled:
                            self.assertEqual(slot.material, source)
                        elif source.subsplat.source in CONVERTIBLE:
                            check_medium(self, slot.material, source)
                            refracting |= source.subsplat.eta > 1.0
                        else:  # reported, not guessed
                            output = next(n for n in slot.material.node_tree.nodes if n.type == "OUTPUT_MATERIAL")
                            self.assertFalse(output.inputs["Volume"].is_linked)
                            self.assertTrue(any(f"material '{source.name}' is not converted" in w for w in warnings),
                                            warnings)
                for light in (o for o in scene.objects if o.type == "LIGHT" and o.data.type in twin.DELTA_LIGHTS):
                    named = any(f"light '{light.name}' does not light the interior" in w for w in warnings)
                    self.assertEqual(named, refracting, (light.name, warnings))
                tiny_cycles(result)
                pixels = render(result, f"twin_{name}")
                self.assertTrue(np.all(np.isfinite(pixels)))
                self.assertGreater(float(pixels[..., :3].mean()), 0.0)

    def test_the_original_renders_the_same_after_the_twin_is_made(self):
        bpy.ops.wm.open_mainfile(filepath=os.path.join(helpers.SOURCE, "example_blends", "marble_pieces.blend"))
        scene = bpy.context.scene
        scene.render.resolution_x, scene.render.resolution_y = 32, 24
        scene.subsplat.irradiance_resolution = 64
        scene.subsplat.quality = "MANUAL"
        before = helpers.render(scene, "original_before_twin")
        first, _reports = twin.make_cycles_twin(scene)
        bpy.context.window.scene = first
        twin.make_cycles_twin(scene)  # made again: replaces the first; a window showing it shows the original
        self.assertEqual(bpy.context.window.scene, scene)
        self.assertEqual([s.name for s in bpy.data.scenes if s.name.startswith(scene.name + " Cycles Twin")],
                         [scene.name + " Cycles Twin"])
        self.assertEqual(len([o for o in bpy.data.objects if twin.MARK in o]), 2)
        self.assertEqual(sorted(m.name for m in bpy.data.materials if twin.MARK in m),
                         ["Cream Cycles Twin", "Marble Cycles Twin"])
        after = render(scene, "original_after_twin")
        self.assertGreater(float(before[..., :3].max()), 0.0)
        np.testing.assert_array_equal(after, before)

    def test_operator_reports_in_blender_b_output(self):
        path = os.path.join(helpers.SOURCE, "example_blends", "marble_pieces.blend")
        result = helpers.run_blender(path, "--python-expr", "import bpy; bpy.ops.subsplat.make_cycles_twin()",
                                     timeout=min(120, helpers.TIMEOUT))
        output = result.stdout + result.stderr
        self.assertEqual(result.returncode, 0, output[-3000:])
        self.assertIn("Info: SubSplat: made scene 'Scene Cycles Twin'", output)
        self.assertIn("Info: SubSplat: material 'Marble': sigma_s = (219, 262, 300)", output)
        self.assertIn("Warning: SubSplat: point light 'PointLight' does not light the interior", output)
        self.assertIn("Warning: SubSplat: sun light 'SunLight' does not light the interior", output)

    def test_delta_lights_are_reported_only_behind_a_refracting_boundary(self):
        scene = helpers.empty_scene(4, 4)
        material = materials.translucent("Skin", mm_per_unit=100.0)
        box(scene, "Box", (-1, -1, -1), (1, 1, 1), material)
        helpers.add_light(scene, "POINT", location=(0, 0, 3), energy=10.0, shadow_soft_size=0.0)
        helpers.add_light(scene, "AREA", location=(0, 0, -3), energy=10.0)
        for eta, warned in ((1.0, False), (1.3, True)):
            material.subsplat.eta = eta
            result, reports = twin.make_cycles_twin(scene)
            warnings = [text for level, text in reports if level == "WARNING"]
            self.assertEqual(any("light 'Point' does not light the interior of 'Box'" in w for w in warnings),
                             warned, (eta, warnings))
            self.assertFalse(any("'Area'" in w for w in warnings), warnings)
            boundary = volume_nodes(self, result.collection.objects["Box Cycles Twin"].material_slots[0].material)[2]
            self.assertEqual(boundary.type, "BSDF_TRANSPARENT" if eta == 1.0 else "BSDF_GLASS")
            self.assertEqual([s.name for s in bpy.data.scenes], [scene.name, result.name])

    def test_normals_that_point_in_or_disagree_are_reported(self):
        """Cycles enters and leaves a volume by the faces' normals: a box whose normals point in, or
        whose faces disagree (one face flipped), holds the medium wrongly (a thin slab lit from below
        rendered black), and the twin says so; a box with outward normals and a mirrored (negatively
        scaled) one are not reported."""
        scene = helpers.empty_scene(4, 4)
        material = materials.translucent("Skin", mm_per_unit=100.0)
        material.subsplat.eta = 1.0
        cases = {"Good": None, "Mirrored": "mirror", "Inside Out": "all", "One Flipped": "one"}
        for index, (name, flip) in enumerate(cases.items()):
            obj = box(scene, name, (3 * index, 0, 0), (3 * index + 1, 1, 1), material)
            if flip == "mirror":
                obj.scale = (-1.0, 1.0, 1.0)
            elif flip:
                shape = bmesh.new()
                shape.from_mesh(obj.data)
                bmesh.ops.reverse_faces(shape, faces=shape.faces if flip == "all" else shape.faces[:1])
                shape.to_mesh(obj.data)
                shape.free()
        _result, reports = twin.make_cycles_twin(scene)
        warnings = [text for level, text in reports if level == "WARNING"]
        self.assertTrue(any("'Inside Out'" in w and "normals point inwards" in w for w in warnings), warnings)
        self.assertTrue(any("'One Flipped'" in w and "normals disagree (4 edges" in w for w in warnings), warnings)
        self.assertFalse(any("'Good'" in w or "'Mirrored'" in w for w in warnings), warnings)

    def test_principled_source_is_its_medium(self):
        """A Principled BSDF's colour is the total reflectance of the material's profile model: the
        twin holds the medium that colour inverts to under that model (the TABULATED model's total is
        the exact half-space albedo, so its twin reflects the colour asked for)."""
        skin_a, skin_s = np.array([0.032, 0.17, 0.48]), np.array([0.74, 0.88, 1.01])
        for model in ("DIPOLE", "TABULATED"):
            with self.subTest(model=model):
                bpy.ops.wm.read_homefile(use_empty=True)
                scene = bpy.context.scene
                albedo, path_mm = subsplat.principled.albedo_and_path(skin_a, skin_s, 1.3, model)
                material = materials.translucent("SkinBSDF", mm_per_unit=100.0, profile_model=model)
                material.use_nodes = True
                material.subsplat.source = "PRINCIPLED"
                node = material.node_tree.nodes["Principled BSDF"]
                node.inputs[subsplat.principled.COLOR_INPUT].default_value = (*albedo, 1.0)
                node.inputs[subsplat.principled.RADIUS_INPUT].default_value = path_mm / 100.0
                node.inputs[subsplat.principled.SCALE_INPUT].default_value = 1.0
                mesh = bpy.data.meshes.new("Box")
                mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
                mesh.materials.append(material)
                scene.collection.objects.link(bpy.data.objects.new("Box", mesh))
                result, _reports = twin.make_cycles_twin(scene)
                made = result.collection.objects["Box Cycles Twin"].material_slots[0].material
                check_medium(self, made, material)
                scatter, absorption, _ = volume_nodes(self, made)
                np.testing.assert_allclose(np.array(scatter.inputs["Color"].default_value[:3])
                                           * scatter.inputs["Density"].default_value, skin_s * 100.0, rtol=1e-3)
                np.testing.assert_allclose((1 - np.array(absorption.inputs["Color"].default_value[:3]))
                                           * absorption.inputs["Density"].default_value, skin_a * 100.0,
                                           rtol=1e-3)


# The conventions check: a slab of thickness D (units) of the twin's medium, index-matched, between an
# orthographic camera looking down a thin pencil and a small emitting square far below it.
MM_PER_UNIT = 10.0
D = 1.0
SIGMA_MM = np.array([0.10, 0.05, 0.025])  # per mm: sigma d = 1, 0.5, 0.25 through the slab


def box(scene, name, low, high, material=None):
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=1.0)
    for vertex in bm.verts:
        vertex.co = [lo + (c + 0.5) * (hi - lo) for c, lo, hi in zip(vertex.co, low, high)]
    bm.to_mesh(mesh)
    bm.free()
    if material is not None:
        mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def pencil_scene(sigma_a_mm, sigma_s_mm):
    scene = helpers.empty_scene(4, 4)
    emission = bpy.data.materials.new("Emitter")
    emission.use_nodes = True
    tree = emission.node_tree
    tree.nodes.clear()
    node = tree.nodes.new("ShaderNodeEmission")
    node.inputs["Strength"].default_value = 1.0
    tree.links.new(node.outputs[0], tree.nodes.new("ShaderNodeOutputMaterial").inputs["Surface"])
    box(scene, "Emitter", (-0.05, -0.05, -0.01), (0.05, 0.05, 0.0), emission)
    medium = materials.translucent("Medium", mm_per_unit=MM_PER_UNIT)
    medium.subsplat.preset = "CUSTOM"
    medium.subsplat.sigma_a, medium.subsplat.sigma_s_prime = tuple(sigma_a_mm), tuple(sigma_s_mm)
    medium.subsplat.eta = 1.0
    slab = box(scene, "Slab", (-2, -2, 3.0), (2, 2, 3.0 + D), medium)
    camera = helpers.top_down_camera(scene, ortho_scale=0.02, height=10.0)
    camera.data.clip_end = 20.0
    return scene, slab


class Conventions(unittest.TestCase):
    """Cycles 3.4's Volume Scatter is sigma_s = colour x density and Volume Absorption sigma_a =
    (1 - colour) x density, per unit: the light that crosses the slab without scattering is
    exp(-sigma_t D) per channel, with sigma_t computed here from the material's coefficients."""

    def transmittance(self, name, sigma_a_mm, sigma_s_mm, volume_bounces, samples, tint=None):
        scene, slab = pencil_scene(sigma_a_mm, sigma_s_mm)
        if tint is not None:  # a uniform tint image into the medium's Base Color
            medium = slab.data.materials[0]
            medium.use_nodes = True
            image = bpy.data.images.new("Tint", 4, 4, float_buffer=True)
            image.pixels.foreach_set(np.tile([*tint, 1.0], 16).astype(np.float32))
            texture = medium.node_tree.nodes.new("ShaderNodeTexImage")
            texture.image = image
            bsdf = next(n for n in medium.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
            medium.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
        result, reports = twin.make_cycles_twin(scene)
        if tint is not None:
            self.assertTrue(any("its tint 'Tint' is the boundary's colour" in text for _, text in reports), reports)
        result.render.resolution_x = result.render.resolution_y = 4
        result.cycles.samples = samples
        result.cycles.device = "CPU"
        result.cycles.volume_bounces = volume_bounces
        through = render(result, f"slab_{name}")
        result.collection.objects["Slab Cycles Twin"].hide_render = True
        bare = render(result, f"slab_{name}_bare")
        measured = through[..., :3].mean(axis=(0, 1)) / bare[..., :3].mean(axis=(0, 1))
        expected = np.exp(-(np.array(sigma_a_mm) + np.array(sigma_s_mm)) * MM_PER_UNIT * D)
        if tint is not None:
            expected = expected * np.array(tint)  # sqrt(T) in, sqrt(T) out
        print(f"{name}: transmittance {np.round(measured, 5)}, exp(-sigma_t d) {np.round(expected, 5)}, "
              f"ratio {np.round(measured / expected, 4)}")
        np.testing.assert_allclose(measured, expected, rtol=0.02)
        self.assertGreater(float(bare[..., :3].min()), 0.5)  # the pencil sees only the emitter

    def test_scattering_only_unscattered(self):
        # Volume bounces 0: a scattering event ends the path, so what comes through is exactly the light
        # that did not scatter.
        self.transmittance("scatter_unscattered", (0, 0, 0), SIGMA_MM, volume_bounces=0, samples=4096)

    def test_absorption_only(self):
        self.transmittance("absorb", SIGMA_MM, (0, 0, 0), volume_bounces=1024, samples=16)

    def test_a_tint_is_its_square_root_in_and_out(self):
        """Issue 20, item 7: a translucent material's tint (an image into Base Color, docs/TEXTURES.md)
        on the twin's boundary: the light that crosses the slab carries T, sqrt(T) where it enters
        and sqrt(T) where it leaves, as in SubSplat."""
        self.transmittance("absorb_tinted", SIGMA_MM, (0, 0, 0), volume_bounces=1024, samples=16,
                           tint=(1.0, 0.5, 0.25))

    def test_scattering_only_thin_pencil_all_bounces(self):
        # The twin's own settings (1024 volume bounces): the light scattered out of a thin pencil from a
        # small emitter does not come back into it, so the pencil still sees exp(-sigma_s d).
        self.transmittance("scatter_pencil", (0, 0, 0), SIGMA_MM, volume_bounces=1024, samples=4096)


if __name__ == "__main__":
    helpers.run_tests()
