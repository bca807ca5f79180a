"""Depsgraph to plain data (export.data): the evaluated meshes, materials, lights, camera and
settings of one frame, one module each. Nothing here calls the library except to make the profile
sets of heterogeneous materials (materials.py); native.py turns the data into the C API's structs."""
from . import camera, data, lights, materials, mesh, settings
from .data import ExportError


class Frame:
    """What one frame sends to a native context; also the viewport's material registry."""

    def __init__(self):
        self.materials = {}   # name -> (material id, data.Material)
        self.mapped = set()   # names of materials whose profiles vary over the surface (need UVs)
        self.meshes = []      # data.Mesh
        self.lights = []      # data.Light
        self.warnings = []
        self.camera = None    # data.Camera
        # World positions are sent relative to this point (a final render's camera, the viewport's
        # camera when its session began): single-precision floats then keep their precision in a
        # scene far from Blender's origin.
        self.origin = (0.0, 0.0, 0.0)

    def material_id(self, material):
        key = material.name_full if material is not None else ""
        if key not in self.materials:
            self._describe(key, material, len(self.materials))
        return self.materials[key][0]

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


def export_frame(depsgraph, width, height):
    """Every visible mesh instance, its materials, the lights and the camera."""
    scene = depsgraph.scene
    frame = Frame()
    frame.origin = camera.camera_origin(scene, depsgraph)
    frame.camera = camera.camera_data(scene, depsgraph, width, height, frame.origin)
    frame.warnings.extend(camera.feature_warnings(scene))
    for instance in depsgraph.object_instances:
        obj = instance.object
        if obj.type == "LIGHT":
            frame.lights.append(lights.light_data(obj, instance.matrix_world, frame.warnings, frame.origin))
        elif mesh.renders(obj):
            exported = mesh.export_mesh(obj, instance.matrix_world, frame)
            if exported is not None:
                frame.meshes.append(exported)
    return frame
