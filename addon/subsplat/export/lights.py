"""Blender lights as Light data."""
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
        warnings.append(f"light '{obj.name}': area lights are rendered as point lights")
    soft = light.angle if light.type == "SUN" else getattr(light, "shadow_soft_size", 0.0)
    if light.type != "AREA" and soft > 0.0:
        size = "angle" if light.type == "SUN" else "radius"
        warnings.append(f"light '{obj.name}': its {size} ({soft:.3g}) is rendered as 0: hard shadows")
    return data
