"""The add-on's own bookkeeping, apart from images: the binding refuses structs laid out otherwise
than the library's, the profile-set cache stays bounded, a frame describes each material once, a
viewport keeps a mesh it failed to send, and the material panel asks the library only when the
material changed."""
import ctypes
import gc
import types
import unittest

import bpy

from subsplat_testing import helpers

native_loaded_by_registration = None


def _enable():
    global native_loaded_by_registration
    module = helpers.enable_addon()
    native_loaded_by_registration = module.native._libs is not None
    return module


subsplat = _enable()
native = subsplat.native
materials = subsplat.export.materials


def principled_material(name, radius):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    material.subsplat.enabled = True
    material.subsplat.source = "PRINCIPLED"
    material.subsplat.mm_per_unit = 100.0
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs[subsplat.principled.COLOR_INPUT].default_value = (0.8, 0.5, 0.4, 1.0)
    bsdf.inputs[subsplat.principled.RADIUS_INPUT].default_value = (radius, radius / 2, radius / 4)
    bsdf.inputs[subsplat.principled.SCALE_INPUT].default_value = 1.0
    return material


class Counting:
    """Wraps module.name, counting its calls, until restored."""

    def __init__(self, module, name):
        self.module, self.name, self.original, self.calls = module, name, getattr(module, name), 0

        def counted(*args, **kwargs):
            self.calls += 1
            return self.original(*args, **kwargs)
        setattr(module, name, counted)

    def restore(self):
        setattr(self.module, self.name, self.original)


class LibraryLoad(unittest.TestCase):
    def test_the_library_is_loaded_when_the_addon_registers_not_in_a_panel_draw(self):
        # Loading releases the GIL for 0.1-0.4 s; inside a draw that let a preview thread leave
        # Blender's "may not write" flag set (docs/DECISIONS.md, "The GIL").
        self.assertTrue(native_loaded_by_registration)


class StructLayout(unittest.TestCase):
    def test_every_struct_matches_the_library(self):
        for structure, name in native.LAYOUTS.items():
            native.check_layout(native.library(), structure, name)

    def test_a_struct_laid_out_otherwise_is_refused_naming_the_struct_and_field(self):
        swapped = [field for field in native.Settings._fields_]
        swapped[2], swapped[3] = swapped[3], swapped[2]  # background after reference_samples

        class Swapped(ctypes.Structure):
            _fields_ = swapped

        with self.assertRaises(native.SubsplatError) as caught:
            native.check_layout(native.library(), Swapped, "SsSettings")
        self.assertIn("SsSettings.reference_samples is at offset 24", str(caught.exception))

        class Short(ctypes.Structure):  # forward_shift missing
            _fields_ = native.Settings._fields_[:-1]

        with self.assertRaises(native.SubsplatError) as caught:
            native.check_layout(native.library(), Short, "SsSettings")
        self.assertIn("SsSettings has 84 bytes", str(caught.exception))

        class Renamed(ctypes.Structure):
            _fields_ = [("kind", ctypes.c_int32), ("colour", ctypes.c_float * 3)]

        with self.assertRaises(native.SubsplatError) as caught:
            native.check_layout(native.library(), Renamed, "SsMaterialDesc")
        self.assertIn("SsMaterialDesc has no field 'colour'", str(caught.exception))


class ProfileSetCache(unittest.TestCase):
    def test_the_cache_keeps_the_most_recently_used_sets_and_releases_the_rest(self):
        bpy.ops.wm.read_homefile(use_empty=True)
        gc.collect()
        before = native.resource_counts()["profile_sets"]
        count = 2 * materials.MAX_PROFILE_SETS + 3
        made = [principled_material(f"Principled {i}", 0.01 + 0.001 * i) for i in range(count)]
        for material in made:
            materials.source_profiles(material)
        gc.collect()
        self.assertLessEqual(native.resource_counts()["profile_sets"] - before, materials.MAX_PROFILE_SETS)
        self.assertLessEqual(materials.cached_profile_sets(), materials.MAX_PROFILE_SETS)
        # The most recent is kept: asking again makes nothing new.
        counter = Counting(native.ProfileSet, "from_dipoles")
        try:
            materials.source_profiles(made[-1])
        finally:
            counter.restore()
        self.assertEqual(counter.calls, 0)


class OneDescriptionPerFrame(unittest.TestCase):
    def test_a_frame_reads_each_material_once(self):
        scene = helpers.empty_scene(16, 16)
        helpers.top_down_camera(scene, ortho_scale=3.0)
        helpers.plane(scene, 2.0, principled_material("Once", 0.02))
        depsgraph = bpy.context.evaluated_depsgraph_get()
        subsplat.export.export_frame(depsgraph, 16, 16)  # the profile set made and cached
        counter = Counting(subsplat.principled, "read")
        try:
            subsplat.export.export_frame(depsgraph, 16, 16)
        finally:
            counter.restore()
        self.assertEqual(counter.calls, 1, "the Principled BSDF read once per frame")


class FailingContext:
    """A native context whose first mesh upload fails as beyond the memory budget."""

    def __init__(self):
        self.meshes, self.failures = {}, 1

    def set_mesh(self, object_id, mesh):
        if self.failures:
            self.failures -= 1
            raise native.SubsplatError("ssSetMesh: mesh needs 10 MiB beyond the memory budget")
        self.meshes[object_id] = mesh

    def set_material(self, material_id, material):
        pass

    def remove_mesh(self, object_id):
        self.meshes.pop(object_id, None)


class ViewportUploads(unittest.TestCase):
    def test_a_mesh_that_failed_to_upload_is_sent_again(self):
        session = subsplat.engine.viewport.ViewportSession()
        session.context = FailingContext()
        session.pending_meshes = {0: "mesh 0", 1: "mesh 1"}
        with self.assertRaises(native.SubsplatError):
            session._send_pending()
        session._send_pending()
        self.assertEqual(session.context.meshes, {0: "mesh 0", 1: "mesh 1"})
        self.assertEqual(session.pending_meshes, {})


class RecordingLayout:
    """Enough of a UILayout for a panel's draw(): records the labels."""

    def __init__(self, labels):
        self.__dict__["labels"] = labels

    def label(self, text="", **_kwargs):
        self.labels.append(text)

    def __getattr__(self, _name):
        return lambda *args, **kwargs: RecordingLayout(self.labels)

    def __setattr__(self, name, value):
        pass


class MaterialPanel(unittest.TestCase):
    def draw(self, material):
        labels = []
        panel = types.SimpleNamespace(layout=RecordingLayout(labels))
        subsplat.ui.SUBSPLAT_PT_material.draw(panel, types.SimpleNamespace(material=material))
        return labels

    def test_redraws_ask_the_library_only_when_the_material_changed(self):
        scene = helpers.empty_scene(8, 8)
        material = principled_material("Panel", 0.02)
        helpers.plane(scene, 1.0, material)
        bpy.context.view_layer.update()
        info = Counting(native, "profile_info")
        reads = Counting(subsplat.principled, "read")
        try:
            first = self.draw(material)
            for _ in range(5):
                self.assertEqual(self.draw(material), first)
            self.assertEqual((info.calls, reads.calls), (1, 1), "five redraws of an unchanged material")
            material.subsplat.eta = 1.4
            self.draw(material)
            self.assertEqual(info.calls, 2, "a SubSplat setting changed")
            bsdf = material.node_tree.nodes["Principled BSDF"]
            bsdf.inputs[subsplat.principled.RADIUS_INPUT].default_value = (0.03, 0.02, 0.01)
            bpy.context.view_layer.update()
            changed = self.draw(material)
            self.assertEqual(info.calls, 3, "a node input changed")
            self.assertNotEqual(changed, first)
            image = bpy.data.images.new("Colour", 4, 4)
            texture = material.node_tree.nodes.new("ShaderNodeTexImage")
            texture.image = image
            material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs[subsplat.principled.COLOR_INPUT])
            bpy.context.view_layer.update()
            self.draw(material)
            self.assertEqual(info.calls, 4, "an image linked")
            self.draw(material)
            self.assertEqual(info.calls, 4, "nothing changed since")
        finally:
            info.restore()
            reads.restore()


class EnumsByName(unittest.TestCase):
    def test_editing_a_coefficient_makes_the_preset_custom_and_a_parameter_the_quality_manual(self):
        scene = helpers.empty_scene(8, 8)
        material = bpy.data.materials.new("Enums")
        material.subsplat.preset = "SKIN1"
        material.subsplat.sigma_a = (0.1, 0.2, 0.3)
        self.assertEqual(material.subsplat.preset, "CUSTOM")
        self.assertEqual(tuple(material.subsplat.sigma_a), tuple(map(lambda v: float(ctypes.c_float(v).value),
                                                                     (0.1, 0.2, 0.3))))
        scene.subsplat.quality = "AUTO"
        scene.subsplat.levels = 3
        self.assertEqual(scene.subsplat.quality, "MANUAL")


if __name__ == "__main__":
    helpers.run_tests()
