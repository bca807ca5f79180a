"""Blender lights as Light data."""
import math

from .. import version
from .data import Light


def light_data(obj, matrix, warnings, origin=(0.0, 0.0, 0.0)):
    """An evaluated light object at matrix (its instance's world matrix), its position relative to
    `origin` (export.Frame.origin); a warning for what is rendered otherwise than in Blender is
    appended to warnings."""
    light = obj.data
    axis = -matrix.col[2].xyz  # lights shine down their local -Z
    direction = tuple(axis.normalized()) if axis.length > 0 else (0.0, 0.0, -1.0)
    data = Light(type="POINT", color=tuple(light.color), strength=version.light_strength(light),
                 position=tuple(t - o for t, o in zip(matrix.translation, origin)), direction=direction)
    if light.type == "SUN":
        data.type = "SUN"
    elif light.type == "SPOT":
        data.type = "SPOT"
        data.spot_size = light.spot_size
        data.spot_blend = light.spot_blend
    elif light.type == "AREA":
        # Blender scales an area light with its object; it faces down its local -Z.
        x_axis, y_axis = matrix.col[0].xyz, matrix.col[1].xyz
        two_sizes = light.shape in {"RECTANGLE", "ELLIPSE"}
        data.type = "AREA"
        data.area_shape = light.shape
        normal = axis.normalized() if axis.length > 0 else axis
        in_plane = x_axis - normal * x_axis.dot(normal)  # perpendicular to the normal, as the library needs
        data.area_axis = tuple(in_plane.normalized()) if in_plane.length > 1e-12 else tuple(normal.orthogonal().normalized())
        data.area_size = (light.size * x_axis.length, (light.size_y if two_sizes else light.size) * y_axis.length)
        spread = getattr(light, "spread", math.pi)
        if spread < math.pi - 1e-4:
            warnings.append(f"light '{obj.name}': its spread ({math.degrees(spread):.3g} degrees) is rendered as 180 "
                            "degrees (a Lambertian emitter)")
    soft = light.angle if light.type == "SUN" else getattr(light, "shadow_soft_size", 0.0)
    if light.type != "AREA":
        data.soft_size = min(soft, math.pi / 2) if light.type == "SUN" else soft
    return data


def environment_sun(sun, strength):
    """One of an environment map's suns (export.environment.Sun) at the Background's strength: it
    shines from the sun's direction, with the irradiance a surface facing it gets, and softens its
    shadows over its angular diameter (docs/WORLD.md)."""
    peak = max(max(sun.irradiance), 1e-30)
    return Light(type="SUN", color=tuple(c / peak for c in sun.irradiance), strength=peak * strength,
                 position=(0.0, 0.0, 0.0), direction=tuple(-c for c in sun.direction),
                 soft_size=min(sun.angle, math.pi / 2))
