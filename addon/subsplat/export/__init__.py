"""Depsgraph to plain data (export.data): the evaluated meshes, materials, lights, camera and
settings of one frame, one module each. Nothing here calls the library except to make the profile
sets of heterogeneous materials (materials.py); native.py turns the data into the C API's structs."""
from . import background, camera, data, lights, materials, mesh, settings
from .data import ExportError, Material

HOLDOUT_KEY = "\0holdout"  # the registry's key of the material a holdout object's triangles get


class Frame:
    """What one frame sends to a native context; also the viewport's material registry."""

    def __init__(self):
        self.materials = {}   # name -> (material id, data.Material)
        self.mapped = set()   # names of materials whose profiles vary over the surface (need UVs)
        self.meshes = []      # data.Mesh
        self.lights = []      # data.Light
        self.warnings = []
        self.camera = None    # data.Camera
        self.environment = None  # data.Environment: the world's map as the background, or None
        # World positions are sent relative to this point (a final render's camera, the viewport's
        # camera when its session began): single-precision floats then keep their precision in a
        # scene far from Blender's origin.
        self.origin = (0.0, 0.0, 0.0)

    def material_id(self, material):
        key = material.name_full if material is not None else ""
        if key not in self.materials:
            self._describe(key, material, len(self.materials))
        return self.materials[key][0]

    def holdout_id(self):
        """The id of the HOLDOUT material (a hole in the image) every triangle of a holdout object gets."""
        if HOLDOUT_KEY not in self.materials:
            self.materials[HOLDOUT_KEY] = (len(self.materials), Material(kind="HOLDOUT"))
        return self.materials[HOLDOUT_KEY][0]

    def refresh_material(self, material):
        """Describes a material again under its id (the viewport, after an edit): (id, Material),
        or None for a material this frame has not used."""
        key = material.name_full
        if key not in self.materials:
            return None
        self._describe(key, material, self.materials[key][0])
        return self.materials[key]

    def _describe(self, key, material, material_id):
        try:
            described = materials.material_data(material, self.warnings)
        except (KeyError, AttributeError) as error:
            raise ExportError(f"material '{key}': cannot read its settings ({error})") from error
        self.materials[key] = (material_id, described)
        self.mapped.discard(key)
        if described.profiles is not None and described.profiles.info()["profiles"] > 1:
            self.mapped.add(key)


def holdout_objects(depsgraph):
    """Names of the objects Blender renders as holdouts: Object Properties > Visibility > Holdout, and
    the objects of the view layer's holdout collections (and their children)."""
    names = set()

    def visit(layer_collection, held):
        held = held or layer_collection.holdout
        if held:
            names.update(obj.name_full for obj in layer_collection.collection.objects)
        for child in layer_collection.children:
            visit(child, held)
    visit(depsgraph.view_layer.layer_collection, False)
    names.update(obj.name_full for obj in depsgraph.scene.objects if getattr(obj, "is_holdout", False))
    return names


def export_frame(depsgraph, width, height):
    """Every visible mesh instance, its materials, the lights and the camera."""
    scene = depsgraph.scene
    frame = Frame()
    holdouts = holdout_objects(depsgraph)
    frame.origin = camera.camera_origin(scene, depsgraph)
    frame.camera = camera.camera_data(scene, depsgraph, width, height, frame.origin)
    frame.warnings.extend(camera.feature_warnings(scene))
    frame.lights.extend(settings.world_lights(scene, frame.warnings))
    frame.environment = background.environment(scene, frame.warnings)
    for instance in depsgraph.object_instances:
        obj = instance.object
        if obj.type == "LIGHT":
            frame.lights.append(lights.light_data(obj, instance.matrix_world, frame.warnings, frame.origin))
        elif mesh.renders(obj):
            exported = mesh.export_mesh(obj, instance.matrix_world, frame, obj.original.name_full in holdouts)
            if exported is not None:
                frame.meshes.append(exported)
    return frame
