"""The Cycles twin of a scene: the physical answer to what SubSplat approximates (docs/PHYSICAL.md).

make_cycles_twin(scene) makes a scene "<name> Cycles Twin" with the same objects, camera, lights and
world, rendered by Cycles, in which every translucent material (material.subsplat.enabled) is the
medium it describes: Volume Scatter (anisotropy 0, so sigma_s = sigma_s') plus Volume Absorption
inside the mesh, per Blender unit (sigma per mm x mm per unit), behind a Transparent BSDF where
eta = 1 or a Glass BSDF (IOR eta, the material's roughness) where eta > 1. In Cycles 3.4 Volume
Scatter gives sigma_s = colour x density and Volume Absorption sigma_a = (1 - colour) x density
(checked by tests/blender/test_twin.py with a transmittance test).

The original scene is not changed: the twin scene holds the original objects, except that each
object with a translucent material is replaced there by a copy of it (sharing its mesh) whose
material slots are linked to the object and hold the twin materials.
"""
import bpy
import numpy as np

from . import principled, version
from .export import data, materials, textures

SUFFIX = " Cycles Twin"
MARK = "subsplat_twin_of"  # custom property on the twin scene and its object copies: the original's name
MAX_BOUNCES = 1024  # Cycles' largest bounce count of every kind; high-albedo media need all of them
DELTA_LIGHTS = {"POINT", "SPOT", "SUN"}
NO_COEFFICIENTS_GREY = (0.5, 0.5, 0.5)


class TwinError(ValueError):
    """A scene the twin cannot be made of; the message says why."""


def medium_coefficients(material):
    """(sigma_a, sigma_s') per Blender unit of a translucent material, or (None, why) when its
    source has no coefficients the twin can use; plus warnings about inputs that are not read."""
    settings = material.subsplat
    unit = settings.mm_per_unit
    if settings.source == "DIPOLE":
        return np.array(settings.sigma_a) * unit, np.array(settings.sigma_s_prime) * unit, []
    if settings.source == "PRINCIPLED":
        node = materials.principled_node(material)
        if node is None:
            return None, "its Principled BSDF source has no Principled BSDF node", []
        try:
            sigma_a, sigma_s, warnings, _key = principled.read(material, node, unit, settings.eta,
                                                               settings.profile_model)
        except principled.PrincipledError as error:
            return None, str(error), []
        sigma_a, sigma_s = sigma_a.reshape(-1, 3), sigma_s.reshape(-1, 3)
        if not (np.all(sigma_a == sigma_a[0]) and np.all(sigma_s == sigma_s[0])):
            return None, ("its Principled BSDF source varies per texel (an image texture): a heterogeneous "
                          "medium the twin does not build"), warnings
        return sigma_a[0].astype(float) * unit, sigma_s[0].astype(float) * unit, warnings
    if settings.source == "SUBEDIT_FILE":
        return None, ("its source is a SubEdit file: scattering profiles, not the absorption and scattering "
                      "coefficients a medium needs"), []
    if settings.source == "ARTIST":
        return None, ("its source is the artist model: a radius and a translucency image, not the absorption "
                      "and scattering coefficients a medium needs"), []
    return None, f"its source '{settings.source}' is not known to the twin", []


def colour_and_density(sigma, absorption):
    """The (colour, density) whose Cycles coefficient is sigma per channel: colour x density for Volume
    Scatter, (1 - colour) x density for Volume Absorption; density is the largest channel."""
    sigma = np.maximum(np.asarray(sigma, dtype=float), 0.0)
    density = float(sigma.max())
    colour = sigma / density if density > 0 else np.zeros(3)
    if absorption:
        colour = 1.0 - colour
    return tuple(float(c) for c in colour), density


def _volume_material(name, sigma_a, sigma_s, eta, roughness):
    material = bpy.data.materials.new(name)
    if not version.BLENDER_5:  # 5.0: always True, and deprecated
        material.use_nodes = True
    if hasattr(material.cycles, "homogeneous_volume"):  # 5.0 has no such setting: Cycles finds out itself
        material.cycles.homogeneous_volume = True
    tree = material.node_tree
    tree.nodes.clear()
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    output.location = (400, 0)
    if eta == 1.0:
        boundary = tree.nodes.new("ShaderNodeBsdfTransparent")
        boundary.inputs["Color"].default_value = (1, 1, 1, 1)
    else:
        boundary = tree.nodes.new("ShaderNodeBsdfGlass")
        boundary.distribution = "SHARP" if roughness == 0.0 else "GGX"
        boundary.inputs["Color"].default_value = (1, 1, 1, 1)
        boundary.inputs["IOR"].default_value = eta
        boundary.inputs["Roughness"].default_value = roughness
    boundary.location = (100, 150)
    scatter = tree.nodes.new("ShaderNodeVolumeScatter")
    colour, density = colour_and_density(sigma_s, absorption=False)
    scatter.inputs["Color"].default_value = (*colour, 1.0)
    scatter.inputs["Density"].default_value = density
    scatter.inputs["Anisotropy"].default_value = 0.0
    scatter.location = (-100, -100)
    absorb = tree.nodes.new("ShaderNodeVolumeAbsorption")
    colour, density = colour_and_density(sigma_a, absorption=True)
    absorb.inputs["Color"].default_value = (*colour, 1.0)
    absorb.inputs["Density"].default_value = density
    absorb.location = (-100, -300)
    add = tree.nodes.new("ShaderNodeAddShader")
    add.location = (100, -150)
    tree.links.new(scatter.outputs[0], add.inputs[0])
    tree.links.new(absorb.outputs[0], add.inputs[1])
    tree.links.new(boundary.outputs[0], output.inputs["Surface"])
    tree.links.new(add.outputs[0], output.inputs["Volume"])
    return material


def _grey_material(name):
    material = bpy.data.materials.new(name)
    if not version.BLENDER_5:  # 5.0: always True, and deprecated
        material.use_nodes = True
    tree = material.node_tree
    tree.nodes.clear()
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*NO_COEFFICIENTS_GREY, 1.0)
    diffuse.location = (-250, 0)
    tree.links.new(diffuse.outputs[0], output.inputs["Surface"])
    return material


def _rendered_objects(scene, view_layer):
    """The objects of the view layer's collections that render (collections not excluded, not
    hidden for render), as a list in a stable order."""
    found = {}

    def walk(layer_collection):
        if layer_collection.exclude or layer_collection.collection.hide_render:
            return
        for obj in layer_collection.collection.objects:
            found.setdefault(obj.name_full, obj)
        for child in layer_collection.children:
            walk(child)
    walk(view_layer.layer_collection)
    return list(found.values())


def _surface(mesh):
    """What the medium's boundary needs from a mesh: {"open": edges without exactly two faces,
    "inconsistent": edges whose two faces run them the same way (their normals disagree about which
    side is inside), "volume": the signed volume the faces enclose (negative: the normals point in)}."""
    if len(mesh.edges) == 0 or len(mesh.polygons) == 0:
        return {"open": 0, "inconsistent": 0, "volume": 0.0}
    loops = len(mesh.loops)
    edge_index = np.empty(loops, dtype=np.int64)
    mesh.loops.foreach_get("edge_index", edge_index)
    vertex = np.empty(loops, dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", vertex)
    start = np.empty(len(mesh.polygons), dtype=np.int64)
    total = np.empty(len(mesh.polygons), dtype=np.int64)
    mesh.polygons.foreach_get("loop_start", start)
    mesh.polygons.foreach_get("loop_total", total)
    # The next corner of each corner in its polygon, and so each corner's directed edge.
    following = np.arange(loops) + 1
    following[start + total - 1] = start
    head = vertex[following]
    open_edges = int(np.count_nonzero(np.bincount(edge_index, minlength=len(mesh.edges)) != 2))
    # Two faces agree about an edge when they run it in opposite directions: the same directed edge
    # twice is a disagreement.
    directed = vertex * (len(mesh.vertices) + 1) + head
    _, counts = np.unique(directed, return_counts=True)
    inconsistent = int(np.count_nonzero(counts > 1))
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    # Each polygon as a fan from its first corner: sum of det(a, b, c) / 6.
    first = np.repeat(vertex[start], total)
    volume = float(np.einsum("ij,ij->i", co[first], np.cross(co[vertex], co[head])).sum() / 6.0)
    return {"open": open_edges, "inconsistent": inconsistent, "volume": volume}


def _surface_of(obj, depsgraph):
    """_surface of the object's evaluated mesh (modifiers applied) when a depsgraph is given, else of
    its mesh. In the object's own space: a mirroring transform does not turn a mesh inside out
    (Blender and Cycles flip its faces back)."""
    if depsgraph is None:
        return _surface(obj.data)
    evaluated = obj.evaluated_get(depsgraph)
    try:
        return _surface(evaluated.to_mesh())
    finally:
        evaluated.to_mesh_clear()


def _remove_twin(name, original):
    old = bpy.data.scenes.get(name)
    if old is None or MARK not in old:
        return False
    for window in bpy.context.window_manager.windows:  # a window showing the old twin shows the original
        if window.scene == old:
            window.scene = original
    for obj in list(old.collection.objects):
        if MARK in obj and obj.users <= 1:
            bpy.data.objects.remove(obj)
    bpy.data.scenes.remove(old)
    for material in list(bpy.data.materials):
        if MARK in material and material.users == 0:
            bpy.data.materials.remove(material)
    return True


def set_cycles_for_convergence(scene):
    """Cycles as the truth needs it: every kind of bounce at 1024, no clamping, no denoising, no
    adaptive sampling or time limit stopping early, no light threshold or glossy filter (both biased),
    caustics on, the Standard view transform."""
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    for bounces in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                    "volume_bounces", "transparent_max_bounces"):
        setattr(cycles, bounces, MAX_BOUNCES)
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.use_denoising = False
    cycles.use_preview_denoising = False
    cycles.use_adaptive_sampling = False
    cycles.use_preview_adaptive_sampling = False
    cycles.time_limit = 0.0
    cycles.light_sampling_threshold = 0.0
    cycles.blur_glossy = 0.0
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    for view_layer in scene.view_layers:
        view_layer.cycles.use_denoising = False
    scene.view_settings.view_transform = "Standard"


def _tint(material, twin_material, reports):
    """A translucent material's tint (an Image Texture into its Principled BSDF's Base Color, when its
    source is not the BSDF; docs/TEXTURES.md) on the twin's boundary: the boundary BSDF's colour is
    sqrt(T) of the same image, read at the same UV map and transform, so that light crossing it in
    and out carries sqrt(T) each way, SubSplat's model. Through a Glass boundary (eta > 1) the light
    reflected inside meets the tint again: said in the reports."""
    if material.subsplat.source == "PRINCIPLED":
        return
    node = materials.principled_node(material)
    if node is None:
        return
    source = textures.linked(node.inputs["Base Color"])
    if source is None or source[0].type != "TEX_IMAGE" or source[0].image is None or source[0].mute:
        return
    image_node = source[0]
    try:
        transform, uv_map = textures.uv_source(material, image_node, None)
    except textures.Unread as unread:
        reports.append(("WARNING", f"material '{material.name}': its tint is not carried to the twin ({unread.reason})"))
        return
    if all(v == 0.0 for v in transform):
        transform = data.IDENTITY_UV
    tree = twin_material.node_tree
    boundary = next(n for n in tree.nodes if n.type in ("BSDF_TRANSPARENT", "BSDF_GLASS"))
    uv = tree.nodes.new("ShaderNodeUVMap")
    uv.uv_map = uv_map or ""
    split = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(uv.outputs["UV"], split.inputs[0])
    combine = tree.nodes.new("ShaderNodeCombineXYZ")
    for row, axis in ((transform[0:3], "X"), (transform[3:6], "Y")):  # a u + b v + c
        inner = tree.nodes.new("ShaderNodeMath")
        inner.operation = "MULTIPLY_ADD"
        tree.links.new(split.outputs["Y"], inner.inputs[0])
        inner.inputs[1].default_value, inner.inputs[2].default_value = row[1], row[2]
        outer = tree.nodes.new("ShaderNodeMath")
        outer.operation = "MULTIPLY_ADD"
        tree.links.new(split.outputs["X"], outer.inputs[0])
        outer.inputs[1].default_value = row[0]
        tree.links.new(inner.outputs[0], outer.inputs[2])
        tree.links.new(outer.outputs[0], combine.inputs[axis])
    image = tree.nodes.new("ShaderNodeTexImage")
    image.image, image.extension = image_node.image, image_node.extension
    image.interpolation = image_node.interpolation
    tree.links.new(combine.outputs[0], image.inputs["Vector"])
    root = tree.nodes.new("ShaderNodeGamma")  # T^0.5 per channel
    root.inputs["Gamma"].default_value = 0.5
    tree.links.new(image.outputs["Color"], root.inputs["Color"])
    tree.links.new(root.outputs["Color"], boundary.inputs["Color"])
    reports.append(("INFO", f"material '{material.name}': its tint '{image_node.image.name}' is the boundary's "
                            "colour, its square root each way in and out"))
    if boundary.type == "BSDF_GLASS":
        reports.append(("WARNING", f"material '{material.name}': its tint is on a Glass boundary (eta > 1), which "
                                   "also tints the light it reflects inside, where SubSplat's tint counts once in "
                                   "and once out"))


def make_cycles_twin(scene, view_layer=None):
    """Makes (or makes again) the scene "<scene.name> Cycles Twin"; returns (twin scene, reports), the
    reports a list of ("INFO" or "WARNING", text). The original scene is not changed. Raises
    TwinError for a scene that is itself a twin."""
    if MARK in scene:
        raise TwinError(f"scene '{scene.name}' is already the Cycles twin of '{scene[MARK]}'")
    if view_layer is None:
        view_layer = scene.view_layers[0]
        if bpy.context.scene == scene and bpy.context.view_layer is not None:
            view_layer = bpy.context.view_layer
    name = scene.name + SUFFIX
    reports = []
    if _remove_twin(name, scene):
        reports.append(("INFO", f"replaced the earlier scene '{name}'"))
    objects = _rendered_objects(scene, view_layer)
    # The evaluated meshes (modifiers applied) where the scene is the context's, else the meshes.
    depsgraph = bpy.context.evaluated_depsgraph_get() if bpy.context.scene == scene else None

    twin = scene.copy()  # the render, colour-management and Cycles settings; the same world and camera
    twin.name = name
    twin[MARK] = scene.name
    for child in list(twin.collection.children):
        twin.collection.children.unlink(child)
    for obj in list(twin.collection.objects):
        twin.collection.objects.unlink(obj)
    set_cycles_for_convergence(twin)

    twin_materials = {}  # original material's name -> its twin material
    refracting = []  # names of the objects whose boundary refracts (eta > 1)

    def twin_material(material):
        if material is None or not material.subsplat.enabled:
            return None
        if material.name_full in twin_materials:
            return twin_materials[material.name_full]
        settings = material.subsplat
        sigma_a, sigma_s, warnings = medium_coefficients(material)
        for warning in warnings:
            reports.append(("WARNING", warning))
        if sigma_a is None:
            made = _grey_material(f"{material.name}{SUFFIX} (no coefficients)")
            reports.append(("WARNING", f"material '{material.name}' is not converted: {sigma_s}; "
                                       f"its objects are opaque grey in the twin"))
        else:
            made = _volume_material(f"{material.name}{SUFFIX}", sigma_a, sigma_s, settings.eta, settings.roughness)
            boundary = ("Transparent BSDF (eta 1)" if settings.eta == 1.0 else
                        f"Glass BSDF (IOR {settings.eta:.4g}, roughness {settings.roughness:.3g})")
            reports.append(("INFO", f"material '{material.name}': sigma_s = "
                                    f"({', '.join(f'{v:.5g}' for v in sigma_s)}), sigma_a = "
                                    f"({', '.join(f'{v:.5g}' for v in sigma_a)}) per unit, {boundary}"))
            made["subsplat_medium"] = {"sigma_a": [float(v) for v in sigma_a],
                                       "sigma_s": [float(v) for v in sigma_s], "eta": float(settings.eta)}
            _tint(material, made, reports)
        made[MARK] = material.name
        twin_materials[material.name_full] = made
        return made

    copies = 0
    for obj in objects:
        replaced = [twin_material(slot.material) for slot in obj.material_slots]
        if not any(m is not None for m in replaced):
            twin.collection.objects.link(obj)
            continue
        copy = obj.copy()  # shares the mesh; its slots are linked to the object from here on
        copy.name = obj.name + SUFFIX
        copy[MARK] = obj.name
        for slot, made in zip(copy.material_slots, replaced):
            if made is not None:
                slot.link = "OBJECT"
                slot.material = made
        twin.collection.objects.link(copy)
        copies += 1
        media = [m for m in replaced if m is not None and "subsplat_medium" in m]
        if any(m["subsplat_medium"]["eta"] > 1.0 for m in media):
            refracting.append(obj.name)
        if media and obj.type == "MESH":
            surface = _surface_of(obj, depsgraph)
            if surface["open"]:
                reports.append(("WARNING", f"object '{obj.name}': its mesh is not closed ({surface['open']} edges "
                                           "without exactly two faces), so the medium inside it is not well "
                                           "defined: Cycles' result may be wrong there"))
            elif surface["inconsistent"]:
                reports.append(("WARNING", f"object '{obj.name}': its faces' normals disagree ({surface['inconsistent']} "
                                           "edges run the same way by both their faces): Cycles enters and leaves "
                                           "the medium by the normals, so light is lost or trapped where they point "
                                           "in (Mesh > Normals > Recalculate Outside fixes it)"))
            elif surface["volume"] < 0:
                reports.append(("WARNING", f"object '{obj.name}': its normals point inwards (the mesh is inside "
                                           "out): Cycles enters and leaves the medium by the normals, so the medium "
                                           "is outside the mesh (Mesh > Normals > Recalculate Outside fixes it)"))

    for obj in objects:
        if obj.instance_type == "COLLECTION" and obj.instance_collection is not None:
            inside = [o.name for o in obj.instance_collection.all_objects
                      if any(slot.material is not None and slot.material.subsplat.enabled for slot in o.material_slots)]
            if inside:
                reports.append(("WARNING", f"'{obj.name}' instances collection '{obj.instance_collection.name}', whose "
                                           f"translucent objects ({', '.join(inside)}) are not converted: the twin "
                                           "renders them with their own node trees"))
        if obj.type == "LIGHT" and not obj.hide_render:
            size = obj.data.angle if obj.data.type == "SUN" else getattr(obj.data, "shadow_soft_size", 0.0)
            if obj.data.type in DELTA_LIGHTS and size > 0.0:
                what = "angle" if obj.data.type == "SUN" else "radius"
                reports.append(("INFO", f"light '{obj.name}' has a {what} of {size:.4g}: Cycles renders it with "
                                        f"it, SubSplat as a {'direction' if what == 'angle' else 'point'}"))

    if refracting:
        for obj in objects:
            if obj.type == "LIGHT" and obj.data.type in DELTA_LIGHTS and not obj.hide_render:
                reports.append(("WARNING", f"{obj.data.type.lower()} light '{obj.name}' does not light the "
                                           f"interior of {', '.join(repr(n) for n in refracting)}: a delta light "
                                           "cannot be connected through a refracting boundary (IOR > 1), so only "
                                           "the world and area lights light their interior (set IOR 1, or use an "
                                           "area light, for a twin that converges)"))
    media = sum(1 for m in twin_materials.values() if "subsplat_medium" in m)
    reports.insert(0, ("INFO", f"made scene '{twin.name}': {len(objects)} object(s), {copies} with translucent "
                               f"materials replaced ({media} material(s) as volumes); Cycles, "
                               f"{twin.cycles.samples} samples, {MAX_BOUNCES} bounces"))
    return twin, reports
