"""The artist-friendly model (material.subsplat.source == 'ARTIST'), docs/ARTIST.md.

From the demo notes in papers/deformable-translucent-objects-demo-notes.md: a radius of influence R
and a 1D translucency image T, the light a point receives from another at distance D being T(D/R),
with the albedo applied as its square root at entry and at exit. As a SubEdit material:

    P_x(r) = a(x) T(r / R) / E,   E = integral of T(r / R) 2 pi r dr,

so that sqrt(P_i P_o) = sqrt(a_i a_o) T / E (the square roots at entry and exit) and the albedo is
the total diffuse reflectance of each point: T shapes the scattering, the albedo sets how much
comes back, and no coefficient has to be typed.
"""
import numpy as np

MAX_KNOTS = 1025        # the library's 1024 segments
PROFILE_BUDGET = 1 << 24  # values of ln P per material (64 MB of float32)
LOG_ZERO = -1000.0      # ln P of P = 0, as SubEdit files write it


class ArtistError(ValueError):
    """Settings the model cannot use; the message says which."""


def _image_rgb(image):
    width, height = image.size
    if width == 0 or height == 0:
        raise ArtistError(f"image '{image.name}' has no pixels (is the file missing?)")
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(height, width, 4)[..., :3]


def segment_energies(log_knots, radius_mm):
    """Integral of exp(ln P) 2 pi r dr over each log-linear segment; log_knots (..., n + 1)."""
    n = log_knots.shape[-1] - 1
    h = radius_mm / n
    a = np.arange(n) * h
    y0, y1 = log_knots[..., :-1].astype(np.float64), log_knots[..., 1:].astype(np.float64)
    x = y1 - y0
    e0, e1 = np.exp(y0), np.exp(y1)
    small = np.abs(x) < 1e-4
    xs = np.where(small, 1.0, x)
    i0 = np.where(small, h * e0 * (1 + x / 2), h * (e1 - e0) / xs)               # integral of e^y
    i1 = np.where(small, h * h * e0 * (0.5 + x / 3), h * h * (e1 * (xs - 1) + e0) / xs ** 2)  # of u e^y
    return 2 * np.pi * (a * i0 + i1)


def profiles(material, mm_per_unit, albedo_rgb):
    """(log_profiles (h, w, n + 1, 3), r_s in mm): the SubEdit profiles of an ARTIST material.

    albedo_rgb: (h, w, 3) linear albedo in [0, 1] (a texture, or one texel)."""
    settings = material.subsplat
    if settings.artist_radius <= 0.0:
        raise ArtistError(f"material '{material.name}': the radius of influence must be positive")
    image = settings.translucency_image
    if image is None:
        raise ArtistError(f"material '{material.name}': the artist model needs a translucency image")
    rgb = _image_rgb(image)
    curve = rgb[rgb.shape[0] // 2].astype(np.float64)  # the middle row, over D/R from 0 to 1
    if curve.shape[0] < 2:
        raise ArtistError(f"material '{material.name}': the translucency image '{image.name}' needs at least "
                          "2 texels across")
    if curve.shape[0] > MAX_KNOTS:
        curve = curve[np.linspace(0, curve.shape[0] - 1, MAX_KNOTS).round().astype(int)]
    if not np.all(np.isfinite(curve)) or curve.min() < 0.0:
        raise ArtistError(f"material '{material.name}': the translucency image '{image.name}' has negative or "
                          "non-finite values")
    radius_mm = settings.artist_radius * mm_per_unit
    log_t = np.where(curve > 0, np.log(np.maximum(curve, 1e-300)), LOG_ZERO).T  # (3, knots)
    energy = segment_energies(log_t, radius_mm).sum(axis=-1)
    if not np.all(energy > 0):
        channel = "RGB"[int(np.flatnonzero(~(energy > 0))[0])]
        raise ArtistError(f"material '{material.name}': the translucency image '{image.name}' is black in "
                          f"channel {channel}")
    albedo = np.asarray(albedo_rgb, dtype=np.float64)
    if not np.all(np.isfinite(albedo)) or albedo.min() < 0.0 or albedo.max() > 1.0:
        raise ArtistError(f"material '{material.name}': the albedo must be in [0, 1]")
    knots = log_t.shape[1]
    side = int(np.sqrt(PROFILE_BUDGET / (3 * knots)))
    step = max(1, -(-max(albedo.shape[:2]) // side))
    albedo = np.round(albedo[::step, ::step] * 255.0) / 255.0 if albedo.shape[:2] != (1, 1) else albedo
    log_albedo = np.where(albedo > 0, np.log(np.maximum(albedo, 1e-300)), LOG_ZERO)
    shape = (log_t - np.log(energy)[:, None]).T  # (knots, 3)
    log_profiles = np.maximum(log_albedo[:, :, None, :] + shape[None, None], LOG_ZERO)
    return log_profiles.astype(np.float32), radius_mm
