"""The world's Environment Texture (or Sky Texture, export/sky.py) as the image's background (data.Environment, C API
ssSetEnvironment; docs/WORLD.md): the map itself where the camera sees no object, turned as the
world's Mapping node turns it, times the Background's strength. Its light is the lights' business
(export/settings.py); this is only what the camera sees of it."""
import collections

import numpy as np

from .. import native, principled
from . import environment as environment_light, settings, sky, textures
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


def _native_sky(world, node):
    key = sky.key(node)
    cached = _maps.get(key)
    if cached is None:
        try:
            rgb = np.clip(sky.sky_map(node), 0.0, MAX_RADIANCE)
            cached = _maps[key] = (key, native.Image(rgb))
        except native.SubsplatError as error:
            raise ExportError(f"world '{world.name}': its Sky Texture: {error}") from None
    _maps.move_to_end(key)
    while len(_maps) > MAX_MAPS:
        _maps.popitem(last=False)
    return cached[1]


def environment(scene, warnings):
    """The world's equirectangular Environment Texture into its Background's Color as the background
    (data.Environment), or None: no world, film transparent, no such texture."""
    world = scene.world
    if world is None or scene.render.film_transparent or not getattr(world, "use_nodes", False):
        return None
    node = settings._world_surface(world, [])
    if node is None:
        return None
    source = textures.linked(node.inputs["Color"])
    if source is not None and sky.is_drawn(source[0]):
        texture, image = source[0], _native_sky(world, source[0])
    elif source is None or source[0].type != "TEX_ENVIRONMENT" or source[0].image is None:
        return None
    else:
        texture, image = source[0], None
    if texture.type == "TEX_ENVIRONMENT" and texture.projection != "EQUIRECTANGULAR":
        warnings.append(f"world '{world.name}': its Environment Texture is a {texture.projection.lower()} "
                        "projection; SubSplat draws equirectangular maps only, and shows the world's mean colour")
        return None
    strength = node.inputs["Strength"]
    if textures.linked(strength) is not None:
        return None  # settings.py warns of the linked strength
    # The Mapping nodes as the light reads them (export/environment.py, which also warns of what it
    # does not read: said once, there).
    rotation = environment_light.texture_lookup(texture, f"world '{world.name}'", [])
    rotation = np.eye(3) if rotation is None else rotation
    return Environment(image=image if image is not None else _native_map(world, texture.image),
                       rotation=tuple(float(v) for v in rotation.T.ravel()),  # column-major
                       strength=float(strength.default_value))
