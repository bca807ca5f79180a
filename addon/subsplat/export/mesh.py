"""Evaluated (deformed) objects as Mesh data: corner positions, normals, triangles, UVs."""
import numpy as np

from .. import version
from .data import ExportError, Mesh, column_major

MESH_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT"}


def renders(obj):
    """Whether an evaluated object is drawn as a mesh."""
    return obj.type in MESH_TYPES and obj.visible_camera


def _corner_normals(mesh, vertices, loop_vertex):
    """Per-corner normals. Where Blender's rules are the plain ones (no custom split normals, no
    auto smooth) they are computed here, in a fixed order: Blender 3.4 sums face normals into
    vertices on several threads, so its normals of a deformed mesh differ in their last bit from
    one process to the next, and so would the frames of a render farm (docs/ANIMATION.md)."""
    if version.needs_blender_corner_normals(mesh):
        normals = np.empty(len(mesh.loops) * 3, dtype=np.float32)
        return version.blender_corner_normals(mesh, normals).reshape(-1, 3)
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


def render_uv_layer(mesh):
    """The UV map Blender renders with (the one marked for rendering, else the active one), or None."""
    return next((layer for layer in mesh.uv_layers if layer.active_render), mesh.uv_layers.active)


def corner_uvs(mesh, name=None):
    """Per-corner UVs of the UV map `name` (None: the one used for rendering), (corners, 2); None
    without one."""
    layer = mesh.uv_layers.get(name) if name else render_uv_layer(mesh)
    if layer is None:
        return None
    uvs = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    layer.data.foreach_get("uv", uvs)
    return uvs.reshape(-1, 2)


def uv_layer_name(obj, mesh, frame):
    """The UV map a mesh sends: the first its materials' textures read (data.Material.uv_maps; a
    material with a profile map reads the render UV map), else the render UV map. The library takes
    one UV map per mesh: materials that want others are warned, as is a UV map the mesh lacks."""
    render = render_uv_layer(mesh)
    if render is None:
        return None
    wanted = []  # (layer name, material name)
    for slot in obj.material_slots:
        if slot.material is None or slot.material.name_full not in frame.materials:
            continue
        described = frame.materials[slot.material.name_full][1]
        names = described.uv_maps + (("",) if slot.material.name_full in frame.mapped else ())
        for name in names:
            if name and name not in mesh.uv_layers:
                frame.warnings.append(f"object '{obj.name}' has no UV map '{name}', which material "
                                      f"'{slot.material.name}' reads: SubSplat reads its render UV map "
                                      f"'{render.name}'")
                name = ""
            wanted.append((name or render.name, slot.material.name))
    if not wanted:
        return render.name
    chosen = wanted[0][0]
    others = [(name, material) for name, material in wanted if name != chosen]
    if others:
        name, material = others[0]
        readers = (f"material '{material}' reads the UV maps '{chosen}' and '{name}'" if material == wanted[0][1] else
                   f"material '{wanted[0][1]}' reads the UV map '{chosen}' and material '{material}' '{name}'")
        frame.warnings.append(f"object '{obj.name}': {readers}; SubSplat sends one UV map a mesh and renders "
                              f"'{chosen}' for all")
    return chosen


def export_mesh(obj, matrix, frame, holdout=False):
    """One evaluated object as Mesh data, its materials registered in frame (an export.Frame); None
    when it has no triangles to draw. A holdout object's triangles all get the HOLDOUT material."""
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
        if holdout:
            slot_materials = [frame.holdout_id()]
        else:
            slot_materials = [frame.material_id(slot.material) for slot in obj.material_slots] or \
                [frame.material_id(None)]
        lookup = np.asarray(slot_materials, dtype=np.uint32)
        triangle_materials = lookup[np.minimum(slots, len(lookup) - 1)]
        uvs = corner_uvs(mesh, None if holdout else uv_layer_name(obj, mesh, frame))
        if uvs is None:
            for slot in obj.material_slots:
                if slot.material is not None and slot.material.name_full in frame.mapped:
                    frame.warnings.append(f"object '{obj.name}' has no UV map: material '{slot.material.name}' "
                                          "shows its most common profile everywhere")
        return Mesh(obj.name, positions, normals, triangles, triangle_materials, column_major(matrix, frame.origin),
                    uvs)
    finally:
        obj.to_mesh_clear()
