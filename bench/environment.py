"""Calibrates the environment map's decomposition into suns and a remainder (docs/WORLD.md,
"Environment textures"; addon/subsplat/export/environment.py) on generated maps, and tests the
constants it chose on other maps. Needs only numpy (no Blender):

    python3 bench/environment.py            # the grid on maps 1-5, then the chosen constants on the test maps
    python3 bench/environment.py --timing   # decompose() of a 2048 x 1024 map

The error of a decomposition on a map is measured on the irradiance of surfaces, against the map's
own (summed over its texels):
- open sky: 14 normals (the axes and the cube's diagonals);
- a floor (normal +z) beside a wall that hides the sky below 30 or 60 degrees over half the
  azimuths, facing 8 ways; and under an overhang that hides the sky within 30 or 60 degrees of the
  zenith.
The suns are shadowed as discs of their diameter; the remainder as the library draws it: unshadowed
when its share of the light is under 10 %, else by the visibility of its harmonics' radiance
(clamped at 0, each half scaled as world_light.cpp scales its directions; docs/WORLD.md); the test maps also print the
error with the remainder as its two halves (the library before API 17).
Each error is relative to the map's irradiance on the same surface in the open sky; a map's error
is their root mean square.

The grid: every combination of BRIGHT_FACTOR, SPLIT_ANGLE, SPLIT_SHARE below. Chosen: the fewest
suns (mean over the calibration maps) among the combinations whose mean error is within 25 % of the
grid's least."""
import argparse
import dataclasses
import importlib.util
import itertools
import math
import os
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location(
    "environment", os.path.join(HERE, "..", "addon", "subsplat", "export", "environment.py"))
environment = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(environment)

CALIBRATION = [1, 2, 3, 4, 5]
TEST = list(range(6, 16))
KINDS = ["sun", "suns", "windows", "overcast", "sun and windows"]
HELD_OUT = ["horizon band", "nearly uniform", "suns across the seam", "sun at the zenith", "uniform"]
HEIGHT, WIDTH = 256, 512


def directions(height=HEIGHT, width=WIDTH):
    """The texels' centres (rows, columns, 3) of a map of this size."""
    return environment.centres((np.arange(height + 1) / height - 0.5) * np.pi, np.arange(width + 1) / width)


def unit(elevation, azimuth):
    return np.array([math.cos(elevation) * math.cos(azimuth), math.cos(elevation) * math.sin(azimuth),
                     math.sin(elevation)])


def generate(seed, kind=None):
    """A map (HEIGHT, WIDTH, 3): a sky (zenith to horizon gradient, clouds), a dim ground, and per kind
    suns (discs of 0.3-3 degrees radius, each giving 1-20x the sky's irradiance), windows (bright discs
    of 10-40 degrees at 3-20x the sky) or soft patches. kind: KINDS[seed % 5] unless given."""
    rng = np.random.default_rng(seed)
    kind = kind or KINDS[seed % len(KINDS)]
    d = directions()
    z = d[..., 2]
    scale = rng.uniform(0.2, 2.0)
    zenith = scale * rng.uniform([0.1, 0.2, 0.5], [0.4, 0.6, 1.0])
    horizon = scale * rng.uniform(0.5, 1.2, 3)
    mix = (1.0 - np.clip(z, 0.0, 1.0)) ** rng.uniform(1.0, 4.0)
    sky = zenith * (1.0 - mix[..., None]) + horizon * mix[..., None]
    clouds = np.ones_like(z)
    for _ in range(4):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        clouds *= 1.0 + rng.uniform(0.0, 0.4) * np.cos(rng.uniform(2.0, 8.0) * (d @ axis) + rng.uniform(0, 6.3))
    sky = sky * clouds[..., None]
    ground = scale * rng.uniform(0.05, 0.3) * rng.uniform(0.7, 1.0, 3)
    rgb = np.where((z >= 0.0)[..., None], sky, ground)
    sky_irradiance = math.pi * float(sky[z >= 0].mean(axis=0) @ environment.LUMINANCE)

    def disc(direction, radius, irradiance, colour):
        inside = d @ direction > math.cos(radius)
        rgb[inside] += colour * irradiance / (2.0 * math.pi * (1.0 - math.cos(radius)))

    suns = {"sun": 1, "suns": rng.integers(2, 4), "sun and windows": 1}.get(kind, 0)
    windows = {"windows": rng.integers(1, 4), "sun and windows": rng.integers(1, 3)}.get(kind, 0)
    for _ in range(suns):
        disc(unit(math.radians(rng.uniform(5, 80)), rng.uniform(0, 2 * math.pi)),
             math.radians(rng.uniform(0.3, 3.0)), sky_irradiance * rng.uniform(1.0, 20.0),
             rng.uniform([0.9, 0.8, 0.6], [1.0, 1.0, 0.9]))
    for _ in range(windows):
        radius = math.radians(rng.uniform(5, 20))
        disc(unit(math.radians(rng.uniform(-10, 60)), rng.uniform(0, 2 * math.pi)), radius,
             sky_irradiance * rng.uniform(3.0, 20.0) * (1 - math.cos(radius)) * 2, rng.uniform(0.7, 1.0, 3))
    if kind == "overcast":
        for _ in range(rng.integers(1, 3)):
            disc(unit(math.radians(rng.uniform(10, 70)), rng.uniform(0, 2 * math.pi)), math.radians(40),
                 sky_irradiance * rng.uniform(0.3, 1.0), np.ones(3))
    return rgb


def held_out(name, seed=100):
    """Shapes that are not in the generator: a bright horizon band (a sunset's glow all round), a
    nearly uniform map (+-20 % noise), two suns either side of the map's seam (-x), a sun at the
    zenith, a uniform map."""
    rng = np.random.default_rng(seed)
    d = directions()
    rgb = np.full((HEIGHT, WIDTH, 3), 0.3)
    if name == "horizon band":
        rgb += np.where((np.abs(d[..., 2]) < 0.08)[..., None], np.array([4.0, 2.0, 1.0]), 0.0)
    elif name == "nearly uniform":
        rgb *= rng.uniform(0.8, 1.2, (HEIGHT, WIDTH, 1))
    elif name == "suns across the seam":
        for azimuth in (math.pi - 0.03, -math.pi + 0.05):
            rgb[d @ unit(0.5, azimuth) > math.cos(math.radians(1.5))] = 3000.0
    elif name == "sun at the zenith":
        rgb[d[..., 2] > math.cos(math.radians(1.0))] = 5000.0
    return rgb


def visibilities(d):
    """(name, normal, visible(directions) -> bool array) of the test surfaces."""
    cases = []
    normals = [np.array(n, dtype=float) for n in itertools.product((-1, 0, 1), repeat=3)
               if sum(map(abs, n)) in (1, 3)]
    for n in normals:
        cases.append(("open", n / np.linalg.norm(n), lambda x: np.ones(x.shape[:-1], bool)))
    up = np.array([0.0, 0.0, 1.0])
    for elevation in (30, 60):
        for k in range(8):
            wall = unit(0.0, k * math.pi / 4)
            t = math.tan(math.radians(elevation))
            cases.append((f"wall {elevation} {k}", up, lambda x, wall=wall, t=t:
                          ~((x @ wall > 0) & (x[..., 2] < t * np.linalg.norm(x[..., :2], axis=-1)))))
    for angle in (30, 60):
        cases.append((f"overhang {angle}", up, lambda x, c=math.cos(math.radians(angle)): x[..., 2] < c))
    return cases


def disc_points(direction, angle, count=64):
    """count directions spread over a cap of diameter `angle` around `direction` (a Vogel spiral)."""
    direction = np.asarray(direction)
    a = np.cross(direction, [1.0, 0.0, 0.0] if abs(direction[0]) < 0.9 else [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(direction, a)
    i = np.arange(count) + 0.5
    r = 0.5 * angle * np.sqrt(i / count)
    theta = i * math.pi * (3 - math.sqrt(5))
    across = np.cos(theta)[:, None] * a + np.sin(theta)[:, None] * b
    return np.cos(r)[:, None] * direction + np.sin(r)[:, None] * across


class Evaluation:
    """A map's exact irradiance on each test surface (visibilities), and the pieces of the
    remainder's, so that a decomposition's error is quick to take."""

    def __init__(self, rgb):
        self.rgb = rgb
        values, lat_edges, u_edges = environment.average_down(rgb)
        self.grid = (values, lat_edges, u_edges)
        _, moments = environment.texels(lat_edges, u_edges)
        d = environment.centres(lat_edges, u_edges)
        self.cases = visibilities(d)
        luminance = values @ environment.LUMINANCE
        self.exact, self.open, self.halves, self.seen = [], [], [], []
        self.directions, self.solid_angle = d, environment.texels(lat_edges, u_edges)[0]
        self.basis = environment.sh_basis(d)
        open_of = {}
        for name, n, visible in self.cases:
            cosine = np.maximum(moments @ n, 0.0)
            v = visible(d)
            self.exact.append(float((luminance * cosine * v).sum()))
            key = tuple(n)
            open_of.setdefault(key, float((luminance * cosine).sum()))
            self.open.append(open_of[key])
            above = d[..., 2] >= 0
            self.halves.append((float((cosine * v * above).sum()), float((cosine * v * ~above).sum()),
                                float((cosine * above).sum()), float((cosine * ~above).sum())))
            self.seen.append(cosine * v)

    def harmonics_remainder(self, decomposition):
        """The rest's luminance per texel as the library draws it shadowed (world_light.cpp): the
        harmonics' radiance, clamped at 0, each half scaled (within [1/2, 2]) so that a surface
        facing up (down) gets the harmonics' irradiance."""
        lum = environment.LUMINANCE
        harmonics = np.asarray(decomposition.harmonics)
        radiance = np.maximum(self.basis @ (harmonics @ lum), 0.0)
        z = self.directions[..., 2]
        for half, normal in ((z >= 0, (0, 0, 1)), (z < 0, (0, 0, -1))):
            target = float(np.dot(environment.harmonics_irradiance(harmonics, normal), lum))
            got = float((radiance * np.abs(z) * self.solid_angle)[half].sum())
            if got > 0 and target > 0:
                radiance[half] *= min(max(target / got, 0.5), 2.0)
        return radiance

    def error(self, decomposition):
        """The root mean square of the relative errors over the test surfaces."""
        lum = environment.LUMINANCE
        above, below = float(np.dot(decomposition.above, lum)), float(np.dot(decomposition.below, lum))
        sun_light = sum(float(np.dot(s.irradiance, lum)) for s in decomposition.suns)
        shadowed_remainder = math.pi * above >= 0.1 * (math.pi * above + sun_light)
        harmonics = bool(decomposition.harmonics)
        rest = self.harmonics_remainder(decomposition) if harmonics and shadowed_remainder else None
        errors = []
        for (name, n, visible), exact, open_, (va, vb, oa, ob), weights in zip(self.cases, self.exact, self.open,
                                                                               self.halves, self.seen):
            model = 0.0
            for sun in decomposition.suns:
                cosine = max(float(np.dot(n, sun.direction)), 0.0)
                if cosine > 0:
                    seen = float(visible(disc_points(sun.direction, sun.angle)).mean())
                    model += float(np.dot(sun.irradiance, lum)) * cosine * seen
            if harmonics and shadowed_remainder:
                model += float((rest * weights).sum())
            elif harmonics:
                model += float(np.dot(environment.harmonics_irradiance(decomposition.harmonics, n), lum))
            elif shadowed_remainder:
                model += above * va + below * vb
            else:
                model += above * oa + below * ob
            errors.append((model - exact) / max(open_, 1e-12))
        return float(np.sqrt(np.mean(np.square(errors))))


def grid():
    return [dict(bright_factor=t, split_angle=math.radians(a), split_share=s)
            for t in (2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 32.0)
            for a in (5.0, 10.0, 20.0, 30.0, 45.0, 90.0)
            for s in (0.005, 0.01, 0.02, 0.05)]


def measure(evaluations, constants):
    errors, suns = [], []
    for evaluation in evaluations:
        decomposition = environment.decompose_grid(*evaluation.grid, **constants)
        errors.append(evaluation.error(decomposition))
        suns.append(len(decomposition.suns))
    return errors, suns


def describe(constants):
    return (f"BRIGHT_FACTOR {constants['bright_factor']:g}, "
            f"SPLIT_ANGLE {math.degrees(constants['split_angle']):g} deg, SPLIT_SHARE {constants['split_share']:g}")


def calibrate():
    evaluations = [Evaluation(generate(seed)) for seed in CALIBRATION]
    no_suns = [e.error(environment.decompose_grid(*e.grid, bright_factor=math.inf)) for e in evaluations]
    print(f"calibration maps {CALIBRATION} ({', '.join(KINDS[s % 5] for s in CALIBRATION)}): "
          f"error with no suns (the map as harmonics): {np.mean(no_suns):.4f}")
    results = []
    for constants in grid():
        errors, suns = measure(evaluations, constants)
        results.append((float(np.mean(errors)), float(np.mean(suns)), constants))
    least = min(r[0] for r in results)
    eligible = [r for r in results if r[0] <= 1.25 * least]
    chosen = min(eligible, key=lambda r: (r[1], r[0]))
    for error, suns, constants in sorted(results, key=lambda r: r[0])[:8]:
        print(f"  {describe(constants)}: error {error:.4f}, suns {suns:.1f}")
    print(f"least error {least:.4f}; chosen (fewest suns within 1.25x): {describe(chosen[2])}: "
          f"error {chosen[0]:.4f}, suns {chosen[1]:.1f}")
    return chosen[2]


def test(constants):
    current = dict(bright_factor=environment.BRIGHT_FACTOR, split_angle=environment.SPLIT_ANGLE,
                   split_share=environment.SPLIT_SHARE)
    print(f"test maps with {describe(constants)}" + ("" if constants == current else " (not the module's constants)"))
    maps = [(f"seed {s} ({KINDS[s % 5]})", generate(s)) for s in TEST] + [(n, held_out(n)) for n in HELD_OUT]
    for name, rgb in maps:
        evaluation = Evaluation(rgb)
        decomposition = environment.decompose_grid(*evaluation.grid, **constants)
        none = evaluation.error(environment.decompose_grid(*evaluation.grid, bright_factor=math.inf))
        halves = evaluation.error(dataclasses.replace(decomposition, harmonics=()))
        print(f"  {name}: {len(decomposition.suns)} suns taking {decomposition.sun_share:.0%} of the light; error "
              f"{evaluation.error(decomposition):.4f} (the rest as two halves: {halves:.4f}; no suns: {none:.4f})")


def timing():
    rng = np.random.default_rng(0)
    rgb = rng.uniform(0.1, 0.3, (1024, 2048, 3)).astype(np.float32)
    rgb[600:620, 300:320] = 5000.0
    times = []
    for _ in range(5):
        start = time.perf_counter()
        environment.decompose(rgb)
        times.append(time.perf_counter() - start)
    print(f"decompose() of a 2048 x 1024 map: median {np.median(times) * 1000:.0f} ms of 5")


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--timing", action="store_true")
    args = parser.parse_args()
    if args.timing:
        timing()
    else:
        test(calibrate())
