"""The scene's SubSplat settings as Settings data."""
import numpy as np

from .. import principled, version
from . import environment, lights, sky
from .data import Light, Settings

# The C API reads 0 as "the default" (8); a user's 0 is eq. 17 without that weight, sent as a tiny
# positive weight (exp(-1e-30 x) is 1 for any difference).
SMALLEST_WEIGHT = 1e-30


# The methods whose transport does not carry the TABULATED model's forward shift, and their labels.
UNSHIFTED_METHODS = {"MATERIAL_EDIT": "Material Edit"}


def forward_shift_applies(scene):
    """Whether the scene's renders carry the forward shift: it is on and a visible material is Tabulated
    (a method in UNSHIFTED_METHODS then renders it without, and says so)."""
    return scene.subsplat.forward_shift and any(
        m.subsplat.enabled and m.subsplat.profile_model == "TABULATED" for m in used_materials(scene))


def used_materials(scene):
    """The materials of the scene's visible mesh objects."""
    return {slot.material for obj in scene.objects if obj.type == "MESH" and obj.visible_get()
            for slot in obj.material_slots if slot.material is not None}


# The pixel filter widths the library takes (SsSettings.filter_width).
FILTER_WIDTH_RANGE = (0.01, 10.0)


def render_settings(scene, debug_passes=False, method=None, viewport_sample=None, warnings=None):
    """The scene's settings; method replaces the scene's (the viewport shows FULL for REFERENCE).
    viewport_sample: the viewport's k-th sample alone (it adds one per redraw); else a final render's
    `samples`. warnings: where to say that the pixel filter's width is out of the library's range."""
    settings = scene.subsplat
    result = Settings(method=method or settings.method, background=background(scene),
                      reference_samples=settings.reference_samples)
    if viewport_sample is None:
        result.samples = settings.samples
    else:
        result.samples, result.first_sample = 1, viewport_sample
    warnings = warnings if warnings is not None else []
    result.filter_width = filter_width(scene, warnings)
    result.shadow_resolution = settings.shadow_resolution
    result.precomputed_atlas = settings.precomputed_atlas
    result.forward_shift = settings.forward_shift
    if result.method in UNSHIFTED_METHODS and forward_shift_applies(scene):
        warnings.append(f"{UNSHIFTED_METHODS[result.method]} centres the light entering a Tabulated material on "
                        "where it enters: its transport is made for every material it can be edited to, so it "
                        "does not carry the forward shift, which depends on the material, and which Full gives (docs/TRANSPORT.md, \"The entry's "
                        "forward shift\")")
    if 0 < settings.shadow_resolution < 16:  # below the library's range: the smallest it takes
        warnings.append(f"Shadow Resolution {settings.shadow_resolution} is below 16 texels; it is rendered at 16")
        result.shadow_resolution = 16
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


def filter_width(scene, warnings):
    """Film > Pixel Filter's width (Blender's filter_size, the Blackman-Harris window's half-support
    in pixels), within the range the library takes."""
    size = float(scene.render.filter_size)
    low, high = FILTER_WIDTH_RANGE
    clamped = min(max(size, low), high)
    if abs(clamped - size) > 1e-6 * max(size, 1.0):  # filter_size is a float32: 0.01 reads 0.00999999977
        warnings.append(f"the pixel filter's width {size:g} px is outside SubSplat's {low:g} to {high:g} px; "
                        f"it is rendered at {clamped:g} px")
    return clamped


def background(scene):
    """RGBA written where no object is hit: transparent, or the world colour (an environment
    texture's mean over the sphere, docs/WORLD.md)."""
    if scene.render.film_transparent:
        return (0.0, 0.0, 0.0, 0.0)
    world = scene.world
    if world is None:
        return (0.0, 0.0, 0.0, 1.0)
    radiance = _world_radiance(world, [])
    if radiance is None:
        return (*world.color, 1.0)
    above, below, power = radiance
    return (*(0.5 * (a + b) * power for a, b in zip(above, below)), 1.0)


_environment_means = {}


def environment_mean(image):
    """An equirectangular image's mean radiance above its horizon and below it (two linear RGB
    tuples, each row weighted by the solid angle it covers), kept per image: a 4K map takes a while
    to read, and the viewport asks at every update."""
    key = (image.name_full, image.filepath_raw, tuple(image.size), image.colorspace_settings.name,
           image.is_float, image.source)
    if key not in _environment_means:
        values = principled._image_values(image, True)  # (rows, columns, 3), row 0 at the bottom
        rows = values.shape[0]
        latitude = ((np.arange(rows) + 0.5) / rows - 0.5) * np.pi
        weights = np.cos(latitude)
        rows_mean = values.mean(axis=1)
        means = []
        for half in (latitude >= 0.0, latitude < 0.0):
            total = weights[half].sum()
            mean = (rows_mean[half] * weights[half, None]).sum(axis=0) / total if total > 0 else values.mean(axis=(0, 1))
            means.append(tuple(float(c) for c in mean))
        _environment_means[key] = tuple(means)
    return _environment_means[key]


def _world_radiance(world, warnings, textures=None):
    """The world's radiance above the horizon and below it (RGB per unit strength) and its strength,
    from the Background node its World Output shows (an Environment Texture into its colour: the
    map's two means), or None when it shows none (black, as in Blender); what is not rendered is
    appended to warnings. textures: a list that receives the Environment Texture node read, if any
    (world_lights decomposes its map)."""
    if not version.uses_nodes(world):
        return tuple(world.color), tuple(world.color), 1.0
    node = _world_surface(world, warnings)
    if node is None:
        return None
    colour, strength = node.inputs["Color"], node.inputs["Strength"]
    above = below = tuple(colour.default_value[:3])
    for socket, what in ((colour, "colour"), (strength, "strength")):
        if not socket.is_linked:
            continue
        source = socket.links[0].from_node
        if socket is colour and source.type == "TEX_SKY":
            if sky.is_drawn(source):
                above, below = sky.means(source)
                if textures is not None:
                    textures.append(source)
                continue
            warnings.append(sky.not_drawn(source, f"world '{world.name}'"))
            continue
        if socket is colour and source.type == "TEX_ENVIRONMENT" and source.image is not None:
            try:
                above, below = environment_mean(source.image)
                if textures is not None:
                    textures.append(source)
                continue
            except principled.PrincipledError as error:
                warnings.append(f"world '{world.name}': {error}")
        warnings.append(f"world '{world.name}': its Background {what} is connected to a {source.bl_label} node, "
                        f"which SubSplat does not render; the world lights the scene with the socket's own {what}, "
                        "and shows it")
    return above, below, float(strength.default_value)


def _world_surface(world, warnings):
    """The Background node that the world's active World Output takes as its surface, or None: no
    output, or nothing connected (Blender's world is black then too), or another node, which is said
    in warnings."""
    outputs = [n for n in world.node_tree.nodes if n.type == "OUTPUT_WORLD"]
    output = next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)
    if output is None or not output.inputs["Surface"].is_linked:
        return None
    source = output.inputs["Surface"].links[0].from_node
    while source.type == "REROUTE" and source.inputs[0].is_linked:
        source = source.inputs[0].links[0].from_node
    if source.type != "BACKGROUND":
        warnings.append(f"world '{world.name}': its World Output's Surface is a {source.bl_label} node, which "
                        "SubSplat does not render (a Background node is); the world neither lights the scene nor "
                        "shows")
        return None
    return source


def world_lights(scene, warnings):
    """The world as lights (docs/WORLD.md): a Light of type WORLD (its Background colour x strength:
    the radiance from above the horizon, and from below it), unless it is black; for an
    equirectangular Environment Texture, suns from the map's brightest regions too, the WORLD light
    then being the rest of its light (export.environment). What is rendered otherwise than in
    Blender is appended to warnings."""
    world = scene.world
    textures = []
    radiance = _world_radiance(world, warnings, textures) if world is not None else None
    if radiance is None:
        return []
    rgb, below, power = radiance
    suns, harmonics = [], ()
    if textures:
        texture = textures[0]
        if texture.type == "TEX_SKY":
            where = f"world '{world.name}': its Sky Texture"
        else:
            where = f"world '{world.name}': its Environment Texture '{texture.image.name}'"
        if texture.type == "TEX_ENVIRONMENT" and texture.projection != "EQUIRECTANGULAR":
            warnings.append(f"{where} has the {texture.projection.replace('_', ' ').title()} projection, which "
                            "SubSplat does not read: the image lights the scene with its mean radiance above its "
                            "middle row and below it, as an equirectangular map's (docs/WORLD.md)")
        else:
            lookup = environment.texture_lookup(texture, where, warnings)
            if texture.type == "TEX_SKY":
                decomposition = environment.map_decomposition(sky.key(texture), lambda: sky.sky_map(texture), lookup)
            else:
                decomposition = environment.image_decomposition(texture.image, lookup)
            rgb, below = decomposition.above, decomposition.below
            harmonics = tuple(v * power for row in decomposition.harmonics for v in row)
            if power > 0.0:
                suns = [lights.environment_sun(sun, power) for sun in decomposition.suns]
            if suns:
                warnings.append(f"{where} lights the scene as {len(suns)} sun{'s' if len(suns) > 1 else ''} from "
                                "its brightest regions and its "
                                "remaining light to the second order of spherical harmonics (docs/WORLD.md)")
            else:
                warnings.append(f"{where} lights the scene with its light to the second order of spherical "
                                "harmonics: no region of it is bright enough for a sun (docs/WORLD.md)")
    result = []
    if max(max(rgb), max(below)) * power > 0.0:
        result.append(Light(type="WORLD", color=tuple(rgb), strength=power, position=(0.0, 0.0, 0.0),
                            direction=(0.0, 0.0, -1.0), world_directions=scene.subsplat.world_directions,
                            world_below=tuple(c * power for c in below), world_sh=harmonics))
    return result + suns


def world_light(scene, warnings):
    """world_lights' WORLD light, or None when the world is black."""
    return next((light for light in world_lights(scene, warnings) if light.type == "WORLD"), None)
