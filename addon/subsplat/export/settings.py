"""The scene's SubSplat settings as Settings data."""
from .. import version
from .data import Light, Settings

# The C API reads 0 as "the default" (8); a user's 0 is eq. 17 without that weight, sent as a tiny
# positive weight (exp(-1e-30 x) is 1 for any difference).
SMALLEST_WEIGHT = 1e-30


def render_settings(scene, debug_passes=False, method=None):
    """The scene's settings; method replaces the scene's (the viewport shows FULL for REFERENCE)."""
    settings = scene.subsplat
    result = Settings(method=method or settings.method, background=background(scene),
                      reference_samples=settings.reference_samples)
    if settings.quality == "AUTO":  # 0: the library's automatic resolution and levels, default thresholds
        result.irradiance_resolution = 0
        result.target_error = settings.target_error
    else:
        result.irradiance_resolution = settings.irradiance_resolution
        result.levels = settings.levels
        result.z0_factor = settings.z0_factor
        result.alpha = settings.alpha
        result.epsilon = settings.epsilon
    result.lambda_z = settings.lambda_z or SMALLEST_WEIGHT
    result.lambda_m = settings.lambda_m or SMALLEST_WEIGHT
    result.debug_passes = bool(debug_passes)
    return result


def background(scene):
    """RGBA written where no object is hit: transparent, or the world colour."""
    if scene.render.film_transparent:
        return (0.0, 0.0, 0.0, 0.0)
    world = scene.world
    if world is None:
        return (0.0, 0.0, 0.0, 1.0)
    if version.uses_nodes(world):
        node = next((n for n in world.node_tree.nodes if n.type == "BACKGROUND"), None)
        if node is not None:
            color = node.inputs["Color"].default_value
            strength = node.inputs["Strength"].default_value
            return (color[0] * strength, color[1] * strength, color[2] * strength, 1.0)
    return (*world.color, 1.0)


def world_light(scene, warnings):
    """The world as a Light of type WORLD (its Background colour x strength: the radiance from every
    direction), or None when it is black; what it renders otherwise than Blender is appended to
    warnings. docs/WORLD.md"""
    world = scene.world
    if world is None:
        return None
    if version.uses_nodes(world):
        node = next((n for n in world.node_tree.nodes if n.type == "BACKGROUND"), None)
        if node is None:
            return None
        colour, strength = node.inputs["Color"], node.inputs["Strength"]
        for socket, what in ((colour, "colour"), (strength, "strength")):
            if socket.is_linked:
                warnings.append(f"world '{world.name}': its Background {what} is connected to a "
                                f"{socket.links[0].from_node.bl_label} node, which SubSplat does not render; the "
                                f"world lights the scene with the socket's own {what}, and shows it")
        rgb, power = tuple(colour.default_value[:3]), float(strength.default_value)
    else:
        rgb, power = tuple(world.color), 1.0
    if max(rgb) * power <= 0.0:
        return None
    return Light(type="WORLD", color=rgb, strength=power, position=(0.0, 0.0, 0.0), direction=(0.0, 0.0, -1.0),
                 world_directions=scene.subsplat.world_directions)
