"""Generates the example SubEdit materials of example_blends/materials/ (deterministic: fixed seeds).

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \
        --python example_blends/make_materials.py

scripts/setup.sh runs it after the build when a file is missing. The files are made, not kept in
git: a SubEdit file stores every texel's whole profile (docs/SUBEDIT_FILE.md), tens of MB each.
Coefficients per mm; 'measured' ones are Jensen et al. 2001's (the add-on's presets).
"""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
OUTPUT = os.path.join(HERE, "materials")
ETA = 1.3

MARBLE = ((0.0021, 0.0041, 0.0071), (2.19, 2.62, 3.00))          # measured marble
GREY_MARBLE = ((0.06, 0.05, 0.045), (2.6, 2.8, 3.1))            # its dark veins: 10-30x the absorption
JADE = ((0.25, 0.02, 0.15), (1.0, 1.3, 1.0))                     # wax_jade.blend's jade
SKIMMILK = ((0.0014, 0.0025, 0.0142), (0.70, 1.22, 1.90))        # measured skim milk: the wax
CLEAR_WAX = ((0.0020, 0.0030, 0.0100), (0.07, 0.12, 0.19))       # a tenth of the scattering: long range
STONE = (((0.02, 0.02, 0.025), (1.8, 1.9, 2.0)),                 # grey matrix
         ((0.5, 0.45, 0.4), (2.0, 2.0, 2.0)),                    # dark grains
         ((0.002, 0.002, 0.003), (4.0, 4.2, 4.5)))               # white grains


def value_noise(size, cells, rng):
    """Smooth periodic value noise in [0, 1], (size, size)."""
    lattice = rng.random((cells, cells))
    x = np.arange(size) * cells / size
    i0 = np.floor(x).astype(int)
    f = x - i0
    s = f * f * (3 - 2 * f)
    i1 = (i0 + 1) % cells
    rows0, rows1 = lattice[i0], lattice[i1]
    top = rows0[:, i0] * (1 - s)[None, :] + rows0[:, i1] * s[None, :]
    bottom = rows1[:, i0] * (1 - s)[None, :] + rows1[:, i1] * s[None, :]
    return top * (1 - s)[:, None] + bottom * s[:, None]


def turbulence(size, rng, octaves=5, cells=4):
    """Perlin's turbulence: a sum of |noise| over octaves."""
    total, amplitude = np.zeros((size, size)), 1.0
    for octave in range(octaves):
        total += amplitude * np.abs(2 * value_noise(size, cells * 2 ** octave, rng) - 1)
        amplitude *= 0.5
    return total


def blend(a, b, t):
    """Coefficients blended in log space by t in [0, 1], (size, size, 3)."""
    t = t[..., None]
    return np.exp(np.log(np.asarray(a)) * (1 - t) + np.log(np.asarray(b)) * t)


def veined_marble(size=128):
    rng = np.random.default_rng(7)
    v, u = np.mgrid[0:size, 0:size] / size
    veins = (0.5 + 0.5 * np.sin(2 * np.pi * (2 * u + v + 1.5 * turbulence(size, rng)))) ** 8
    return blend(MARBLE[0], GREY_MARBLE[0], veins), blend(MARBLE[1], GREY_MARBLE[1], veins)


def chessboard(size=8):
    y, x = np.mgrid[0:size, 0:size]
    dark = ((x + y) % 2).astype(float)
    return blend(MARBLE[0], GREY_MARBLE[0], dark), blend(MARBLE[1], GREY_MARBLE[1], dark)


def jade(size=64):
    rng = np.random.default_rng(11)
    clouds = value_noise(size, 4, rng) * 0.6 + value_noise(size, 16, rng) * 0.4
    sigma_a = np.broadcast_to(np.asarray(JADE[0]), (size, size, 3)).copy()
    sigma_s = np.asarray(JADE[1]) * (0.5 + clouds)[..., None]  # cloudy: 0.5-1.5x the scattering
    return sigma_a, sigma_s


def varying_wax(size=64):
    """Short and long scattering side by side: bands of milky and clear wax, 10x apart in range."""
    rng = np.random.default_rng(13)
    u = np.mgrid[0:size, 0:size][1] / size
    bands = np.clip(0.5 + 2.0 * np.sin(2 * np.pi * (3 * u + 0.3 * value_noise(size, 4, rng))), 0.0, 1.0)
    return blend(SKIMMILK[0], CLEAR_WAX[0], bands), blend(SKIMMILK[1], CLEAR_WAX[1], bands)


def artificial_stone(size=128):
    """Grey matrix with dark and white grains: three profiles only."""
    rng = np.random.default_rng(17)
    grain = value_noise(size, 32, rng)
    kind = np.where(grain > 0.78, 1, np.where(grain < 0.2, 2, 0))
    sigma_a = np.stack([np.asarray(STONE[k][0]) for k in range(3)])[kind]
    sigma_s = np.stack([np.asarray(STONE[k][1]) for k in range(3)])[kind]
    return sigma_a, sigma_s


MATERIALS = {"veined_marble": veined_marble, "marble_chessboard": chessboard, "jade": jade,
             "varying_wax": varying_wax, "artificial_stone": artificial_stone}


def main(only_missing=False):
    import subsplat
    os.makedirs(OUTPUT, exist_ok=True)
    for name, make in MATERIALS.items():
        path = os.path.join(OUTPUT, f"{name}.exr")
        if only_missing and os.path.exists(path):
            continue
        sigma_a, sigma_s = make()
        profiles = subsplat.native.ProfileSet.from_dipoles(sigma_a, sigma_s, ETA)
        profiles.save(path)
        info = profiles.info()
        print(f"wrote {path}: {info['width']} x {info['height']} texels, {info['profiles']} profiles of "
              f"{info['segments']} segments (from {info['source_profiles']}), fit error {info['fit_error']:.4f}")


if __name__ == "__main__":
    main(only_missing="--missing" in sys.argv)
