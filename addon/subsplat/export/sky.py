"""Blender's Sky Texture (Nishita, the default sky type) as an equirectangular map (docs/WORLD.md,
"Sky Texture"), so that it lights the scene and shows as the background as an Environment Texture
does (export/environment.py, export/background.py).

The sky is the single scattering of sunlight by air (Rayleigh), dust (Mie) and ozone (absorption)
in a spherical atmosphere, integrated over 21 wavelengths into CIE XYZ (Nishita et al. 1993,
"Display of the Earth taking into account atmospheric scattering"). Blender computes it once per
render into a 512 x 128 table over the sky, with more rows near the horizon, and draws the sun's
disc from two precomputed colours (its lower and upper limb) with limb darkening. This module
computes the same table with numpy on the whole grid and looks it up as Cycles 3.4 does
(`kernel/svm/sky.h`, which Blender installs with Cycles' kernel sources): the same atmosphere, the
same quadrature, the same look-up, so that SubSplat's sky is Cycles' sky, not another model of it.
The tables of physical data below (the sun's spectral irradiance, the scattering and absorption
coefficients, CIE 1931 colour matching functions at 20 nm) are the published values that Blender's
model uses.

`nishita_map` knows nothing of Blender (bench and native-free tests call it); `sky_map` reads the
node."""
import collections
import math

import numpy as np

EARTH_RADIUS = 6360e3        # m
ATMOSPHERE_RADIUS = 6420e3   # m
RAYLEIGH_SCALE = 8e3         # scale height, m
MIE_SCALE = 1.2e3            # m
MIE_COEFFICIENT = 2e-5       # scattering, 1/m; extinction is 1.11 times it
MIE_G = 0.76                 # aerosols' anisotropy
STEPS = 32                   # segments of a view ray
LAMBDA_STEP = 20.0           # nm, 380 to 780 nm

# Solar irradiance at the top of the atmosphere (W m^-2 nm^-1), 380 to 780 nm in 20 nm steps.
SUN_IRRADIANCE = np.array([
    1.45756829855592995315, 1.56596305559738380175, 1.65148449067670455293, 1.71496242737209314555,
    1.75797983805020541226, 1.78256407885924539336, 1.79095108475838560302, 1.78541550133410664714,
    1.76815554864306845317, 1.74122069647250410362, 1.70647127164943679389, 1.66556087452739887134,
    1.61993437242451854274, 1.57083597368892080581, 1.51932335059305478886, 1.46628494965214395407,
    1.41245852740172450623, 1.35844961970384092709, 1.30474913844739281998, 1.25174963272610817455,
    1.19975998755420620867])
# Rayleigh scattering coefficient of air at sea level (1/m).
RAYLEIGH = np.array([
    5.424820087636473e-05, 4.418549866505454e-05, 3.635151910165377e-05, 3.017929012024763e-05,
    2.526320226989157e-05, 2.130859310621843e-05, 1.809838025320633e-05, 1.547057129129042e-05,
    1.330284977336850e-05, 1.150184784075764e-05, 9.99557429990163e-06, 8.72799973630707e-06,
    7.65513700977967e-06, 6.74217203751443e-06, 5.96134125832052e-06, 5.29034598065810e-06,
    4.71115687557433e-06, 4.20910481110487e-06, 3.77218381260133e-06, 3.39051255477280e-06,
    3.05591531679811e-06])
# Ozone absorption coefficient at its peak density (1/m).
OZONE = np.array([
    3.25126849861e-09, 5.85395365047e-09, 1.977191155085e-08, 7.309568762914e-08, 2.0084561514287e-07,
    4.0383958096161e-07, 6.3551335912363e-07, 9.6707041180970e-07, 1.54797400424410e-06,
    2.09038647223331e-06, 2.46128056164565e-06, 2.73551299461512e-06, 2.15125863128643e-06,
    1.59051840791988e-06, 1.12356197979857e-06, 7.3527551487574e-07, 4.6450130357806e-07,
    3.3096079921048e-07, 2.2512612292678e-07, 1.4879129266490e-07, 1.6828623364192e-07])
# CIE 1931 2-degree colour matching functions x, y, z at 380, 400, ..., 780 nm.
CMF = np.array([
    [0.001368, 0.000039, 0.006450001], [0.01431, 0.000396, 0.06785001], [0.13438, 0.004, 0.6456],
    [0.34828, 0.023, 1.74706], [0.2908, 0.06, 1.6692], [0.09564, 0.13902, 0.8129501],
    [0.0049, 0.323, 0.272], [0.06327, 0.71, 0.07824999], [0.2904, 0.954, 0.0203],
    [0.5945, 0.995, 0.0039], [0.9163, 0.87, 0.001650001], [1.0622, 0.631, 0.0008],
    [0.8544499, 0.381, 0.00019], [0.4479, 0.175, 0.00002], [0.1649, 0.061, 0.0],
    [0.04677, 0.017, 0.0], [0.01135916, 0.004102, 0.0], [0.002899327, 0.001047, 0.0],
    [0.0006900786, 0.0002492, 0.0], [0.0001661505, 0.00006, 0.0], [0.00004150994, 0.00001499, 0.0]])
# An 8-point Gauss-Laguerre rule for optical depth along a ray to the top of the atmosphere, its
# parameter scaled so that the last node lies inside (nodes along the ray, weights with the e^x
# of the rule folded in): integral of density over [0, 1] of the ray = sum of weights x density.
QUADRATURE_NODES = np.array([0.006811185292, 0.03614807107, 0.09004346519, 0.1706680068, 0.2818362161,
                             0.4303406404, 0.6296271457, 0.9145252695])
QUADRATURE_WEIGHTS = np.array([0.01750893642, 0.04135477391, 0.06678839063, 0.09507698807, 0.1283416365,
                               0.1707430204, 0.2327233347, 0.3562490486])
# CIE XYZ (D65) to Blender's scene-linear Rec. 709: the inverse of Blender's own
# datafiles/colormanagement/luts/srgb_to_xyz.spimtx, which is what Cycles converts the sky with.
XYZ_TO_RGB = np.linalg.inv(np.array([[0.4124564, 0.3575761, 0.1804375],
                                     [0.2126729, 0.7151522, 0.0721750],
                                     [0.0193339, 0.1191920, 0.9503041]]))
TABLE_WIDTH, TABLE_HEIGHT = 512, 128   # Cycles' table over the sky
MIN_ALTITUDE, MAX_ALTITUDE = 1.0, 59999.0  # Cycles clamps the altitude so (m)


def _densities(height):
    """Relative densities of air, dust and ozone at a height above sea level (m), stacked on the
    last axis."""
    ozone = np.where((height >= 10000.0) & (height < 25000.0), height / 15000.0 - 2.0 / 3.0,
                     np.where((height >= 25000.0) & (height < 40000.0), -(height / 15000.0 - 8.0 / 3.0), 0.0))
    return np.stack([np.exp(-height / RAYLEIGH_SCALE), np.exp(-height / MIE_SCALE), ozone], axis=-1)


def _to_atmosphere(origin, direction):
    """Distance from points inside the atmosphere along unit directions to its outer sphere."""
    b = np.sum(direction * origin, axis=-1)
    c = np.sum(origin * origin, axis=-1) - ATMOSPHERE_RADIUS ** 2
    return -b + np.sqrt(np.maximum(b * b - c, 0.0))


def _optical_depth(origin, direction):
    """Relative optical depth (air, dust, ozone; m) from points to the top of the atmosphere."""
    length = _to_atmosphere(origin, direction)
    depth = 0.0
    for node, weight in zip(QUADRATURE_NODES, QUADRATURE_WEIGHTS):
        points = origin + (node * length)[..., None] * direction
        depth = depth + weight * _densities(np.linalg.norm(points, axis=-1) - EARTH_RADIUS)
    return depth * length[..., None]


def _phases(mu):
    rayleigh = 3.0 / (16.0 * math.pi) * (1.0 + mu * mu)
    g2 = MIE_G * MIE_G
    mie = 3.0 * (1.0 - g2) * (1.0 + mu * mu) / (8.0 * math.pi * (2.0 + g2) * (1.0 + g2 - 2.0 * MIE_G * mu) ** 1.5)
    return rayleigh, mie


def _spectrum_to_xyz(spectrum):
    return spectrum @ CMF * LAMBDA_STEP


def _geographic(latitude, longitude):
    return np.stack(np.broadcast_arrays(np.cos(latitude) * np.cos(longitude), np.cos(latitude) * np.sin(longitude),
                                        np.sin(latitude)), axis=-1)


def sky_table(sun_elevation, altitude, air, dust, ozone, width=TABLE_WIDTH, height=TABLE_HEIGHT):
    """The sky's single scattering in CIE XYZ over a (height, width) table, as Blender lays it out:
    row y at latitude (pi/2 + half a row) (y / height)^2 (more rows near the horizon), column x at
    longitude 2 pi x / width - pi from the sun (whose longitude is 0), mirrored about it."""
    half = width // 2
    lat_step = 0.5 * math.pi / height
    latitude = (0.5 * math.pi + 0.5 * lat_step) * (np.arange(height) / height) ** 2
    longitude = 2.0 * math.pi / width * np.arange(half) - math.pi
    direction = _geographic(latitude[:, None], longitude[None, :]).reshape(-1, 3)
    camera = np.array([0.0, 0.0, EARTH_RADIUS + altitude])
    sun = _geographic(sun_elevation, 0.0)
    scale = np.array([air, dust, ozone])
    length = _to_atmosphere(np.broadcast_to(camera, direction.shape), direction)
    segment = length / STEPS
    rayleigh_phase, mie_phase = _phases(direction @ sun)
    spectrum = np.zeros((direction.shape[0], SUN_IRRADIANCE.size))
    view_depth = np.zeros((direction.shape[0], 3))
    extinction = np.stack([RAYLEIGH, np.full_like(RAYLEIGH, 1.11 * MIE_COEFFICIENT), OZONE])  # (3, 21)
    for step in range(STEPS):
        points = camera + ((step + 0.5) * segment)[:, None] * direction
        density = scale * _densities(np.linalg.norm(points, axis=-1) - EARTH_RADIUS)
        view_depth += segment[:, None] * density
        # Blender's test of the Earth in the way: a sun above the horizon never is; one below it is
        # wherever the line towards it meets the Earth's sphere (a twilight sky is lit from above).
        lit = np.ones(points.shape[0], dtype=bool)
        if sun[2] < 0.0:
            b = 2.0 * (points @ sun)
            lit = b * b - 4.0 * (np.sum(points * points, axis=-1) - EARTH_RADIUS ** 2) < 0.0
            if not lit.any():
                continue
        total = view_depth + scale * _optical_depth(points, np.broadcast_to(sun, points.shape))
        attenuation = np.exp(-(total @ extinction))
        scattering = (density[:, :1] * RAYLEIGH * rayleigh_phase[:, None]
                      + density[:, 1:2] * MIE_COEFFICIENT * mie_phase[:, None])
        spectrum += (attenuation * scattering * SUN_IRRADIANCE * segment[:, None]) * lit[:, None]
    xyz = _spectrum_to_xyz(spectrum).reshape(height, half, 3)
    return np.concatenate([xyz, xyz[:, ::-1]], axis=1)


def sun_colours(sun_elevation, angular_diameter, altitude, air, dust):
    """The sun disc's radiance (CIE XYZ, per unit Sun Intensity) at its lower and its upper limb: the
    sun's irradiance spread over its solid angle, attenuated by air and dust (not ozone, as in
    Blender) along a ray at each limb's elevation (0 below the horizon)."""
    half = 0.5 * angular_diameter
    solid_angle = 2.0 * math.pi * (1.0 - math.cos(half))
    camera = np.array([0.0, 0.0, EARTH_RADIUS + altitude])
    colours = []
    for elevation in (max(sun_elevation - half, 0.0), max(sun_elevation + half, 0.0)):
        depth = _optical_depth(camera[None, :], _geographic(elevation, 0.0)[None, :])[0]
        spectrum = SUN_IRRADIANCE * np.exp(-(RAYLEIGH * depth[0] * air + 1.11 * MIE_COEFFICIENT * depth[1] * dust))
        colours.append(_spectrum_to_xyz(spectrum / solid_angle))
    return colours


def _stored_rotation(sun_rotation):
    """The node's Sun Rotation as Cycles stores it: 2 pi minus it, within [0, 2 pi)."""
    return 2.0 * math.pi - math.fmod(sun_rotation, 2.0 * math.pi) % (2.0 * math.pi)


def _table_lookup(table, x, y):
    """Bilinear look-up at (x, y) in [0, 1)^2 with texel centres at (i + 1/2) / size and indices
    wrapping, as Cycles reads an image with the default (repeat) extension."""
    h, w = table.shape[:2]
    px, py = x * w - 0.5, y * h - 0.5
    x0, y0 = np.floor(px), np.floor(py)
    fx, fy = (px - x0)[..., None], (py - y0)[..., None]
    x0, y0 = x0.astype(np.int64) % w, y0.astype(np.int64) % h
    x1, y1 = (x0 + 1) % w, (y0 + 1) % h
    return ((table[y0, x0] * (1 - fx) + table[y0, x1] * fx) * (1 - fy)
            + (table[y1, x0] * (1 - fx) + table[y1, x1] * fx) * fy)


def radiance(directions, table, sun_elevation, sun_rotation, angular_diameter, sun_intensity, bottom, top,
             sun_disc=True):
    """The sky's radiance (Blender's scene-linear RGB) along unit world directions (..., 3), as
    Cycles 3.4 draws the Nishita sky: the table above the horizon, the table's horizon row faded
    to black down to z = -0.4 below it, and the sun's disc (interpolated from its lower to its upper
    limb, limb-darkened) instead of the sky where it is. sun_rotation: the node's, in radians."""
    d = np.asarray(directions, dtype=np.float64)
    rotation = _stored_rotation(sun_rotation)
    theta = np.arccos(np.clip(d[..., 2], -1.0, 1.0))
    phi = np.arctan2(d[..., 0], d[..., 1])
    x = (phi + math.pi + rotation) / (2.0 * math.pi)
    x = x - np.floor(x)
    elevation = 0.5 * math.pi - theta
    above = d[..., 2] >= 0.0
    sky = _table_lookup(table, x, np.sqrt(np.maximum(elevation, 0.0) / (0.5 * math.pi)))
    # Cycles reads the ground at y = -0.5, which its sky image clamps to the first row: the horizon.
    ground = _table_lookup(table, x, np.full_like(x, 0.5 / table.shape[0]))
    fade = np.clip(1.0 + 2.5 * d[..., 2], 0.0, None) ** 3
    xyz = np.where(above[..., None], sky, np.where((d[..., 2] >= -0.4)[..., None], ground * fade[..., None], 0.0))
    if sun_disc and angular_diameter >= 0.0:
        half = 0.5 * angular_diameter
        sun = _geographic(sun_elevation, rotation + 0.5 * math.pi)
        angle = 2.0 * np.arctan2(np.linalg.norm(d - sun, axis=-1), np.linalg.norm(d + sun, axis=-1))
        inside = above & (angle < half)
        if np.any(inside):
            if sun_elevation - half > 0.0:
                t = (elevation - sun_elevation) / angular_diameter + 0.5
            elif sun_elevation + half > 0.0:
                t = elevation / (sun_elevation + half)
            else:
                t = None
            if t is None:
                disc = np.zeros_like(xyz)
            else:
                disc = (np.asarray(bottom)[None] * (1.0 - t[..., None]) + np.asarray(top)[None] * t[..., None]) * sun_intensity
            limb = 1.0 - 0.6 * (1.0 - np.sqrt(np.clip(1.0 - (angle / max(half, 1e-30)) ** 2, 0.0, None)))
            xyz = np.where(inside[..., None], disc * limb[..., None], xyz)
    return np.maximum(xyz @ XYZ_TO_RGB.T, 0.0)


def _disc_integral(table, params, rotation_node, bottom, top, radial=48, around=96):
    """The disc's light above the sky it hides (RGB, W/m^2 over the disc), by a polar rule centred on
    the sun: the exact amount the map must carry, however few texels the disc covers."""
    sun_elevation, angular_diameter, intensity = params
    half = 0.5 * angular_diameter
    rotation = _stored_rotation(rotation_node)
    centre = _geographic(sun_elevation, rotation + 0.5 * math.pi)
    helper = np.array([0.0, 0.0, 1.0]) if abs(centre[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = np.cross(centre, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(centre, e1)
    r = (np.arange(radial) + 0.5) / radial * half
    psi = (np.arange(around) + 0.5) / around * 2.0 * math.pi
    rr, pp = np.meshgrid(r, psi, indexing="ij")
    d = (np.cos(rr)[..., None] * centre + np.sin(rr)[..., None] * (np.cos(pp)[..., None] * e1 + np.sin(pp)[..., None] * e2))
    with_disc = radiance(d, table, sun_elevation, rotation_node, angular_diameter, intensity, bottom, top, True)
    without = radiance(d, table, sun_elevation, rotation_node, angular_diameter, intensity, bottom, top, False)
    weight = np.sin(rr) * (half / radial) * (2.0 * math.pi / around)
    return np.sum((with_disc - without) * weight[..., None], axis=(0, 1))


def _sky_grid(table, lat_edges, u_edges, sun_rotation):
    """radiance() without the disc over an equirectangular grid, separably: a row's elevation picks
    its row of the table (or the horizon row, faded, below it) and a column's longitude its column,
    u + 1/4 + rotation / 2 pi in the table's terms (Cycles' atan2(x, y) is a quarter turn from the
    map's atan2(-y, x))."""
    h, w = table.shape[:2]
    latitude = 0.5 * (lat_edges[1:] + lat_edges[:-1])
    above = latitude >= 0.0
    py = np.sqrt(np.maximum(latitude, 0.0) / (0.5 * math.pi)) * h - 0.5
    y0 = np.floor(py)
    fy = (py - y0)[:, None, None]
    y0 = y0.astype(np.int64) % h
    rows = table[y0] * (1.0 - fy) + table[(y0 + 1) % h] * fy
    fade = np.clip(1.0 + 2.5 * np.sin(latitude), 0.0, None) ** 3
    rows = np.where(above[:, None, None], rows, table[0][None] * fade[:, None, None]).astype(np.float32)
    rotation = _stored_rotation(sun_rotation)
    x = 0.5 * (u_edges[1:] + u_edges[:-1]) + 0.25 + rotation / (2.0 * math.pi)
    px = (x - np.floor(x)) * w - 0.5
    x0 = np.floor(px)
    fx = (px - x0)[None, :, None].astype(np.float32)
    x0 = x0.astype(np.int64) % w
    xyz = rows[:, x0] * (1.0 - fx) + rows[:, (x0 + 1) % w] * fx
    return np.maximum(xyz @ XYZ_TO_RGB.T.astype(np.float32), 0.0)


def nishita_map(sun_elevation=math.radians(15.0), sun_rotation=0.0, sun_size=math.radians(0.545),
                sun_intensity=1.0, sun_disc=True, altitude=0.0, air=1.0, dust=1.0, ozone=1.0, width=2048):
    """The Nishita sky as an equirectangular map (width/2, width, 3), row 0 at the bottom, in
    Cycles' convention (export/environment.py): each texel the sky at its centre, and the sun's disc
    spread over the texels it covers (16 x 16 samples a texel), scaled so that the map carries the
    disc's light exactly (a disc narrower than a texel still lights the scene as Blender's does)."""
    from . import environment
    altitude = min(max(altitude, MIN_ALTITUDE), MAX_ALTITUDE)
    table = sky_table(sun_elevation, altitude, air, dust, ozone)
    diameter = sun_size if sun_disc else -1.0
    bottom, top = sun_colours(sun_elevation, max(sun_size, 1e-6), altitude, air, dust)
    height = width // 2
    lat_edges = (np.arange(height + 1) / height - 0.5) * np.pi
    u_edges = np.arange(width + 1) / width
    args = (table, sun_elevation, sun_rotation, diameter, sun_intensity, bottom, top)
    rgb = _sky_grid(table, lat_edges, u_edges, sun_rotation)
    if diameter <= 0.0 or sun_intensity <= 0.0 or sun_elevation + 0.5 * diameter <= 0.0:
        return rgb
    directions = environment.centres(lat_edges, u_edges)
    exact = _disc_integral(table, (sun_elevation, diameter, sun_intensity), sun_rotation, bottom, top)
    rotation = _stored_rotation(sun_rotation)
    centre = _geographic(sun_elevation, rotation + 0.5 * math.pi)
    texel = math.pi / height
    near = np.argwhere(directions @ centre > math.cos(0.5 * diameter + 2.0 * texel))
    solid_angle, _ = environment.texels(lat_edges, u_edges)
    n = 16
    offsets = (np.arange(n) + 0.5) / n
    added = []
    for row, column in near:
        lat = lat_edges[row] + offsets * (lat_edges[row + 1] - lat_edges[row])
        u = u_edges[column] + offsets * (u_edges[column + 1] - u_edges[column])
        sub = environment.centres(np.append(lat - 0.5 * (lat_edges[row + 1] - lat_edges[row]) / n, lat_edges[row + 1]),
                                  np.append(u - 0.5 * (u_edges[column + 1] - u_edges[column]) / n, u_edges[column + 1]))
        weights = np.cos(lat)[:, None] * np.ones(n)[None, :]
        difference = (radiance(sub, *args, sun_disc=True) - radiance(sub, *args, sun_disc=False))
        added.append(np.sum(difference * weights[..., None], axis=(0, 1)) / weights.sum())
    added = np.array(added) if added else np.zeros((0, 3))
    carried = np.sum(added * solid_angle[near[:, 0], near[:, 1]][:, None], axis=0) if len(near) else np.zeros(3)
    if len(near) and np.all(carried > 0.0):
        rgb[near[:, 0], near[:, 1]] += added * (exact / carried)
    else:  # the disc falls between the samples: its light goes to the texel around its centre
        row, column = np.unravel_index(np.argmax(directions @ centre), directions.shape[:2])
        rgb[row, column] += exact / solid_angle[row, column]
    return rgb


# Blender's side: the node's parameters, and the maps made so far.

MAP_WIDTH = 2048  # texels around; a texel is 0.18 degrees, a third of the sun's default disc
MAX_KEPT = 4
_maps = collections.OrderedDict()  # node key -> nishita_map


def is_drawn(node):
    """Whether SubSplat draws this Sky Texture: Nishita, as Blender 3.x and 4.x have it (Blender 5's
    Single and Multiple Scattering skies, Preetham and Hosek-Wilkie are not)."""
    return node.type == "TEX_SKY" and node.sky_type == "NISHITA"


def not_drawn(node, where):
    """The warning for a Sky Texture that is_drawn refuses."""
    return (f"{where}: its Sky Texture is the {node.sky_type.replace('_', ' ').title()} model, which SubSplat does "
            "not draw (the Nishita sky of Blender 3.x and 4.x is drawn); the world lights the scene with, and shows, "
            "the Background's own colour")


def key(node):
    """What the map depends on: the node's parameters, rounded where the slider's last digits do not
    change the sky."""
    values = (node.sun_elevation, node.sun_rotation, node.sun_size, node.sun_intensity, node.altitude,
              node.air_density, node.dust_density, node.ozone_density)
    return ("sky", bool(node.sun_disc)) + tuple(round(float(v), 7) for v in values)


def sky_map(node):
    """nishita_map of the node's parameters, kept per parameters (a viewport asks at every update)."""
    k = key(node)
    if k not in _maps:
        _maps[k] = nishita_map(node.sun_elevation, node.sun_rotation, node.sun_size, node.sun_intensity,
                               node.sun_disc, node.altitude, node.air_density, node.dust_density,
                               node.ozone_density, width=MAP_WIDTH)
    _maps.move_to_end(k)
    while len(_maps) > MAX_KEPT:
        _maps.popitem(last=False)
    return _maps[k]


def means(node):
    """The sky's mean radiance above the horizon and below it (two RGB tuples, by solid angle)."""
    from . import environment
    values, lat_edges, u_edges = environment.averaged_map(key(node), lambda: sky_map(node))
    weight = np.diff(np.sin(lat_edges))
    centre = 0.5 * (lat_edges[1:] + lat_edges[:-1])
    row_means = values.mean(axis=1)
    return tuple(tuple(float(c) for c in (row_means[half] * weight[half, None]).sum(axis=0) / weight[half].sum())
                 for half in (centre >= 0.0, centre < 0.0))
