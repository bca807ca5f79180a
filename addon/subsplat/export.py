"""Depsgraph to arrays: the evaluated (deformed) meshes, materials, lights and camera of one frame."""
import os

import bpy
import numpy as np

from . import artist, native, principled

BLENDER_4 = bpy.app.version >= (4, 0, 0)
# Principled BSDF inputs that were renamed in 4.0.
SPECULAR_INPUT = "Specular IOR Level" if BLENDER_4 else "Specular"


class ExportError(RuntimeError):
    """Scene data the engine cannot render; the message names the object or material."""


def column_major(matrix):
    """A mathutils 4x4 Matrix as 16 floats, column-major (OpenGL order)."""
    return [matrix[row][col] for col in range(4) for row in range(4)]


def _principled(material):
    if not material.use_nodes or material.node_tree is None:
        return None
    for node in material.node_tree.nodes:
        if node.type == "OUTPUT_MATERIAL" and node.is_active_output:
            link = node.inputs["Surface"].links
            if link and link[0].from_node.type == "BSDF_PRINCIPLED":
                return link[0].from_node
    return next((n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED"), None)


# Loaded SubEdit files by (path, modification time, size, tolerance): a file is
# read again only when it changed on disk or the tolerance changed.
_subedit_files = {}


def subedit_file_profiles(material):
    """The ProfileSet of a SUBEDIT_FILE material; ExportError names the material and the file."""
    settings = material.subsplat
    if not settings.subedit_path:
        raise ExportError(f"material '{material.name}': no SubEdit file is set (Material > Translucency > File)")
    path = os.path.normpath(bpy.path.abspath(settings.subedit_path, library=material.library))
    try:
        status = os.stat(path)
    except OSError:
        raise ExportError(f"material '{material.name}': SubEdit file '{path}' does not exist") from None
    key = (path, status.st_mtime_ns, status.st_size, settings.fit_tolerance)
    profiles = _subedit_files.get(key)
    if profiles is None:
        try:
            profiles = native.ProfileSet.load(path, settings.fit_tolerance)
        except native.SubsplatError as error:
            raise ExportError(f"material '{material.name}': {error}") from None
        for old in [k for k in _subedit_files if k[0] == path]:
            del _subedit_files[old]
        _subedit_files[key] = profiles
    return profiles


# Profile sets made from Principled BSDFs, by material: (inputs key, ProfileSet).
_principled_sets = {}


def principled_profiles(material, warnings=None):
    """The ProfileSet of a PRINCIPLED material, made again only when its inputs changed."""
    settings = material.subsplat
    node = _principled(material)
    if node is None:
        raise ExportError(f"material '{material.name}': the Principled BSDF source needs a Principled BSDF node")
    try:
        sigma_a, sigma_s, notes, key = principled.read(material, node, settings.mm_per_unit, settings.eta)
    except principled.PrincipledError as error:
        raise ExportError(str(error)) from None
    if warnings is not None:
        warnings.extend(notes)
    key = (key, settings.fit_tolerance, settings.mm_per_unit)
    cached = _principled_sets.get(material.name_full)
    if cached is not None and cached[0] == key:
        return cached[1]
    try:
        profiles = native.ProfileSet.from_dipoles(sigma_a, sigma_s, settings.eta, settings.fit_tolerance)
    except native.SubsplatError as error:
        raise ExportError(f"material '{material.name}': {error}") from None
    _principled_sets[material.name_full] = (key, profiles)
    return profiles


# Profile sets of the artist model, by material: (inputs key, ProfileSet).
_artist_sets = {}


def artist_profiles(material):
    """The ProfileSet of an ARTIST material, made again only when its inputs changed."""
    import hashlib
    settings = material.subsplat
    try:
        if settings.albedo_image is not None:
            albedo = principled._image_values(settings.albedo_image, linear_colour=True)
        else:
            albedo = np.asarray(settings.albedo_color, dtype=np.float32).reshape(1, 1, 3)
        log_profiles, radius_mm = artist.profiles(material, settings.mm_per_unit, albedo)
    except (artist.ArtistError, principled.PrincipledError) as error:
        raise ExportError(str(error) if str(error).startswith("material") else
                          f"material '{material.name}': {error}") from None
    key = (hashlib.blake2b(log_profiles.tobytes(), digest_size=16).hexdigest(), radius_mm, settings.fit_tolerance)
    cached = _artist_sets.get(material.name_full)
    if cached is not None and cached[0] == key:
        return cached[1]
    try:
        profiles = native.ProfileSet.from_profiles(log_profiles, radius_mm, settings.fit_tolerance)
    except native.SubsplatError as error:
        raise ExportError(f"material '{material.name}': {error}") from None
    _artist_sets[material.name_full] = (key, profiles)
    return profiles


def source_profiles(material, warnings=None):
    """The ProfileSet of a SUBEDIT_FILE, PRINCIPLED or ARTIST material (None for DIPOLE)."""
    source = material.subsplat.source
    if source == "SUBEDIT_FILE":
        return subedit_file_profiles(material)
    if source == "PRINCIPLED":
        return principled_profiles(material, warnings)
    if source == "ARTIST":
        return artist_profiles(material)
    return None


def material_profiles(material):
    """A translucent material as a ProfileSet, whatever its source (what Bake SubEdit Material writes)."""
    settings = material.subsplat
    profiles = source_profiles(material)
    if profiles is not None:
        return profiles
    sigma_a = np.array(settings.sigma_a, dtype=np.float32).reshape(1, 1, 3)
    sigma_s_prime = np.array(settings.sigma_s_prime, dtype=np.float32).reshape(1, 1, 3)
    try:
        return native.ProfileSet.from_dipoles(sigma_a, sigma_s_prime, settings.eta, settings.fit_tolerance)
    except native.SubsplatError as error:
        raise ExportError(f"material '{material.name}': {error}") from None


def material_desc(material, warnings=None):
    """The native description of a Blender material (None: the default grey).

    A SUBEDIT desc points at a ProfileSet that this module's caches keep alive. Warnings about the
    material (inputs that are not read) are appended to `warnings`.
    """
    desc = native.MaterialDesc()
    if material is None:
        desc.kind = native.MATERIAL_OPAQUE
        desc.base_color = native.Float3(0.8, 0.8, 0.8)
        desc.roughness, desc.specular = 0.5, 0.5
        return desc
    settings = material.subsplat
    if settings.enabled:
        desc.kind = native.MATERIAL_DIPOLE
        desc.sigma_a = native.Float3(*settings.sigma_a)
        desc.sigma_s_prime = native.Float3(*settings.sigma_s_prime)
        desc.eta = settings.eta
        desc.mm_per_unit = settings.mm_per_unit
        desc.roughness = settings.roughness
        desc.specular = settings.specular
        profiles = source_profiles(material, warnings)
        if profiles is not None:
            desc.kind = native.MATERIAL_SUBEDIT
            desc.profiles = profiles.handle
        return desc
    desc.kind = native.MATERIAL_OPAQUE
    node = _principled(material)
    if node is not None:
        desc.base_color = native.Float3(*node.inputs["Base Color"].default_value[:3])
        desc.roughness = node.inputs["Roughness"].default_value
        desc.specular = min(max(node.inputs[SPECULAR_INPUT].default_value, 0.0), 1.0)
    else:
        desc.base_color = native.Float3(*material.diffuse_color[:3])
        desc.roughness = material.roughness
        desc.specular = material.specular_intensity
    return desc


def _corner_normals(mesh, vertices, loop_vertex):
    """Per-corner normals. Where Blender's rules are the plain ones (no custom split normals, no
    auto smooth) they are computed here, in a fixed order: Blender 3.4 sums face normals into
    vertices on several threads, so its normals of a deformed mesh differ in their last bit from
    one process to the next, and so would the frames of a render farm (docs/ANIMATION.md)."""
    if BLENDER_4 or mesh.has_custom_normals or mesh.use_auto_smooth:
        normals = np.empty(len(mesh.loops) * 3, dtype=np.float32)
        if BLENDER_4:
            mesh.corner_normals.foreach_get("vector", normals)
        else:
            mesh.calc_normals_split()
            mesh.loops.foreach_get("normal", normals)
        return normals.reshape(-1, 3)
    return smooth_corner_normals(mesh, vertices, loop_vertex)


def smooth_corner_normals(mesh, vertices, loop_vertex):
    """Blender's corner normals without auto smooth, deterministically: face normals by Newell's
    formula, vertex normals as the sum of the face normals around them weighted by the corner
    angle, and each corner the vertex normal on smooth faces, the face normal on flat ones."""
    count = len(mesh.polygons)
    starts = np.empty(count, dtype=np.int64)
    totals = np.empty(count, dtype=np.int64)
    smooth = np.empty(count, dtype=bool)
    mesh.polygons.foreach_get("loop_start", starts)
    mesh.polygons.foreach_get("loop_total", totals)
    mesh.polygons.foreach_get("use_smooth", smooth)
    points = vertices.astype(np.float64)[loop_vertex]
    first = np.repeat(starts, totals)
    sides = np.repeat(totals, totals)
    local = np.arange(len(loop_vertex)) - first
    following = points[first + (local + 1) % sides]
    preceding = points[first + (local - 1) % sides]
    face = np.add.reduceat(np.cross(points, following), starts, axis=0) if count else np.zeros((0, 3))
    length = np.linalg.norm(face, axis=1, keepdims=True)
    face = np.divide(face, length, out=np.zeros_like(face), where=length > 0)
    a, b = following - points, preceding - points
    a /= np.maximum(np.linalg.norm(a, axis=1, keepdims=True), 1e-300)
    b /= np.maximum(np.linalg.norm(b, axis=1, keepdims=True), 1e-300)
    angle = np.arccos(np.clip(np.einsum("ij,ij->i", a, b), -1.0, 1.0))
    corner_face = np.repeat(face, totals, axis=0)
    weighted = corner_face * angle[:, None]
    vertex = np.stack([np.bincount(loop_vertex, weighted[:, c], minlength=len(mesh.vertices)) for c in range(3)],
                      axis=1)
    length = np.linalg.norm(vertex, axis=1, keepdims=True)
    vertex = np.divide(vertex, length, out=np.zeros_like(vertex), where=length > 0)
    corner = np.where(np.repeat(smooth, totals)[:, None], vertex[loop_vertex], corner_face)
    return corner.astype(np.float32)


def mesh_arrays(mesh):
    """Per-corner positions and normals, triangle corner indices, per-triangle material slots."""
    mesh.calc_loop_triangles()
    vertices = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", vertices)
    loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    triangles = np.empty(len(mesh.loop_triangles) * 3, dtype=np.uint32)
    mesh.loop_triangles.foreach_get("loops", triangles)
    slots = np.empty(len(mesh.loop_triangles), dtype=np.uint32)
    mesh.loop_triangles.foreach_get("material_index", slots)
    vertices = vertices.reshape(-1, 3)
    return vertices[loop_vertex], _corner_normals(mesh, vertices, loop_vertex), triangles.reshape(-1, 3), slots


def corner_uvs(mesh):
    """Per-corner UVs of the UV map used for rendering, (corners, 2); None without one."""
    layer = next((layer for layer in mesh.uv_layers if layer.active_render), mesh.uv_layers.active)
    if layer is None:
        return None
    uvs = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    layer.data.foreach_get("uv", uvs)
    return uvs.reshape(-1, 2)


class Frame:
    """What one frame sends to the native context."""

    def __init__(self):
        self.materials = {}   # name -> (material id, MaterialDesc)
        self.mapped = set()   # names of materials whose profiles vary over the surface (need UVs)
        self.profile_sets = {}  # material name -> ProfileSet, kept alive while the native context may use it
        # (object name, positions, normals, triangles, triangle materials, matrix, uvs or None)
        self.meshes = []
        self.lights = []
        self.warnings = []
        self.camera = None

    def material_id(self, material):
        key = material.name_full if material is not None else ""
        if key not in self.materials:
            self._describe(key, material, len(self.materials))
        return self.materials[key][0]

    def refresh_material(self, material):
        """Describes a material again under its id (the viewport, after an edit): (id, desc), or
        None for a material this frame has not used."""
        key = material.name_full
        if key not in self.materials:
            return None
        self._describe(key, material, self.materials[key][0])
        return self.materials[key]

    def _describe(self, key, material, material_id):
        try:
            desc = material_desc(material, self.warnings)
        except (KeyError, AttributeError) as error:
            raise ExportError(f"material '{key}': cannot read its settings ({error})") from error
        self.materials[key] = (material_id, desc)
        self.mapped.discard(key)
        self.profile_sets.pop(key, None)
        if desc.kind == native.MATERIAL_SUBEDIT:
            profiles = source_profiles(material)
            self.profile_sets[key] = profiles
            if profiles.info()["profiles"] > 1:
                self.mapped.add(key)


def _light_desc(obj, matrix, frame):
    light = obj.data
    desc = native.LightDesc()
    desc.color = native.Float3(*light.color)
    desc.position = native.Float3(*matrix.translation)
    axis = -matrix.col[2].xyz  # lights shine down their local -Z
    desc.direction = native.Float3(*axis.normalized()) if axis.length > 0 else native.Float3(0, 0, -1)
    if light.type == "SUN":
        desc.type = native.LIGHT_SUN
        desc.strength = light.energy
    elif light.type == "SPOT":
        desc.type = native.LIGHT_SPOT
        desc.strength = light.energy
        desc.spot_size = light.spot_size
        desc.spot_blend = light.spot_blend
    else:
        if light.type == "AREA":
            frame.warnings.append(f"light '{obj.name}': area lights are rendered as point lights")
        desc.type = native.LIGHT_POINT
        desc.strength = light.energy
    return desc


def camera_desc(scene, depsgraph, width, height):
    camera = scene.camera
    if camera is None:
        raise ExportError("the scene has no camera")
    camera = camera.evaluated_get(depsgraph)
    render = scene.render
    projection = camera.calc_matrix_camera(depsgraph, x=width, y=height,
                                           scale_x=render.pixel_aspect_x, scale_y=render.pixel_aspect_y)
    desc = native.CameraDesc()
    desc.world_to_view = native.Float16(*column_major(camera.matrix_world.inverted_safe()))
    desc.view_to_clip = native.Float16(*column_major(projection))
    desc.orthographic = 1 if camera.data.type == "ORTHO" else 0
    return desc


MESH_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT"}


def export_mesh(obj, matrix, frame):
    """One evaluated object's (name, positions, normals, triangles, triangle materials, matrix, uvs),
    its materials registered in frame; None when it has no triangles to draw."""
    try:
        mesh = obj.to_mesh()
    except RuntimeError:
        mesh = None
    if mesh is None:
        return None
    try:
        if len(mesh.polygons) == 0:
            return None
        positions, normals, triangles, slots = mesh_arrays(mesh)
        bad = np.flatnonzero(~np.isfinite(positions).all(axis=1))
        if len(bad):
            loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
            mesh.loops.foreach_get("vertex_index", loop_vertex)
            vertex = int(loop_vertex[bad[0]])
            raise ExportError(f"object '{obj.name}': vertex {vertex} has a non-finite position "
                              f"{tuple(mesh.vertices[vertex].co)}")
        if len(triangles) == 0:
            return None
        slot_materials = [frame.material_id(slot.material) for slot in obj.material_slots] or \
            [frame.material_id(None)]
        lookup = np.asarray(slot_materials, dtype=np.uint32)
        triangle_materials = lookup[np.minimum(slots, len(lookup) - 1)]
        uvs = corner_uvs(mesh)
        if uvs is None:
            for slot in obj.material_slots:
                if slot.material is not None and slot.material.name_full in frame.mapped:
                    frame.warnings.append(f"object '{obj.name}' has no UV map: material '{slot.material.name}' "
                                          "shows its most common profile everywhere")
        return (obj.name, positions, normals, triangles, triangle_materials, column_major(matrix), uvs)
    finally:
        obj.to_mesh_clear()


def renders(obj):
    """Whether an evaluated object is drawn as a mesh."""
    return obj.type in MESH_TYPES and obj.visible_camera


def export_frame(depsgraph, width, height):
    """Every visible mesh instance, its materials, the lights and the camera."""
    scene = depsgraph.scene
    frame = Frame()
    frame.camera = camera_desc(scene, depsgraph, width, height)
    for instance in depsgraph.object_instances:
        obj = instance.object
        if obj.type == "LIGHT":
            frame.lights.append(_light_desc(obj, instance.matrix_world, frame))
        elif renders(obj):
            mesh = export_mesh(obj, instance.matrix_world, frame)
            if mesh is not None:
                frame.meshes.append(mesh)
    return frame


SMALLEST_WEIGHT = 1e-30


def native_settings(scene, debug_passes=False):
    """The scene's SubSplat settings as the library's Settings."""
    settings = scene.subsplat
    result = native.Settings()
    result.method = native.METHODS[settings.method]
    result.background = native.Float4(*background(scene))
    result.reference_samples = settings.reference_samples
    if settings.quality == "AUTO":  # 0: the library's automatic resolution and levels, default thresholds
        result.irradiance_resolution = 0
        result.target_error = settings.target_error
    else:
        result.irradiance_resolution = settings.irradiance_resolution
        result.levels = settings.levels
        result.z0_factor = settings.z0_factor
        result.alpha = settings.alpha
        result.epsilon = settings.epsilon
    # The C API reads 0 as "the default" (8); here 0 is the user's value, eq. 17 without that weight,
    # sent as a tiny positive weight (exp(-1e-30 x) is 1 for any difference).
    result.lambda_z = settings.lambda_z or SMALLEST_WEIGHT
    result.lambda_m = settings.lambda_m or SMALLEST_WEIGHT
    result.debug_passes = int(debug_passes)
    return result


def send_mesh(context, object_id, mesh):
    """Sends export_mesh()'s tuple to a native context; its errors name the object."""
    name, positions, normals, triangles, materials, matrix, uvs = mesh
    try:
        context.set_mesh(object_id, positions, normals, triangles, materials, matrix, uvs)
    except native.SubsplatError as error:
        raise native.SubsplatError(f"object '{name}': {error}") from error


def background(scene):
    """RGBA written where no object is hit: transparent, or the world colour."""
    if scene.render.film_transparent:
        return (0.0, 0.0, 0.0, 0.0)
    world = scene.world
    if world is None:
        return (0.0, 0.0, 0.0, 1.0)
    if world.use_nodes and world.node_tree is not None:
        node = next((n for n in world.node_tree.nodes if n.type == "BACKGROUND"), None)
        if node is not None:
            color = node.inputs["Color"].default_value
            strength = node.inputs["Strength"].default_value
            return (color[0] * strength, color[1] * strength, color[2] * strength, 1.0)
    return (*world.color, 1.0)
