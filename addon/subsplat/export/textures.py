"""Image textures of materials as Texture data (docs/TEXTURES.md): which node set-ups are read, the
2 x 3 map of UVs they make, and the images' pixels as native Images, kept across frames.

Read: an Image Texture node (Flat projection) whose Color output feeds the socket, through reroutes;
its Vector input unlinked (the mesh's UVs), or a UV Map node, or a Texture Coordinate node's UV
output, through any number of Mapping nodes (Point, Texture or Vector; their unlinked Location,
Rotation about z and Scale). A Normal Map node in Tangent Space whose Color is such a texture is a
normal map. Anything else raises Unread, which the caller turns into its one-line warning.
"""
import collections
import hashlib
import math
import os

import bpy
import numpy as np

from .. import native, principled
from .data import IDENTITY_UV, ExportError, Texture

INTERPOLATIONS = {"Linear": "LINEAR", "Closest": "CLOSEST"}  # Cubic and Smart: LINEAR, warned
EXTENSIONS = {"REPEAT", "EXTEND", "CLIP"}                     # MIRROR (4.x): REPEAT, warned
MAX_NORMAL_STRENGTH = 10.0                                     # the Normal Map node's Strength range

# Native Images made so far, most recently used last: image.name_full -> (key, native.Image, texels).
# An image is read again only when its key changed (_image_key). Beyond MAX_IMAGES images or
# MAX_CACHED_TEXELS texels in all, the least recently used are dropped (a frame that uses one keeps
# it alive through its Material); the most recent is always kept.
MAX_IMAGES = 64
MAX_CACHED_TEXELS = 1 << 26  # 67 M texels: 0.8 GB of float RGB
_images = collections.OrderedDict()


class Unread(Exception):
    """A set-up SubSplat does not read; reason: why, in words (None: the node feeding the socket is
    not a texture at all)."""

    def __init__(self, reason=None):
        super().__init__(reason)
        self.reason = reason


def cached_images():
    """How many native Images the cache holds now (tests)."""
    return len(_images)


def linked(socket):
    """(node, output socket) feeding an input socket, through reroutes; None when nothing does (no
    link, or a muted one: Blender then uses the socket's own value)."""
    while socket.is_linked:
        link = socket.links[0]
        if getattr(link, "is_muted", False) or not link.is_valid:
            return None
        if link.from_node.type != "REROUTE":
            return link.from_node, link.from_socket
        socket = link.from_node.inputs[0]
    return None


def _enum_name(node, prop):
    """The UI name of an enum property's value ("Object Space" for space OBJECT)."""
    return node.bl_rna.properties[prop].enum_items[getattr(node, prop)].name


# -- UVs --------------------------------------------------------------------------------------

def _compose(outer, inner):
    """The 2 x 3 affine map outer(inner(uv))."""
    a = np.array(outer, dtype=np.float64).reshape(2, 3)
    b = np.vstack([np.array(inner, dtype=np.float64).reshape(2, 3), [0.0, 0.0, 1.0]])
    return tuple(float(v) for v in (a @ b).ravel())


def _socket_value(material, node, name, warnings):
    socket = node.inputs[name]
    if linked(socket) is not None and warnings is not None:
        warnings.append(f"material '{material.name}': the {node.bl_label} node '{node.name}' has its {name} "
                        "connected to a node, which SubSplat does not read; using the socket's own value")
    return tuple(float(v) for v in socket.default_value)


def mapping_transform(material, node, warnings):
    """The 2 x 3 map of a Mapping node on UVs (w = 0), from Blender's own formulas (Cycles'
    svm_mapping): Point v' = R (S v) + L, Vector v' = R (S v), Texture v' = S^-1 R^T (v - L) (the
    inverse of Point; a zero scale divides to 0, as safe_divide). R is the Euler rotation; only its
    z angle turns UVs within their plane: x and y are warned and left out. Normal raises Unread."""
    kind = node.vector_type
    if kind == "NORMAL":
        raise Unread(f"the Mapping node '{node.name}' is of type Normal")
    location = _socket_value(material, node, "Location", warnings) if kind != "VECTOR" else (0.0, 0.0, 0.0)
    rotation = _socket_value(material, node, "Rotation", warnings)
    scale = _socket_value(material, node, "Scale", warnings)
    if (abs(rotation[0]) > 1e-6 or abs(rotation[1]) > 1e-6) and warnings is not None:
        warnings.append(f"material '{material.name}': the Mapping node '{node.name}' rotates about x or y, which "
                        "SubSplat does not read on UVs; only its rotation about z is rendered")
    c, s = math.cos(rotation[2]), math.sin(rotation[2])
    sx, sy = scale[0], scale[1]
    if kind in ("POINT", "VECTOR"):  # R S, then + L
        return (c * sx, -s * sy, location[0], s * sx, c * sy, location[1])
    # TEXTURE: S^-1 R^T (v - L)
    ix = 1.0 / sx if sx != 0.0 else 0.0
    iy = 1.0 / sy if sy != 0.0 else 0.0
    a = (c * ix, s * ix, -s * iy, c * iy)
    return (a[0], a[1], -(a[0] * location[0] + a[1] * location[1]),
            a[2], a[3], -(a[2] * location[0] + a[3] * location[1]))


def uv_source(material, texture_node, warnings):
    """(transform, uv map) of an Image Texture node's Vector input: the 2 x 3 map of the Mapping
    nodes on the way, and the UV map read ("" : the mesh's render UV map)."""
    transform = IDENTITY_UV
    source = linked(texture_node.inputs["Vector"])
    while source is not None:
        node, output = source
        if node.type == "MAPPING":
            if not node.mute:
                transform = _compose(transform, mapping_transform(material, node, warnings))
            source = linked(node.inputs["Vector"])
            if source is None:  # Blender reads the Mapping node's own Vector value, not the UVs
                raise Unread(f"the Mapping node '{node.name}' has no Vector input")
            continue
        if node.type == "UVMAP" and not node.mute and not node.from_instancer:
            return transform, node.uv_map
        if node.type == "TEX_COORD" and output.name == "UV" and not node.mute and not node.from_instancer:
            return transform, ""
        what = f"a {node.bl_label} node's {output.name} output" if len(node.outputs) > 1 else f"a {node.bl_label} node"
        raise Unread(f"the Image Texture node '{texture_node.name}' reads its Vector from {what}; SubSplat reads "
                     "UVs (a UV Map node, a Texture Coordinate node's UV) through Mapping nodes")
    return transform, ""


# -- textures ---------------------------------------------------------------------------------

def image_texture(material, socket, warnings):
    """(Texture, uv map) of the Image Texture node whose Color output feeds `socket`, or None when
    the socket is not linked; Unread for any other set-up."""
    source = linked(socket)
    if source is None:
        return None
    node, output = source
    if node.type != "TEX_IMAGE":
        raise Unread()
    name = f"the Image Texture node '{node.name}'"
    if node.mute:
        raise Unread(f"{name} is muted")
    if output.name != "Color":
        raise Unread(f"{name}'s {output.name} output is connected, not its Color")
    if node.image is None:
        raise Unread(f"{name} has no image")
    if node.projection != "FLAT":
        raise Unread(f"{name} has {_enum_name(node, 'projection')} projection; SubSplat reads Flat")
    transform, uv_map = uv_source(material, node, warnings)
    interpolation = INTERPOLATIONS.get(node.interpolation, "LINEAR")
    if node.interpolation not in INTERPOLATIONS and warnings is not None:
        warnings.append(f"material '{material.name}': {name} interpolates {node.interpolation}, which SubSplat "
                        "renders as Linear")
    extension = node.extension if node.extension in EXTENSIONS else "REPEAT"
    if node.extension not in EXTENSIONS and warnings is not None:
        warnings.append(f"material '{material.name}': {name} extends its image by {_enum_name(node, 'extension')}, "
                        "which SubSplat renders as Repeat")
    if all(v == 0.0 for v in transform):  # all six 0 means the identity to the library: read (0, 0)
        transform = (0.0, 0.0, 0.0, 0.0, 0.0, 1e-30)
    image = native_image(material, node.image, warnings)
    return Texture(image, transform, extension, interpolation), uv_map


def normal_map(material, socket, warnings):
    """(Texture, strength, uv maps) of a Normal Map node in Tangent Space feeding `socket` whose
    Color is an Image Texture (image_texture), or None when the socket is not linked or the
    Strength is 0 (the mesh's own normal); Unread for any other set-up."""
    source = linked(socket)
    if source is None:
        return None
    node, _output = source
    if node.type != "NORMAL_MAP":
        raise Unread()
    if node.mute:
        raise Unread(f"the Normal Map node '{node.name}' is muted")
    if node.space != "TANGENT":
        raise Unread(f"its space is {_enum_name(node, 'space')}; SubSplat reads Tangent Space normal maps")
    colour = linked(node.inputs["Color"])
    if colour is None:
        raise Unread("its Color is not connected to an Image Texture node")
    try:
        found = image_texture(material, node.inputs["Color"], warnings)
    except Unread as unread:
        raise Unread(unread.reason or f"its Color is connected to a {colour[0].bl_label} node, not an "
                     "Image Texture") from None
    strength_socket = node.inputs["Strength"]
    if linked(strength_socket) is not None and warnings is not None:
        warnings.append(f"material '{material.name}': the Normal Map node '{node.name}' has its Strength connected "
                        "to a node, which SubSplat does not read; using the socket's own value")
    strength = min(max(float(strength_socket.default_value), 0.0), MAX_NORMAL_STRENGTH)
    if strength == 0.0:  # Blender renders the mesh's normal; the library would read 0 as 1
        return None
    texture, uv_map = found
    # The tangent frame is the Normal Map node's UV map's; the image is read through its own.
    return texture, strength, (node.uv_map, uv_map)


# -- images -----------------------------------------------------------------------------------

def _image_key(image):
    """What an image's pixels depend on, short of reading them: its size, source, file (path, time
    and size on disk, packed data), colour space, generated settings. None for an image whose pixels
    must be read to know (a painted, dirty one): its key then includes their digest."""
    if image.is_dirty:
        return None
    key = [tuple(image.size), image.channels, image.source, image.filepath_raw, image.colorspace_settings.name,
           image.is_float]
    if image.packed_file is not None:
        key.append(("packed", image.packed_file.size, image.packed_file.as_pointer()))
    elif image.source in ("FILE", "SEQUENCE", "MOVIE", "TILED"):
        try:
            status = os.stat(bpy.path.abspath(image.filepath, library=image.library))
            key.append((status.st_mtime_ns, status.st_size))
        except (OSError, ValueError):
            key.append(None)
    if image.source == "GENERATED":
        key.append((image.generated_type, tuple(image.generated_color), image.generated_width,
                    image.generated_height, image.use_generated_float))
    return tuple(key)


def native_image(material, image, warnings):
    """The native Image of a Blender image: its RGB as Blender's shaders read it (an sRGB byte image
    made linear; float images are linear already; data as stored), clipped to [0, 1]. Read and
    converted again only when the image changed; ExportError names the material and the image.
    What the conversion changed (clipped values, a colour space read as linear) is warned each time
    the image is used."""
    key = _image_key(image)
    pixels = None
    if key is None:
        try:
            pixels = principled.image_pixels(image)
        except principled.PrincipledError as error:
            raise ExportError(f"material '{material.name}': {error}") from None
        key = ("dirty", pixels.shape, image.colorspace_settings.name, image.is_float,
               hashlib.sha1(pixels.data).hexdigest())  # a change detector, 3x blake2b's speed here
    cached = _images.get(image.name_full)
    if cached is None or cached[0] != key:
        cached = _images[image.name_full] = (key, *_convert(material, image, pixels))
    _images.move_to_end(image.name_full)
    while len(_images) > 1 and (len(_images) > MAX_IMAGES or
                                sum(entry[2] for entry in _images.values()) > MAX_CACHED_TEXELS):
        _images.popitem(last=False)
    if warnings is not None:
        warnings.extend(f"material '{material.name}': image '{image.name}' {note}" for note in cached[3])
    return cached[1]


# Colour spaces whose byte values are read as stored: data, and linear Rec.709 (3.x and 4.x names).
STORED_AS_READ = {"Non-Color", "Raw", "Linear", "Linear Rec.709"}


def _convert(material, image, pixels):
    """(native.Image, texels, notes) of an image (pixels: principled.image_pixels(image), or None)."""
    notes = []
    try:
        rgb = principled.image_rgb(image, True, pixels=pixels)
    except principled.PrincipledError as error:
        raise ExportError(f"material '{material.name}': {error}") from None
    if image.is_float:
        if not np.all(np.isfinite(rgb)) or rgb.min() < 0.0 or rgb.max() > 1.0:
            notes.append("has values outside [0, 1], which SubSplat clips (colours, tints and normal maps are "
                         "read in [0, 1])")
            rgb = np.clip(np.nan_to_num(rgb, nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
    elif not principled.converts_from_srgb(image) and image.colorspace_settings.name not in STORED_AS_READ:
        notes.append(f"is in the colour space {image.colorspace_settings.name}, which SubSplat reads as linear")
    if image.source in ("SEQUENCE", "MOVIE", "TILED"):
        notes.append(f"is a {image.source.lower()} image, of which SubSplat reads one picture (the first tile, "
                     "or the frame Blender holds)")
    try:
        made = native.Image(rgb)
    except native.SubsplatError as error:
        raise ExportError(f"material '{material.name}': image '{image.name}': {error}") from None
    return made, rgb.shape[0] * rgb.shape[1], tuple(notes)
