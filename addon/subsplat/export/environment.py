"""An equirectangular environment map as the lights SubSplat renders (docs/WORLD.md, "Environment
textures"): a few suns from its brightest regions, found by a median-cut split of the map
(Debevec 2005, "A Median Cut Algorithm for Light Probe Sampling"), and the rest of its light as the
WORLD light's spherical harmonics to order 2.

`decompose` is numpy on the whole map and knows nothing of Blender (bench/environment.py calibrates
it on generated maps); `texture_lookup` reads the Mapping nodes on the texture's vector, and
`image_decomposition` keeps the results per image and lookup, so that viewport redraws do not redo
them."""
import collections
import math
from dataclasses import dataclass
from typing import Tuple

import numpy as np

# Rec. 709 luminance of linear RGB (Blender's default scene-linear space).
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])

# The rule and its constants (docs/WORLD.md, "Environment textures"), calibrated by
# bench/environment.py on generated maps 1-5 and tested on the others.
MAX_HEIGHT = 256               # the map is averaged down to at most 2 MAX_HEIGHT x MAX_HEIGHT texels
BRIGHT_FACTOR = 6.0            # texels brighter than this x the map's mean luminance make its bright part
SPLIT_ANGLE = math.radians(45.0)  # a region whose light spreads wider than this (diameter) is split
SPLIT_SHARE = 0.005            # ... when it holds at least this share of the map's light
MAX_SUNS = 16
MAX_SUN_ANGLE = math.pi / 2    # the library's largest sun diameter (SsLightDesc.soft_size)

Vector3 = Tuple[float, float, float]


@dataclass
class Sun:
    """A region of the map as a sun: the unit direction towards it (world), the irradiance a surface
    facing it gets from the region (RGB, W/m^2 per unit strength), and its angular diameter."""
    direction: Vector3
    irradiance: Vector3
    angle: float


@dataclass
class Decomposition:
    """suns; above, below: the remainder's radiance above the horizon and below it (RGB per unit
    strength), such that a surface facing up (down) gets the map's irradiance; sun_share: the share
    of the map's light (luminance x solid angle) the suns took; harmonics: the rest's radiance to
    order 2 (what the library draws; above and below are then its fallback)."""
    suns: list
    above: Vector3
    below: Vector3
    sun_share: float = 0.0
    harmonics: tuple = ()  # the rest's radiance as 9 RGB spherical harmonics (SsLightDesc.world_sh), or ()


def average_down(rgb, max_height=MAX_HEIGHT):
    """An equirectangular map (h, w, 3), row 0 at the bottom, averaged over blocks of f x f texels
    (each texel weighted by its solid angle) to at most max_height rows and 2 max_height columns:
    (values, latitude edges (rows + 1), u edges (columns + 1)). The light it holds is unchanged."""
    h, w = rgb.shape[:2]
    lat_edges = (np.arange(h + 1) / h - 0.5) * np.pi
    u_edges = np.arange(w + 1) / w
    f = max(1, -(-h // max_height), -(-w // (2 * max_height)))
    if f == 1:
        return np.asarray(rgb, dtype=np.float64), lat_edges, u_edges
    row_weight = np.diff(np.sin(lat_edges))  # a row's solid angle per unit of longitude
    rows, cols = np.arange(0, h, f), np.arange(0, w, f)
    weighted = np.asarray(rgb, dtype=np.float32) * row_weight[:, None, None].astype(np.float32)
    sums = np.add.reduceat(np.add.reduceat(weighted, rows, axis=0), cols, axis=1).astype(np.float64)
    block = np.add.reduceat(row_weight, rows)[:, None] * np.diff(np.append(cols, w))[None, :]
    return sums / block[..., None], lat_edges[np.append(rows, h)], u_edges[np.append(cols, w)]


def texels(lat_edges, u_edges):
    """Each texel's solid angle (rows, columns) and the integral of the direction over it (rows,
    columns, 3; its length is the solid angle times the mean resultant length), exactly, in Cycles'
    convention: u = atan2(-y, x) / 2 pi + 1/2 (+x at the map's middle, +y at a quarter),
    v = latitude / pi + 1/2. A sum of radiance times the moment's component along a normal is the
    irradiance, exact for texels wholly in front of the surface."""
    sin_lat, phi = np.sin(lat_edges), np.pi * (1.0 - 2.0 * u_edges)  # phi falls as u rises
    solid_angle = np.diff(sin_lat)[:, None] * -np.diff(phi)[None, :]
    cos_squared = np.diff(0.5 * lat_edges + 0.25 * np.sin(2.0 * lat_edges))  # integral of cos^2 lat
    moments = np.stack(np.broadcast_arrays(cos_squared[:, None] * -np.diff(np.sin(phi))[None, :],
                                           cos_squared[:, None] * np.diff(np.cos(phi))[None, :],
                                           (0.5 * np.diff(sin_lat ** 2))[:, None] * -np.diff(phi)[None, :]), axis=-1)
    return solid_angle, moments


def centres(lat_edges, u_edges):
    """The unit direction of each texel's centre (rows, columns, 3), in texels' convention."""
    lat = 0.5 * (lat_edges[1:] + lat_edges[:-1])
    phi = np.pi * (1.0 - (u_edges[1:] + u_edges[:-1]))
    cos_lat = np.cos(lat)[:, None]
    return np.stack(np.broadcast_arrays(cos_lat * np.cos(phi)[None, :], cos_lat * np.sin(phi)[None, :],
                                        np.sin(lat)[:, None]), axis=-1)


class _Regions:
    """The median cut of the bright part (its luminance `radiance`, zero elsewhere; its light,
    radiance x solid angle, is `energy`): rectangles of texels (r0, r1, c0, c1), half-open, each
    shrunk to the texels with light."""

    def __init__(self, radiance, solid_angle, moments, lat_edges, u_edges):
        self.energy = radiance * solid_angle
        self.radiance, self.moments = radiance, moments
        self.lat_edges, self.u_edges = lat_edges, u_edges

    def bounds(self, r0, r1, c0, c1):
        """The region shrunk to its texels with light, or None."""
        lit = self.energy[r0:r1, c0:c1] > 0
        rows, cols = np.flatnonzero(lit.any(axis=1)), np.flatnonzero(lit.any(axis=0))
        if rows.size == 0:
            return None
        return (r0 + rows[0], r0 + rows[-1] + 1, c0 + cols[0], c0 + cols[-1] + 1)

    def stats(self, region):
        """(light, unit centroid direction, angular diameter): the light's mean direction m (its
        length, the mean resultant length, falls as the light spreads) and the diameter of the cap
        of uniform light with the same |m| = (1 + cos r) / 2."""
        r0, r1, c0, c1 = region
        power = float(self.energy[r0:r1, c0:c1].sum())
        mean = np.einsum("ij,ijk->k", self.radiance[r0:r1, c0:c1], self.moments[r0:r1, c0:c1]) / power
        length = float(np.linalg.norm(mean))
        return power, mean / max(length, 1e-30), 2.0 * math.acos(min(max(2.0 * length - 1.0, -1.0), 1.0))

    def split(self, region):
        """The region cut across its longer side (in angle) where its light is halved, or None when it
        is one texel."""
        r0, r1, c0, c1 = region
        lat = self.lat_edges[r0:r1 + 1]
        widest = 1.0 if lat[0] <= 0.0 <= lat[-1] else max(math.cos(lat[0]), math.cos(lat[-1]))
        height = lat[-1] - lat[0]
        width = 2.0 * np.pi * (self.u_edges[c1] - self.u_edges[c0]) * widest
        across_rows = (height >= width and r1 - r0 > 1) or c1 - c0 == 1
        if r1 - r0 == 1 and c1 - c0 == 1:
            return None
        e = self.energy[r0:r1, c0:c1]
        profile = np.cumsum(e.sum(axis=1) if across_rows else e.sum(axis=0))
        cut = int(np.searchsorted(profile, 0.5 * profile[-1])) + 1
        cut = min(max(cut, 1), profile.size - 1)
        if across_rows:
            halves = ((r0, r0 + cut, c0, c1), (r0 + cut, r1, c0, c1))
        else:
            halves = ((r0, r1, c0, c0 + cut), (r0, r1, c0 + cut, c1))
        return [b for b in (self.bounds(*h) for h in halves) if b is not None]


def decompose(rgb, lookup=None, **constants):
    """An equirectangular map (h, w, 3 linear RGB radiance, row 0 at the bottom) as a Decomposition
    (decompose_grid), averaged down first to at most MAX_HEIGHT rows."""
    return decompose_grid(*average_down(rgb), lookup=lookup, **constants)


def decompose_grid(values, lat_edges, u_edges, lookup=None, bright_factor=BRIGHT_FACTOR, split_angle=SPLIT_ANGLE,
                   split_share=SPLIT_SHARE, max_suns=MAX_SUNS):
    """A map of texels bounded by lat_edges and u_edges (average_down) as a Decomposition.
    lookup: the 3 x 3 matrix M by which the texture is looked up (the map's direction m = M d for
    the world's direction d; a rotation), or None.

    1. The bright part: the texels whose luminance is above bright_factor x the map's mean.
    2. Its regions: one around all of it; then, while there are fewer than max_suns, the region
       with the most light among those whose light spreads wider than split_angle and holds at
       least split_share of the map's light is cut in two where its light is halved, across its
       longer side (a median cut).
    3. Each region is a sun at its light's centroid, its diameter the spread of its light, its
       irradiance what a surface facing it gets from the region.
    4. The rest: the radiance above (below) the horizon that gives a surface facing up (down) the
       map's irradiance, less the suns'; and the texels outside the bright part as spherical
       harmonics to order 2, with those same irradiances facing up and down (horizontal_exact)."""
    solid_angle, moments = texels(lat_edges, u_edges)
    if lookup is not None:
        moments = moments @ np.asarray(lookup, dtype=np.float64)  # d = M^T m, as rows
    luminance = values @ LUMINANCE
    light = luminance * solid_angle
    total = float(light.sum())
    up = np.einsum("ijk,ij->k", values, np.maximum(moments[..., 2], 0.0))
    down = np.einsum("ijk,ij->k", values, np.maximum(-moments[..., 2], 0.0))
    suns, taken = [], 0.0
    if total > 0.0 and np.isfinite(total):
        bright = luminance > bright_factor * total / (4.0 * np.pi)
        if bright.any():
            suns = _median_cut_suns(np.where(bright[..., None], values, 0.0), solid_angle, moments, lat_edges,
                                    u_edges, split_angle, split_share * total, max_suns)
            taken = float(light[bright].sum()) / total
    sun_up = sum((np.array(s.irradiance) * max(s.direction[2], 0.0) for s in suns), np.zeros(3))
    sun_down = sum((np.array(s.irradiance) * max(-s.direction[2], 0.0) for s in suns), np.zeros(3))
    above = np.maximum(up - sun_up, 0.0) / np.pi
    below = np.maximum(down - sun_down, 0.0) / np.pi
    rest = values if not suns else np.where(bright[..., None], 0.0, values)
    harmonics = rest_harmonics(rest, solid_angle, moments, lat_edges, u_edges, lookup)
    harmonics = horizontal_exact(harmonics, above, below)
    return Decomposition(suns, tuple(float(c) for c in above), tuple(float(c) for c in below), taken,
                         tuple(tuple(float(c) for c in row) for row in harmonics))


# Real spherical harmonics to order 2 (SsLightDesc.world_sh's basis, world_light.cpp) and the cosine
# lobe's share of each band (Ramamoorthi and Hanrahan 2001): E(n) / pi = sum_i BAND_i L_i Y_i(n).
SH_BAND = np.array([1.0, 2 / 3, 2 / 3, 2 / 3, 0.25, 0.25, 0.25, 0.25, 0.25])


def sh_basis(d):
    """The 9 basis functions at unit directions d (..., 3): (..., 9)."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack(np.broadcast_arrays(0.28209479 + 0 * x, 0.48860251 * y, 0.48860251 * z, 0.48860251 * x,
                                        1.09254843 * x * y, 1.09254843 * y * z, 0.31539157 * (3 * z * z - 1),
                                        1.09254843 * x * z, 0.54627422 * (x * x - y * y)), axis=-1)


def rest_harmonics(rest, solid_angle, moments, lat_edges, u_edges, lookup):
    """The rest's radiance (texels' RGB over the grid) projected on sh_basis: (9, 3). Band 0 from the
    texels' solid angles and band 1 from their direction moments, exactly; band 2 at their centres."""
    directions = centres(lat_edges, u_edges)
    if lookup is not None:
        directions = directions @ np.asarray(lookup, dtype=np.float64)
    weights = sh_basis(directions) * solid_angle[..., None]
    weights[..., 0] = 0.28209479 * solid_angle
    weights[..., 1:4] = 0.48860251 * moments[..., [1, 2, 0]]
    return np.einsum("ijk,ijc->kc", weights, np.asarray(rest, dtype=np.float64))


def horizontal_exact(harmonics, above, below):
    """The harmonics with L_00 and L_10 set so that surfaces facing up and down get pi `above` and
    pi `below`, as the two halves give them: the map's irradiance less the suns'. A sun is a disc at
    its region's centroid; where the region is wide (a bright band round the horizon) a horizontal
    surface gets less from the disc than from the region, and the rest makes it up, as the two
    halves did. L_00 is kept no lower than 0."""
    harmonics = np.array(harmonics, dtype=np.float64)
    y20 = 0.31539157 * 2.0  # Y_20 at either pole
    mean = 0.5 * (np.asarray(above) + np.asarray(below)) - 0.25 * harmonics[6] * y20  # L_00 Y_00
    harmonics[0] = np.maximum(mean, 0.0) / 0.28209479
    harmonics[2] = 0.5 * (np.asarray(above) - np.asarray(below)) / (2.0 / 3.0 * 0.48860251)
    return harmonics


def harmonics_irradiance(harmonics, normal):
    """E(n) of radiance harmonics (9, 3) on a surface of unit normal n (RGB), as world_light.cpp's
    worldRemainder (clamped at 0)."""
    e = (SH_BAND[:, None] * np.asarray(harmonics)).T @ sh_basis(np.asarray(normal, dtype=np.float64))
    return np.pi * np.maximum(e, 0.0)


def _median_cut_suns(bright_values, solid_angle, moments, lat_edges, u_edges, split_angle, split_light, max_suns):
    """decompose_grid's steps 2 and 3 on the bright part (its RGB radiance, zero elsewhere)."""
    radiance = bright_values @ LUMINANCE
    # The seam between the map's last column and its first goes where the bright part is least,
    # so that a region does not straddle it.
    shift = int(np.argmin((radiance * solid_angle).sum(axis=0)))

    def roll(a):
        return np.roll(a, -shift, axis=1)
    u_rolled = np.append(u_edges[shift:-1] - u_edges[shift], u_edges[:shift + 1] + 1.0 - u_edges[shift])
    bright_values, moments = roll(bright_values), roll(moments)
    regions = _Regions(roll(radiance), roll(solid_angle), moments, lat_edges, u_rolled)
    first = regions.bounds(0, radiance.shape[0], 0, radiance.shape[1])
    stats = {first: regions.stats(first)}
    while len(stats) < max_suns:
        wide = [r for r, (light, _, angle) in stats.items()
                if angle > split_angle and light >= split_light and (r[1] - r[0], r[3] - r[2]) != (1, 1)]
        if not wide:
            break
        region = max(wide, key=lambda r: stats[r][0])
        del stats[region]
        for half in regions.split(region):
            stats[half] = regions.stats(half)
    suns = []
    for (r0, r1, c0, c1), (_, centre, angle) in stats.items():
        facing = np.maximum(moments[r0:r1, c0:c1] @ centre, 0.0)
        irradiance = np.einsum("ijk,ij->k", bright_values[r0:r1, c0:c1], facing)
        suns.append(Sun(tuple(float(c) for c in centre), tuple(float(c) for c in irradiance),
                        min(angle, MAX_SUN_ANGLE)))
    return suns


def irradiance(decomposition, normal):
    """The irradiance (RGB) the decomposition gives an unoccluded surface of unit normal `normal`, as
    the library renders it: each sun times the cosine to its centre, the remainder's harmonics (or,
    without them, its two halves mixed by (1 + n_z) / 2; docs/WORLD.md)."""
    normal = np.asarray(normal, dtype=np.float64)
    total = np.zeros(3)
    for sun in decomposition.suns:
        total += np.array(sun.irradiance) * max(float(np.dot(normal, sun.direction)), 0.0)
    if decomposition.harmonics:
        return total + harmonics_irradiance(decomposition.harmonics, normal)
    share = 0.5 * (1.0 + normal[2])
    return total + np.pi * (share * np.array(decomposition.above) + (1.0 - share) * np.array(decomposition.below))


def map_irradiance(rgb, normal, lookup=None):
    """The map's own irradiance on an unoccluded surface of unit normal `normal` (RGB), summed over
    its texels (the same average_down as decompose)."""
    values, lat_edges, u_edges = average_down(rgb)
    _, moments = texels(lat_edges, u_edges)
    if lookup is not None:
        moments = moments @ np.asarray(lookup, dtype=np.float64)
    return np.einsum("ijk,ij->k", values, np.maximum(moments @ np.asarray(normal, dtype=np.float64), 0.0))


# Blender's side: the Environment Texture's vector, and the results kept per image and lookup.

MAX_KEPT = 4  # maps kept averaged down, and decompositions kept (least recently used dropped first)
_maps = collections.OrderedDict()            # image key -> average_down(image)
_decompositions = collections.OrderedDict()  # (image key, lookup) -> Decomposition


def _kept(cache, key, make):
    if key not in cache:
        cache[key] = make()
    cache.move_to_end(key)
    while len(cache) > MAX_KEPT:
        cache.popitem(last=False)
    return cache[key]


def image_decomposition(image, lookup=None):
    """decompose() of an image (linear RGB) looked up by `lookup`, kept per image and lookup (a
    viewport asks at every update); the averaged-down map is kept per image, so that turning the
    map does not read the image again. PrincipledError when the image has no pixels."""
    from .. import principled
    from . import textures
    key, pixels = textures._image_key(image), None
    if key is None:  # a painted image: its pixels decide
        pixels = principled.image_pixels(image)
        key = ("dirty", pixels.shape, hash(pixels.tobytes()))
    return map_decomposition(key, lambda: principled.image_rgb(image, True, pixels=pixels), lookup)


def map_decomposition(key, rgb, lookup=None):
    """decompose() of the map that rgb() makes (an image's pixels, a sky), looked up by `lookup`,
    kept per key and lookup; the averaged-down map is kept per key."""
    grid = averaged_map(key, rgb)
    lookup_key = None if lookup is None else tuple(round(float(x), 6) for x in np.asarray(lookup).ravel())
    return _kept(_decompositions, (key, lookup_key), lambda: decompose_grid(*grid, lookup=lookup))


def averaged_map(key, rgb):
    """average_down(rgb()), kept per key."""
    return _kept(_maps, key, lambda: average_down(rgb()))


def _euler_matrix(rotation):
    """Blender's Euler XYZ rotation (the Mapping node's): R = Rz Ry Rx."""
    (cx, cy, cz), (sx, sy, sz) = np.cos(rotation), np.sin(rotation)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


def _mapping_matrix(mapping, where, warnings):
    """The matrix a Mapping node applies to a direction: its rotation R (Point, Vector, Normal) or
    R^T (Texture), negated by a negative uniform scale; a Location, a non-uniform scale and linked
    inputs are not read (said in warnings)."""
    values = {}
    for name in ("Location", "Rotation", "Scale"):
        socket = mapping.inputs.get(name)
        if socket is None or not getattr(socket, "enabled", True):
            continue
        if socket.is_linked:
            warnings.append(f"{where}: its Mapping node's {name} is connected to a node, which SubSplat does not "
                            "read; the socket's own value is used")
        values[name] = np.array(socket.default_value[:3], dtype=np.float64)
    matrix = _euler_matrix(values.get("Rotation", np.zeros(3)))
    if mapping.vector_type == "TEXTURE":
        matrix = matrix.T
    location = values.get("Location")
    if location is not None and np.any(np.abs(location) > 1e-6):
        warnings.append(f"{where}: its Mapping node's Location {tuple(round(float(x), 4) for x in location)} is not "
                        "read (the map is looked up by direction only)")
    scale = values.get("Scale", np.ones(3))
    if np.ptp(scale) > 1e-6 * max(float(np.abs(scale).max()), 1e-30) or not np.all(scale != 0.0):
        warnings.append(f"{where}: its Mapping node's Scale {tuple(round(float(x), 4) for x in scale)} is not read "
                        "(a uniform scale, which keeps directions, is)")
    elif scale[0] < 0.0:
        matrix = -matrix
    return matrix


def texture_lookup(texture, where, warnings):
    """The 3 x 3 matrix M by which an Environment Texture is looked up (m = M d for the world's
    direction d): the Mapping nodes on its Vector (through reroutes), down to a Texture Coordinate's
    Generated or Object output or to nothing (the direction itself); None for the identity. Other
    nodes are said in warnings and taken as the direction."""
    from . import textures
    matrix = np.eye(3)
    vector = texture.inputs.get("Vector")  # get: Blender 4.5 refused inputs["Vector"] of a Sky Texture in a render
    source = None if vector is None else textures.linked(vector)
    while source is not None:
        node, output = source
        if node.type == "TEX_COORD" and output.name in ("Generated", "Object"):
            if output.name == "Object" and getattr(node, "object", None) is not None:
                warnings.append(f"{where}: its Texture Coordinate's object '{node.object.name}' is not read (the map "
                                "is looked up by the world's direction)")
            break
        if node.type != "MAPPING":
            what = (f"a Texture Coordinate's {output.name} output" if node.type == "TEX_COORD"
                    else f"a {node.bl_label} node")
            warnings.append(f"{where}: its Vector comes from {what}, which SubSplat does not read (taken as the "
                            "world's direction)")
            break
        matrix = matrix @ _mapping_matrix(node, where, warnings)  # the texture reads M1 (M2 (... d))
        vector = node.inputs.get("Vector")
        source = None if vector is None else textures.linked(vector)
    return None if np.allclose(matrix, np.eye(3), atol=1e-9) else matrix
