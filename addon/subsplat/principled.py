"""Translucency from a Principled BSDF (material.subsplat.source == 'PRINCIPLED'), docs/PRINCIPLED.md.

The BSDF's subsurface colour is read as the diffuse albedo, the total reflectance of the material's
profile model (Rd_total of the dipole, or the half-space's R(1) for TABULATED), and its radius as the
diffuse mean free path 1 / sigma_tr per channel (Jensen et al. 2001). Inverting the total per channel
gives the reduced albedo alpha'; then

    sigma_t' = sigma_tr / sqrt(3 (1 - alpha')),  sigma_s' = alpha' sigma_t',  sigma_a = sigma_t' - sigma_s'.

Blender 3.x: Subsurface Color, radius = Subsurface Radius x Subsurface (the weight scales the
radius, as in Cycles 3.x). Blender 4.x: Base Color, radius = Subsurface Radius x Subsurface Scale;
a Subsurface Weight other than 1 (a mix with diffuse reflection) is not made, and a warning says so.
An Image Texture node connected straight to the colour or radius input gives a value per texel;
any other link is not read: the socket's own value is used and a warning says so.
"""
import hashlib

import numpy as np

from . import native, version

COLOR_INPUT = version.PRINCIPLED_SUBSURFACE_COLOR
RADIUS_INPUT = version.PRINCIPLED_SUBSURFACE_RADIUS
SCALE_INPUT = version.PRINCIPLED_SUBSURFACE_SCALE
WEIGHT_INPUT = version.PRINCIPLED_SUBSURFACE_WEIGHT
MAX_SIDE = 512          # texels per side read from an image (larger images are sampled down)
MAX_REDUCED_ALBEDO = 0.99999  # albedo 1 would mean no absorption, which the dipole cannot have


class PrincipledError(ValueError):
    """Inputs the conversion cannot use; the message names the socket and the value."""


def dipole_total_reflectance(reduced_albedo, eta):
    """Rd_total(alpha') of Jensen et al. 2001 (DESIGN.md), elementwise, from the library."""
    return native.dipole_total_reflectance(reduced_albedo, eta)


def total_reflectance(reduced_albedo, eta, profile_model="DIPOLE"):
    """The profile model's total reflectance at normal incidence, elementwise, from the library."""
    if profile_model == "DIPOLE":
        return dipole_total_reflectance(reduced_albedo, eta)
    return native.total_reflectance(profile_model, reduced_albedo, eta)


INVERSION_NODES = 4096  # nodes of the total's inverse, uniform in s = sqrt(1 - alpha') (reduced_albedo)
_inverses = {}


def _inverse_nodes(eta, profile_model):
    """(totals, s) of the model at INVERSION_NODES + 1 values of s = sqrt(1 - alpha') from
    sqrt(1 - MAX_REDUCED_ALBEDO) to 1, totals rising: one call to the library per (eta, model)."""
    key = (float(eta), profile_model)
    if key not in _inverses:
        s = np.linspace(np.sqrt(1.0 - MAX_REDUCED_ALBEDO), 1.0, INVERSION_NODES + 1)[::-1]
        totals = total_reflectance(1.0 - s * s, eta, profile_model)
        if len(_inverses) > 64:
            _inverses.clear()
        _inverses[key] = (totals, s)
    return _inverses[key]


def reduced_albedo(total, eta, profile_model="DIPOLE"):
    """The alpha' whose total reflectance is the given albedo, for an array of any size at once: the
    total rises with alpha', and s = sqrt(1 - alpha') is nearly linear in it (1 - total is about
    H(1) s near alpha' = 1), so s is interpolated between the model's totals at nodes uniform in s
    (4097 of them: the albedo comes back within 1e-6 of itself, test_principled's conversion tests);
    a texture of a million texels converts in well under a second. Clipped to [0, MAX_REDUCED_ALBEDO]."""
    target = np.asarray(total, dtype=np.float64)
    totals, s = _inverse_nodes(eta, profile_model)
    root = np.interp(target, totals, s)  # beyond the ends: the ends (alpha' 0 and MAX_REDUCED_ALBEDO)
    return 1.0 - root * root


def coefficients(albedo, mean_free_path_mm, eta, profile_model="DIPOLE"):
    """sigma_a and sigma_s' per mm from albedo (the model's total reflectance) and mean free path
    1/sigma_tr in mm."""
    alpha = reduced_albedo(np.clip(albedo, 0.0, 1.0), eta, profile_model)
    sigma_tr = 1.0 / np.asarray(mean_free_path_mm, dtype=np.float64)
    sigma_t = sigma_tr / np.sqrt(3.0 * (1.0 - alpha))
    sigma_s = alpha * sigma_t
    return (sigma_t - sigma_s).astype(np.float32), sigma_s.astype(np.float32)


def albedo_and_path(sigma_a, sigma_s_prime, eta, profile_model="DIPOLE"):
    """The inverse: the albedo and mean free path (mm) a medium has under the profile model; for
    building test materials."""
    sigma_a, sigma_s_prime = np.asarray(sigma_a, float), np.asarray(sigma_s_prime, float)
    sigma_t = sigma_a + sigma_s_prime
    return (total_reflectance(sigma_s_prime / sigma_t, eta, profile_model),
            1.0 / np.sqrt(3 * sigma_a * sigma_t))


def srgb_to_linear(values):
    """The sRGB transfer function's inverse (IEC 61966-2-1), elementwise: stored values to linear."""
    return np.where(values <= 0.04045, values / 12.92, ((values + 0.055) / 1.055) ** 2.4)


# A byte image's values are k / 255 (image.pixels gives k * (1 / 255) in single precision): its
# conversion is a table of 256, indexed by k, rather than a power per value.
_BYTE_VALUES = np.arange(256, dtype=np.float32) * np.float32(1.0 / 255.0)
_LINEAR_BYTES = srgb_to_linear(_BYTE_VALUES).astype(np.float32)


def image_pixels(image):
    """An image's stored values, (height, width, channels) float32, row 0 at v = 0 (image.pixels,
    read in one call); PrincipledError when it has none."""
    width, height = image.size
    channels = image.channels
    if width == 0 or height == 0 or channels == 0:
        raise PrincipledError(f"image '{image.name}' has no pixels (is the file missing?)")
    pixels = np.empty(width * height * channels, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(height, width, channels)


def converts_from_srgb(image):
    """Whether an image's stored values are sRGB-encoded colours (a byte image in sRGB): Blender has
    already made float images scene-linear, and data (Non-Color) is read as stored."""
    return not image.is_float and image.colorspace_settings.name == "sRGB"


def image_rgb(image, linear_colour, max_side=None, pixels=None):
    """An image's RGB as a (height, width, 3) float32 array, row 0 at v = 0; with max_side, at most
    that many texels per side (larger images are sampled down); with linear_colour, an sRGB byte
    image converted to linear (converts_from_srgb). pixels: image_pixels(image), when read already."""
    pixels = image_pixels(image) if pixels is None else pixels
    rgb = pixels[..., :3] if pixels.shape[2] >= 3 else np.repeat(pixels[..., :1], 3, axis=2)
    if max_side:
        step = max(1, -(-max(rgb.shape[:2]) // max_side))
        rgb = rgb[::step, ::step]
    if linear_colour and converts_from_srgb(image):
        return _LINEAR_BYTES[(rgb * np.float32(255.0) + np.float32(0.5)).astype(np.uint8)]
    return np.ascontiguousarray(rgb, dtype=np.float32)


def _image_values(image, linear_colour):
    """An image's RGB as a (height, width, 3) float array, row 0 at v = 0, at most MAX_SIDE per side."""
    return image_rgb(image, linear_colour, MAX_SIDE)


def _socket_map(material, socket, linear_colour, warnings):
    """A socket's value: (height, width, 3) from a directly connected image, else its value (1, 1, 3)."""
    if socket.is_linked:
        node = socket.links[0].from_node
        if node.type == "TEX_IMAGE" and node.image is not None:
            return _image_values(node.image, linear_colour), node.image
        warnings.append(f"material '{material.name}': {socket.name} is connected to a {node.bl_label} node, "
                        "which SubSplat does not read; using the socket's own value")
    return np.asarray(socket.default_value[:3], dtype=np.float32).reshape(1, 1, 3), None


def _resample(values, shape):
    """Nearest-texel resampling of (h, w, 3) to shape (H, W)."""
    h, w = values.shape[:2]
    rows = (np.arange(shape[0]) * h // shape[0]).astype(int)
    cols = (np.arange(shape[1]) * w // shape[1]).astype(int)
    return values[rows][:, cols]


def read(material, node, mm_per_unit, eta, profile_model="DIPOLE"):
    """Per-texel coefficients of a Principled BSDF under the profile model: (sigma_a, sigma_s_prime,
    warnings, key), both (height, width, 3) per mm; key identifies the inputs, for caching."""
    warnings = []
    colour, colour_image = _socket_map(material, node.inputs[COLOR_INPUT], True, warnings)
    radius, radius_image = _socket_map(material, node.inputs[RADIUS_INPUT], False, warnings)
    scale_socket = node.inputs[SCALE_INPUT]
    if scale_socket.is_linked:
        warnings.append(f"material '{material.name}': {scale_socket.name} is connected to a node, which "
                        "SubSplat does not read; using the socket's own value")
    scale = float(scale_socket.default_value)
    weight = node.inputs[WEIGHT_INPUT] if WEIGHT_INPUT else None
    if weight is not None and (weight.is_linked or weight.default_value != 1.0):
        warnings.append(f"material '{material.name}': {WEIGHT_INPUT} is "
                        f"{'connected to a node' if weight.is_linked else round(float(weight.default_value), 4)}; "
                        "SubSplat renders the whole material as subsurface scattering, as weight 1")
    if not np.all(np.isfinite(colour)) or colour.min() < 0.0 or colour.max() > 1.0:
        bad = colour.reshape(-1, 3)[np.flatnonzero(~((colour >= 0) & (colour <= 1)).all(axis=-1).ravel())[0]]
        raise PrincipledError(f"material '{material.name}': {COLOR_INPUT} must be in [0, 1] (the diffuse albedo), "
                              f"got {tuple(round(float(v), 4) for v in bad)}")
    path = radius * scale
    if not np.all(np.isfinite(path)) or path.min() <= 0.0:
        raise PrincipledError(f"material '{material.name}': the scattering radius ({RADIUS_INPUT} x "
                              f"{SCALE_INPUT} = {tuple(round(float(v), 6) for v in path.reshape(-1, 3).min(axis=0))}) "
                              "must be positive in every channel")
    shape = max(colour.shape[:2], radius.shape[:2])
    colour = _resample(colour, shape) if colour.shape[:2] != shape else colour
    path = _resample(path, shape) if path.shape[:2] != shape else path
    path_mm = path * mm_per_unit
    if colour_image is not None:  # 8-bit steps: image noise below what an image holds is not worth a profile
        colour = np.round(colour * 255.0) / 255.0
    if radius_image is not None:  # steps of 0.4 %
        path_mm = np.exp(np.round(np.log(path_mm) * 256.0) / 256.0)
    sigma_a, sigma_s = coefficients(colour, path_mm, eta, profile_model)
    digest = hashlib.blake2b(colour.tobytes() + path_mm.tobytes(), digest_size=16).hexdigest()
    key = (digest, eta, profile_model, shape, colour_image.name if colour_image else None,
           radius_image.name if radius_image else None)
    return sigma_a, sigma_s, warnings, key
