"""Blender materials as plain Material data, and the profile sets of heterogeneous materials."""
import collections
import dataclasses
import hashlib
import os

import bpy
import numpy as np

from .. import artist, native, principled, version
from . import textures
from .data import ExportError, Material

# The profile sets made so far (SubEdit files, Principled BSDFs, the artist model), most recently
# used last: identity -> (inputs key, ProfileSet). The identity is the file for a SubEdit file (the
# materials that use one file share its set) and the material for the others; a set is made again
# only when its inputs key changed. Sets beyond MAX_PROFILE_SETS, least recently used first, are
# released (a frame that uses one keeps it alive through its Material). A scene with more
# heterogeneous materials than that makes some sets again each frame: same images, slower export.
MAX_PROFILE_SETS = 64
_profile_sets = collections.OrderedDict()


def _cached(identity, key, make):
    """The cached set of identity if its inputs key is key, else make()'s, stored under it."""
    cached = _profile_sets.get(identity)
    if cached is not None and cached[0] == key:
        _profile_sets.move_to_end(identity)
        return cached[1]
    profiles = make()
    _profile_sets[identity] = (key, profiles)
    _profile_sets.move_to_end(identity)
    while len(_profile_sets) > MAX_PROFILE_SETS:
        _profile_sets.popitem(last=False)
    return profiles


def cached_profile_sets():
    """How many profile sets the cache holds now (tests)."""
    return len(_profile_sets)


def principled_node(material):
    if not version.uses_nodes(material):
        return None
    for node in material.node_tree.nodes:
        if node.type == "OUTPUT_MATERIAL" and node.is_active_output:
            link = node.inputs["Surface"].links
            if link and link[0].from_node.type == "BSDF_PRINCIPLED":
                return link[0].from_node
    return next((n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED"), None)


def _native_profiles(material, make):
    try:
        return make()
    except native.SubsplatError as error:
        raise ExportError(f"material '{material.name}': {error}") from None


def subedit_file_profiles(material):
    """The ProfileSet of a SUBEDIT_FILE material, read again only when the file changed on disk or
    the tolerance changed; ExportError names the material and the file."""
    settings = material.subsplat
    if not settings.subedit_path:
        raise ExportError(f"material '{material.name}': no SubEdit file is set (Material > Translucency > File)")
    path = os.path.normpath(bpy.path.abspath(settings.subedit_path, library=material.library))
    try:
        status = os.stat(path)
    except OSError:
        raise ExportError(f"material '{material.name}': SubEdit file '{path}' does not exist") from None
    key = (status.st_mtime_ns, status.st_size, settings.fit_tolerance)
    return _cached(("SUBEDIT_FILE", path), key, lambda: _native_profiles(
        material, lambda: native.ProfileSet.load(path, settings.fit_tolerance)))


def principled_coefficients(material, warnings=None):
    """The per-texel coefficients of a PRINCIPLED material under its profile model: (sigma_a,
    sigma_s_prime, key), each (height, width, 3) per mm."""
    settings = material.subsplat
    node = principled_node(material)
    if node is None:
        raise ExportError(f"material '{material.name}': the Principled BSDF source needs a Principled BSDF node")
    try:
        sigma_a, sigma_s, notes, key = principled.read(material, node, settings.mm_per_unit, settings.eta,
                                                       settings.profile_model)
    except principled.PrincipledError as error:
        raise ExportError(str(error)) from None
    if warnings is not None:
        warnings.extend(notes)
    return sigma_a, sigma_s, key


def uniform(sigma_a, sigma_s):
    """Whether every texel holds the same medium (a Principled BSDF with no texture)."""
    return bool(np.all(sigma_a == sigma_a.reshape(-1, 3)[0]) and np.all(sigma_s == sigma_s.reshape(-1, 3)[0]))


def principled_profiles(material, warnings=None, coefficients=None):
    """The ProfileSet of a PRINCIPLED material, made again only when its inputs changed
    (coefficients: principled_coefficients' answer, when the caller has it)."""
    settings = material.subsplat
    sigma_a, sigma_s, key = coefficients or principled_coefficients(material, warnings)
    key = (key, settings.fit_tolerance, settings.mm_per_unit)
    return _cached(("PRINCIPLED", material.name_full), key, lambda: _native_profiles(
        material, lambda: native.ProfileSet.from_dipoles(sigma_a, sigma_s, settings.eta, settings.fit_tolerance,
                                                         settings.profile_model)))


def artist_profiles(material):
    """The ProfileSet of an ARTIST material, made again only when its inputs changed."""
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
    return _cached(("ARTIST", material.name_full), key, lambda: _native_profiles(
        material, lambda: native.ProfileSet.from_profiles(log_profiles, radius_mm, settings.fit_tolerance)))


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
    return _native_profiles(material, lambda: native.ProfileSet.from_dipoles(
        sigma_a, sigma_s_prime, settings.eta, settings.fit_tolerance, settings.profile_model))


# Blender's material without a material slot: light grey, half rough.
DEFAULT_MATERIAL = Material(kind="OPAQUE", base_color=(0.8, 0.8, 0.8), roughness=0.5, specular=0.5)


def unread_inputs(material, node, names, warnings):
    """Warns, one line a socket, of the Principled BSDF's inputs among `names` that are connected to
    a node SubSplat does not read (a texture into Roughness, a Bump node into Normal): they render as
    the socket's own value, or not at all, and the artist is told."""
    if node is None or warnings is None:
        return
    for name in names:
        socket = node.inputs.get(name)
        if socket is not None and textures.linked(socket) is not None:
            _warn_unread(material, socket, None, warnings)


def _warn_unread(material, socket, reason, warnings):
    """The one-line warning of a socket whose link SubSplat does not read; reason: why, or None."""
    if warnings is None:
        return
    source = textures.linked(socket)[0]
    what = "its own value" if socket.name != "Normal" else "the mesh's shading normal"
    because = f" ({reason})" if reason else ""
    warnings.append(f"material '{material.name}': {socket.name} is connected to a {source.bl_label} node, "
                    f"which SubSplat does not read{because}; it renders {what}")


def read_textures(material, node, data, colour, warnings):
    """Sets data's textures from the Principled BSDF `node` (docs/TEXTURES.md): with colour, an
    Image Texture into Base Color (OPAQUE: the albedo, base_color then white; translucent: the
    tint); a Normal Map of an Image Texture into Normal. Other links into them are warned."""
    if node is None:
        return
    uv_maps = []
    if colour:
        socket = node.inputs["Base Color"]
        try:
            found = textures.image_texture(material, socket, warnings)
        except textures.Unread as unread:
            _warn_unread(material, socket, unread.reason, warnings)
        else:
            if found is not None:
                data.color_texture, uv_map = found
                uv_maps.append(uv_map)
                if data.kind == "OPAQUE":
                    data.base_color = (1.0, 1.0, 1.0)
    socket = node.inputs["Normal"]
    try:
        found = textures.normal_map(material, socket, warnings)
    except textures.Unread as unread:
        _warn_unread(material, socket, unread.reason, warnings)
    else:
        if found is not None:
            data.normal_texture, data.normal_strength, maps = found
            uv_maps.extend(maps)
    data.uv_maps = tuple(dict.fromkeys(uv_maps))  # each once, in the order met (export.mesh chooses)


def material_data(material, warnings=None):
    """The Material data of a Blender material (None: the default grey).

    A SUBEDIT Material holds its ProfileSet (this module's cache keeps it too), a textured one its
    native Images (export.textures keeps them too). Warnings about the material (inputs that are not
    read) are appended to `warnings`.
    """
    if material is None:
        return dataclasses.replace(DEFAULT_MATERIAL)
    settings = material.subsplat
    if settings.enabled:
        data = translucent_data(material, warnings)
        # A source other than the BSDF does not take its colour: an image there is a tint. (4.x's
        # PRINCIPLED source reads Base Color as its albedo, principled.py.)
        node = principled_node(material)
        read_textures(material, node, data, settings.source != "PRINCIPLED", warnings)
        if (settings.source == "PRINCIPLED" and principled.COLOR_INPUT != "Base Color" and node is not None
                and warnings is not None and textures.linked(node.inputs["Base Color"]) is not None):
            warnings.append(f"material '{material.name}': Base Color is connected to a "
                            f"{textures.linked(node.inputs['Base Color'])[0].bl_label} node, which SubSplat does "
                            f"not read: its Principled BSDF source takes the colour from {principled.COLOR_INPUT}")
        return data
    node = principled_node(material)
    if node is not None:
        data = Material(kind="OPAQUE", base_color=tuple(node.inputs["Base Color"].default_value[:3]),
                        roughness=node.inputs["Roughness"].default_value,
                        specular=min(max(node.inputs[version.PRINCIPLED_SPECULAR].default_value, 0.0), 1.0))
        read_textures(material, node, data, True, warnings)
        unread_inputs(material, node, ("Roughness", version.PRINCIPLED_SPECULAR), warnings)
        return data
    return Material(kind="OPAQUE", base_color=tuple(material.diffuse_color[:3]), roughness=material.roughness,
                    specular=material.specular_intensity)


def translucent_data(material, warnings=None):
    """The Material data of a translucent material (material.subsplat.enabled), without textures."""
    settings = material.subsplat
    data = Material(kind="DIPOLE", sigma_a=tuple(settings.sigma_a), sigma_s_prime=tuple(settings.sigma_s_prime),
                    eta=settings.eta, mm_per_unit=settings.mm_per_unit, roughness=settings.roughness,
                    specular=settings.specular, profile_model=settings.profile_model)
    if settings.source == "PRINCIPLED" and settings.profile_model == "TABULATED":
        # An untextured BSDF is one medium: rendered as such, the model's angular and thin-part
        # factors apply (a profile set keeps radial profiles alone).
        coefficients = principled_coefficients(material, warnings)
        sigma_a, sigma_s, _key = coefficients
        if uniform(sigma_a, sigma_s):
            data.sigma_a = tuple(float(v) for v in sigma_a.reshape(-1, 3)[0])
            data.sigma_s_prime = tuple(float(v) for v in sigma_s.reshape(-1, 3)[0])
            return data
        data.kind, data.profiles = "SUBEDIT", principled_profiles(material, None, coefficients)
        if warnings is not None:
            warnings.append(f"material '{material.name}': its textured Principled BSDF varies the medium per "
                            "texel, which SubSplat renders with the TABULATED model's radial profiles alone: "
                            "without its angular and thin-part factors (those of one medium; docs/TRANSPORT.md)")
        return data
    profiles = source_profiles(material, warnings)
    if profiles is not None:
        data.kind = "SUBEDIT"
        data.profiles = profiles
    return data
