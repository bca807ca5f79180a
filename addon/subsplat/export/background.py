"""The world's Environment Texture as the image's background (data.Environment, C API
ssSetEnvironment; docs/WORLD.md): the map itself where the camera sees no object, turned as the
world's Mapping node turns it, times the Background's strength. Its light is the lights' business
(export/settings.py); this is only what the camera sees of it."""
import collections
import math

import numpy as np

from .. import native, principled
from . import textures
from .data import Environment, ExportError

# Native images of environment maps made so far: image.name_full -> (key, native.Image), at most
# MAX_MAPS (the least recently used dropped first). Unclipped: a map's sun is far above 1.
MAX_MAPS = 4
MAX_RADIANCE = 1e4  # the library's range for a texel
_maps = collections.OrderedDict()


def _native_map(world, image):
    key = textures._image_key(image)
    pixels = None
    if key is None:  # a painted map: its pixels decide
        pixels = principled.image_pixels(image)
        key = ("dirty", pixels.shape, hash(pixels.tobytes()))
    cached = _maps.get(image.name_full)
    if cached is None or cached[0] != key:
        try:
            rgb = principled.image_rgb(image, True, pixels=pixels)
            rgb = np.clip(np.nan_to_num(rgb, nan=0.0, posinf=MAX_RADIANCE, neginf=0.0), 0.0, MAX_RADIANCE)
            cached = _maps[image.name_full] = (key, native.Image(rgb))
        except (principled.PrincipledError, native.SubsplatError) as error:
            raise ExportError(f"world '{world.name}': {error}") from None
    _maps.move_to_end(image.name_full)
    while len(_maps) > MAX_MAPS:
        _maps.popitem(last=False)
    return cached[1]


def _euler(rotation):
    """Blender's XYZ Euler rotation matrix (Rz Ry Rx)."""
    x, y, z = rotation
    cx, sx, cy, sy, cz, sz = math.cos(x), math.sin(x), math.cos(y), math.sin(y), math.cos(z), math.sin(z)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


def _direction_rotation(world, node, warnings):
    """The 3 x 3 matrix the Environment Texture's vector applies to a world direction: the identity
    unlinked (Generated coordinates), else a chain of Mapping nodes' rotations (Point and Vector:
    R; Texture: its inverse) down to a Texture Coordinate's Generated or Object output. None: a set-up
    that is not read (warned)."""
    matrix = np.eye(3)
    source = textures.linked(node.inputs["Vector"])
    while source is not None:
        mapping, _ = source
        if mapping.type == "TEX_COORD" and source[1].name in ("Generated", "Object"):
            return matrix
        if mapping.type != "MAPPING" or mapping.vector_type not in ("POINT", "VECTOR", "TEXTURE"):
            warnings.append(f"world '{world.name}': the Environment Texture's Vector comes from a {mapping.bl_label} "
                            "node, which SubSplat does not read; the background is drawn unturned")
            return np.eye(3)
        rotation = _euler(tuple(mapping.inputs["Rotation"].default_value))
        scale = tuple(mapping.inputs["Scale"].default_value)
        if max(scale) - min(scale) > 1e-6 * max(abs(v) for v in scale) or min(scale) <= 0.0:
            warnings.append(f"world '{world.name}': its Mapping node '{mapping.name}' scales unevenly, which SubSplat "
                            "does not read for the environment; only its rotation is")
        matrix = (rotation.T if mapping.vector_type == "TEXTURE" else rotation) @ matrix
        source = textures.linked(mapping.inputs["Vector"])
    return matrix


def environment(scene, warnings):
    """The world's equirectangular Environment Texture into its Background's Color as the background
    (data.Environment), or None: no world, film transparent, no such texture."""
    from . import settings  # (settings reads the world's light; this module, what the camera sees)
    world = scene.world
    if world is None or scene.render.film_transparent or not getattr(world, "use_nodes", False):
        return None
    node = settings._world_surface(world, [])
    if node is None:
        return None
    source = textures.linked(node.inputs["Color"])
    if source is None or source[0].type != "TEX_ENVIRONMENT" or source[0].image is None:
        return None
    texture = source[0]
    if texture.projection != "EQUIRECTANGULAR":
        warnings.append(f"world '{world.name}': its Environment Texture is a {texture.projection.lower()} "
                        "projection; SubSplat draws equirectangular maps only, and shows the world's mean colour")
        return None
    strength = node.inputs["Strength"]
    if textures.linked(strength) is not None:
        return None  # settings.py warns of the linked strength
    rotation = _direction_rotation(world, texture, warnings)
    return Environment(image=_native_map(world, texture.image),
                       rotation=tuple(float(v) for v in rotation.T.ravel()),  # column-major
                       strength=float(strength.default_value))
