"""The plain data one frame is made of: what the export modules produce and native.py converts to
the library's structs (native/include/subsplat/subsplat.h). No bpy, no ctypes."""
from dataclasses import dataclass
from typing import Any, Optional, Tuple

import numpy as np

Vector3 = Tuple[float, float, float]
ZERO3 = (0.0, 0.0, 0.0)


class ExportError(RuntimeError):
    """Scene data the engine cannot render; the message names the object or material."""


def column_major(matrix, origin=None):
    """A mathutils 4x4 Matrix as 16 floats, column-major (OpenGL order); with `origin` (3 floats),
    its translation taken relative to it (export.Frame.origin)."""
    values = [matrix[row][col] for col in range(4) for row in range(4)]
    if origin is not None:
        for i in range(3):
            values[12 + i] -= origin[i]
    return tuple(values)


# The 2 x 3 map of UVs that leaves them as they are: u' = u, v' = v (SsTextureDesc.transform).
IDENTITY_UV = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0)


@dataclass
class Texture:
    """SsTextureDesc: an image (a native.Image) read at (u', v') = transform x (u, v, 1), row-major
    (u' = t[0] u + t[1] v + t[2], v' = t[3] u + t[4] v + t[5]); extension: "REPEAT", "EXTEND" or "CLIP";
    interpolation: "LINEAR" or "CLOSEST" (docs/TEXTURES.md)."""
    image: Any
    transform: Tuple[float, ...] = IDENTITY_UV
    extension: str = "REPEAT"
    interpolation: str = "LINEAR"


@dataclass
class Environment:
    """SsEnvironmentDesc: the background where no object is, an equirectangular image (a native.Image)
    looked up along rotation x the world direction (9 floats, column-major), times strength."""
    image: Any
    rotation: Tuple[float, ...] = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    strength: float = 1.0


@dataclass
class Material:
    """SsMaterialDesc. kind: "OPAQUE", "DIPOLE", "SUBEDIT" (which has profiles, a native.ProfileSet) or
    "HOLDOUT" (a hole in the image);
    profile_model: "DIPOLE" or "TABULATED" (a DIPOLE kind's);
    color_texture: OPAQUE: the albedo times base_color; DIPOLE, SUBEDIT: a tint (sqrt of it where
    light enters and where it leaves); normal_texture: a tangent-space normal map, mixed in by
    normal_strength (docs/TEXTURES.md);
    uv_maps: the UV maps the textures read, in the order met ("" is the mesh's render UV map); not
    sent to the library: export.mesh sends a mesh's one UV map from them."""
    kind: str
    base_color: Vector3 = ZERO3
    sigma_a: Vector3 = ZERO3
    sigma_s_prime: Vector3 = ZERO3
    eta: float = 0.0
    mm_per_unit: float = 0.0
    roughness: float = 0.0
    specular: float = 0.0
    profile_model: str = "DIPOLE"
    profiles: Any = None
    color_texture: Optional[Texture] = None
    normal_texture: Optional[Texture] = None
    normal_strength: float = 0.0
    uv_maps: Tuple[str, ...] = ()


@dataclass
class Mesh:
    """One object instance: per-corner positions and normals (float32 (n, 3)), triangle corner
    indices (uint32 (t, 3)), material ids per triangle (uint32 (t,)), 16 floats column-major, and
    per-corner UVs (float32 (n, 2)) or None."""
    name: str
    positions: np.ndarray
    normals: np.ndarray
    triangles: np.ndarray
    triangle_materials: np.ndarray
    object_to_world: Tuple[float, ...]
    uvs: Optional[np.ndarray] = None


@dataclass
class Light:
    """SsLightDesc. type: "POINT", "SPOT", "SUN", "AREA" (docs/AREA_LIGHTS.md) or "WORLD" (strength:
    radiance; world_directions: 0 automatic, -1 unshadowed, or the count; docs/WORLD.md)."""
    type: str
    color: Vector3
    strength: float
    position: Vector3
    direction: Vector3
    spot_size: float = 0.0
    spot_blend: float = 0.0
    world_directions: int = 0
    area_shape: str = "SQUARE"                 # AREA: SQUARE, RECTANGLE, DISK, ELLIPSE
    area_axis: Vector3 = (1.0, 0.0, 0.0)       # AREA: its local x axis in the world
    area_size: Tuple[float, float] = (1.0, 1.0)  # AREA: sizes along x and y, scene units
    soft_size: float = 0.0  # SUN: angular diameter (radians); POINT, SPOT: radius (docs/SOFT_SHADOWS.md)
    world_below: Vector3 = (0.0, 0.0, 0.0)  # WORLD: radiance below the horizon (absolute, docs/WORLD.md)
    world_sh: Tuple[float, ...] = ()  # WORLD: 27 floats, the radiance's harmonics (absolute), or () for two halves


@dataclass
class Camera:
    """SsCameraDesc: 16 floats each, column-major."""
    world_to_view: Tuple[float, ...]
    view_to_clip: Tuple[float, ...]
    orthographic: bool = False


@dataclass
class Settings:
    """SsSettings. method: "BRUTE", "MULTIRES", "ADAPTIVE", "FULL" or "REFERENCE"; 0 in a field is
    the library's default (automatic resolution and levels)."""
    method: str
    background: Tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    irradiance_resolution: int = 0
    reference_samples: int = 0
    levels: int = 0
    z0_factor: float = 0.0
    alpha: float = 0.0
    epsilon: float = 0.0
    lambda_z: float = 0.0
    lambda_m: float = 0.0
    debug_passes: bool = False
    target_error: float = 0.0
    samples: int = 1
    filter_width: float = 0.0
    first_sample: int = 0
    shadow_resolution: int = 0
    precomputed_atlas: str = "UV_MAP"  # PRECOMPUTED's atlas: "UV_MAP" where it fits, or "MADE"
    forward_shift: bool = True  # the TABULATED model's forward shift (docs/TRANSPORT.md)
