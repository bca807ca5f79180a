"""ctypes binding of libsubsplat (native/include/subsplat/subsplat.h), and nothing else: the one
module that turns the add-on's plain data (export.data) into the library's structs.

Every call checks the status and raises SubsplatError with the library's message, so the engine
can show it to the user. At load, every Structure here is checked against the library's own
sizeof and offsetof (ssGetStructLayout).
"""
import ctypes
import os
import threading

import numpy as np

API_VERSION = 25  # SS_API_VERSION of subsplat.h
STAGES = ("buffers", "splatting", "shading", "readback")

# The header's enums (subsplat.h), by name.
SS_GL_ERROR = 4
SS_CANCELLED = 7
SS_METHOD_BRUTE, SS_METHOD_MULTIRES, SS_METHOD_ADAPTIVE, SS_METHOD_FULL, SS_METHOD_REFERENCE = 0, 1, 2, 3, 4
SS_METHOD_MATERIAL_EDIT, SS_METHOD_PRECOMPUTED = 5, 6
SS_LIGHT_POINT, SS_LIGHT_SPOT, SS_LIGHT_SUN, SS_LIGHT_WORLD, SS_LIGHT_AREA = 0, 1, 2, 3, 4
AREA_SHAPES = {"SQUARE": 0, "RECTANGLE": 1, "DISK": 2, "ELLIPSE": 3}
SS_MATERIAL_OPAQUE, SS_MATERIAL_DIPOLE, SS_MATERIAL_SUBEDIT, SS_MATERIAL_HOLDOUT = 0, 1, 2, 3
SS_PROFILE_DIPOLE, SS_PROFILE_TABULATED = 0, 1
SS_PASS_EXITANCE, SS_PASS_SELECTION, SS_PASS_LEVEL_EXITANCE = 0, 1, 2
SS_TEXTURE_REPEAT, SS_TEXTURE_EXTEND, SS_TEXTURE_CLIP = 0, 1, 2
SS_TEXTURE_LINEAR, SS_TEXTURE_CLOSEST = 0, 1
SS_ATLAS_UV_MAP, SS_ATLAS_MADE = 0, 1

# The plain data's names (export.data) for them.
METHODS = {"BRUTE": SS_METHOD_BRUTE, "MULTIRES": SS_METHOD_MULTIRES, "ADAPTIVE": SS_METHOD_ADAPTIVE,
           "FULL": SS_METHOD_FULL, "REFERENCE": SS_METHOD_REFERENCE, "MATERIAL_EDIT": SS_METHOD_MATERIAL_EDIT,
           "PRECOMPUTED": SS_METHOD_PRECOMPUTED}
LIGHT_TYPES = {"POINT": SS_LIGHT_POINT, "SPOT": SS_LIGHT_SPOT, "SUN": SS_LIGHT_SUN, "WORLD": SS_LIGHT_WORLD,
               "AREA": SS_LIGHT_AREA}
MATERIAL_KINDS = {"OPAQUE": SS_MATERIAL_OPAQUE, "DIPOLE": SS_MATERIAL_DIPOLE, "SUBEDIT": SS_MATERIAL_SUBEDIT,
                  "HOLDOUT": SS_MATERIAL_HOLDOUT}
PROFILE_MODELS = {"DIPOLE": SS_PROFILE_DIPOLE, "TABULATED": SS_PROFILE_TABULATED}
TEXTURE_EXTENSIONS = {"REPEAT": SS_TEXTURE_REPEAT, "EXTEND": SS_TEXTURE_EXTEND, "CLIP": SS_TEXTURE_CLIP}
TEXTURE_INTERPOLATIONS = {"LINEAR": SS_TEXTURE_LINEAR, "CLOSEST": SS_TEXTURE_CLOSEST}
ATLASES = {"UV_MAP": SS_ATLAS_UV_MAP, "MADE": SS_ATLAS_MADE}

_STATUS = {1: "invalid argument", 2: "invalid handle", 3: "out of memory", 4: "OpenGL error",
           5: "limit exceeded", 6: "internal error", 7: "cancelled"}

Float3 = ctypes.c_float * 3
Float4 = ctypes.c_float * 4
Float16 = ctypes.c_float * 16


class SubsplatError(RuntimeError):
    """A failed library call; str() is the library's message."""

    def __init__(self, message, status=None):
        super().__init__(message)
        self.status = status


class Cancelled(SubsplatError):
    """The render was stopped through the progress callback (the user cancelled)."""


# int32_t (*)(float fraction, void* user): non-zero stops the render.
ProgressCallback = ctypes.CFUNCTYPE(ctypes.c_int32, ctypes.c_float, ctypes.c_void_p)


class MeshDesc(ctypes.Structure):
    _fields_ = [("positions", ctypes.POINTER(ctypes.c_float)),
                ("normals", ctypes.POINTER(ctypes.c_float)),
                ("uvs", ctypes.POINTER(ctypes.c_float)),
                ("vertex_count", ctypes.c_uint32),
                ("indices", ctypes.POINTER(ctypes.c_uint32)),
                ("triangle_materials", ctypes.POINTER(ctypes.c_uint32)),
                ("triangle_count", ctypes.c_uint32),
                ("default_material", ctypes.c_uint32),
                ("object_to_world", Float16)]


class ResourceCounts(ctypes.Structure):
    _fields_ = [(name, ctypes.c_int64) for name in ("contexts", "profile_sets", "images", "textures", "buffers",
                                                     "framebuffers", "vertex_arrays", "programs", "queries",
                                                     "orphaned_gl_objects")]


class TextureDesc(ctypes.Structure):
    _fields_ = [("image", ctypes.c_void_p), ("transform", ctypes.c_float * 6), ("extension", ctypes.c_int32),
                ("interpolation", ctypes.c_int32)]


class MaterialDesc(ctypes.Structure):
    _fields_ = [("kind", ctypes.c_int32), ("base_color", Float3), ("sigma_a", Float3),
                ("sigma_s_prime", Float3), ("eta", ctypes.c_float), ("mm_per_unit", ctypes.c_float),
                ("roughness", ctypes.c_float), ("specular", ctypes.c_float), ("profile_model", ctypes.c_int32),
                ("profiles", ctypes.c_void_p), ("color_texture", TextureDesc), ("normal_texture", TextureDesc),
                ("normal_strength", ctypes.c_float)]


class EnvironmentDesc(ctypes.Structure):
    _fields_ = [("image", ctypes.c_void_p), ("rotation", ctypes.c_float * 9), ("strength", ctypes.c_float)]


class ImageDesc(ctypes.Structure):
    _fields_ = [("width", ctypes.c_uint32), ("height", ctypes.c_uint32), ("rgb", ctypes.POINTER(ctypes.c_float))]


class ProfileSetDesc(ctypes.Structure):
    _fields_ = [("segments", ctypes.c_uint32), ("radius_mm", ctypes.c_float), ("width", ctypes.c_uint32),
                ("height", ctypes.c_uint32), ("log_profiles", ctypes.POINTER(ctypes.c_float))]


class ProfileSetInfo(ctypes.Structure):
    _fields_ = [("segments", ctypes.c_uint32), ("profiles", ctypes.c_uint32), ("width", ctypes.c_uint32),
                ("height", ctypes.c_uint32), ("radius_mm", ctypes.c_float), ("fit_error", ctypes.c_float),
                ("max_fit_error", ctypes.c_float), ("effective_range_mm", ctypes.c_float * 2),
                ("gpu_bytes", ctypes.c_uint64), ("source_segments", ctypes.c_uint32),
                ("source_profiles", ctypes.c_uint32)]


class LightDesc(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int32), ("color", Float3), ("strength", ctypes.c_float),
                ("position", Float3), ("direction", Float3), ("spot_size", ctypes.c_float),
                ("spot_blend", ctypes.c_float), ("world_directions", ctypes.c_int32), ("area_shape", ctypes.c_int32),
                ("area_axis", Float3), ("area_size", ctypes.c_float * 2), ("soft_size", ctypes.c_float),
                ("world_below", Float3), ("world_sh", ctypes.c_float * 27)]


class CameraDesc(ctypes.Structure):
    _fields_ = [("world_to_view", Float16), ("view_to_clip", Float16), ("orthographic", ctypes.c_int32)]


class Settings(ctypes.Structure):
    _fields_ = [("method", ctypes.c_int32), ("irradiance_resolution", ctypes.c_int32),
                ("background", Float4), ("reference_samples", ctypes.c_uint32), ("levels", ctypes.c_int32),
                ("z0_factor", ctypes.c_float), ("alpha", ctypes.c_float), ("epsilon", ctypes.c_float),
                ("lambda_z", ctypes.c_float), ("lambda_m", ctypes.c_float), ("debug_passes", ctypes.c_int32),
                ("target_error", ctypes.c_float), ("samples", ctypes.c_int32), ("filter_width", ctypes.c_float),
                ("first_sample", ctypes.c_int32), ("shadow_resolution", ctypes.c_int32),
                ("precomputed_atlas", ctypes.c_int32), ("forward_shift", ctypes.c_int32)]


class Stats(ctypes.Structure):
    _fields_ = [("frame_ms", ctypes.c_double), ("stage_ms", ctypes.c_double * 4),
                ("fragment_invocations", ctypes.c_uint64 * 4), ("splat_count", ctypes.c_uint64),
                ("width", ctypes.c_int32), ("height", ctypes.c_int32), ("light_views", ctypes.c_int32),
                ("timers_available", ctypes.c_int32), ("statistics_available", ctypes.c_int32),
                ("translucent_pixels", ctypes.c_uint64), ("lit_translucent_pixels", ctypes.c_uint64),
                ("nonfinite_pixels", ctypes.c_uint64), ("kernel_evaluations", ctypes.c_uint64),
                ("levels", ctypes.c_int32), ("selected_per_level", ctypes.c_uint64 * 8),
                ("splat_levels", ctypes.c_int32), ("splat_level_ms", ctypes.c_double * 8),
                ("splat_level_fragments", ctypes.c_uint64 * 8), ("accumulation_ms", ctypes.c_double),
                ("accumulation_fragments", ctypes.c_uint64), ("irradiance_resolution", ctypes.c_int32),
                ("texels_per_range", ctypes.c_float), ("samples", ctypes.c_int32),
                ("shadow_resolution", ctypes.c_int32), ("splatting_complete", ctypes.c_int32),
                ("splatting_progress", ctypes.c_float), ("target_reachable", ctypes.c_int32),
                ("precompute_ms", ctypes.c_double), ("transport_reused", ctypes.c_int32),
                ("transport_full_pipeline", ctypes.c_int32),
                ("precomputed_bytes", ctypes.c_uint64), ("precomputed_texels", ctypes.c_uint64),
                ("precomputed_factors", ctypes.c_uint64), ("relight_ms", ctypes.c_double),
                ("selection_ms", ctypes.c_double)]


class ProfileInfo(ctypes.Structure):
    _fields_ = [("total_reflectance", Float3), ("effective_range", Float3), ("support_radius", ctypes.c_float)]


# Each Structure and its struct in subsplat.h, checked at load (check_layout).
class PrecomputedObject(ctypes.Structure):
    _fields_ = [("object_id", ctypes.c_uint32), ("vertices", ctypes.c_uint32), ("bytes", ctypes.c_uint64),
                ("texels", ctypes.c_uint64), ("kernel_taps", ctypes.c_uint64), ("factors", ctypes.c_uint64),
                ("atlas_width", ctypes.c_int32), ("atlas_height", ctypes.c_int32), ("texel_size", ctypes.c_float),
                ("local_range", ctypes.c_float), ("precompute_ms", ctypes.c_double), ("charts", ctypes.c_int32),
                ("uv_charts", ctypes.c_int32), ("uv_islands_refused", ctypes.c_int32)]


LAYOUTS = {MeshDesc: "SsMeshDesc", ResourceCounts: "SsResourceCounts", MaterialDesc: "SsMaterialDesc",
           TextureDesc: "SsTextureDesc", ImageDesc: "SsImageDesc", EnvironmentDesc: "SsEnvironmentDesc", ProfileSetDesc: "SsProfileSetDesc", ProfileSetInfo: "SsProfileSetInfo", LightDesc: "SsLightDesc",
           CameraDesc: "SsCameraDesc", Settings: "SsSettings", Stats: "SsStats", ProfileInfo: "SsProfileInfo",
           PrecomputedObject: "SsPrecomputedObject"}

_libs = None


def library():
    """The loaded library (loaded on first use), as seen from the calling thread.

    On Blender's main thread the library's functions keep the GIL while they run (ctypes.PyDLL); in
    other threads (final and preview renders) they release it (ctypes.CDLL). Blender keeps one global
    "Python may not write to ID data" flag, which each read-only callback (panel draw, view_draw)
    saves, sets and restores. If a render thread's Python callback starts while the main thread is
    inside one of those with the GIL released, the two save/restore pairs interleave and the flag
    stays set for the rest of the session: every timer and handler of every add-on then fails to
    write ("Writing to ID classes in this context is not allowed"). Keeping the GIL through native
    calls made from the main thread closes that window (docs/DECISIONS.md, "The GIL")."""
    global _libs
    if _libs is None:
        path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "libsubsplat.so")
        if not os.path.exists(path):
            raise SubsplatError(f"native library missing: {path} (build with cmake, or reinstall the add-on)")
        try:
            libs = (_declare(ctypes.PyDLL(path)), _declare(ctypes.CDLL(path)))
        except OSError as error:  # typically a missing system library
            raise SubsplatError(f"cannot load {path}: {error} (on Debian: apt install libepoxy0 libembree3-3 libopenimageio2.4)")
        if libs[0].ssGetApiVersion() != API_VERSION:
            raise SubsplatError(f"native library API {libs[0].ssGetApiVersion()} does not match the add-on's {API_VERSION}")
        for structure, name in LAYOUTS.items():
            check_layout(libs[0], structure, name)
        _libs = libs
    return _libs[0] if threading.current_thread() is threading.main_thread() else _libs[1]


def preload():
    """Loads the library now, if it can be loaded (a failure is raised again where it is used).

    The add-on calls this when it registers, on the main thread and outside any draw: loading
    (dlopen of the library, OpenImageIO, Embree, ...) takes 0.1 to 0.4 s, and ctypes releases the GIL
    while it runs. Left to the material panel's first draw, a read-only callback, that was the window
    in which a preview render thread's callback started and left Blender's "may not write" flag set
    (docs/DECISIONS.md, "The GIL").

    It also makes the TABULATED model's tables, which the library made once on first use (0.3 s,
    mostly 257 H-function solves, embedded since: under 1 ms now): in the material panel's first draw that call kept the GIL
    (ctypes.PyDLL) so long that a waiting preview thread was handed the GIL in the middle of the draw
    as soon as it returned, with the same result (half of bench/preview_write_flag.py's runs beside
    two busy processes, always at the first edit)."""
    try:
        library()
        total_reflectance("TABULATED", np.array([0.5]), 1.0)
    except SubsplatError:
        pass


def check_layout(lib, structure, name):
    """Raises SubsplatError unless a Structure has the size of the library's struct `name` and
    each of its fields the library's offset and size (a header changed without the binding)."""
    offset, size = ctypes.c_uint32(), ctypes.c_uint32()

    def layout(field):
        status = lib.ssGetStructLayout(name.encode(), field and field.encode(), ctypes.byref(offset),
                                       ctypes.byref(size))
        if status != 0:
            raise SubsplatError(f"native library: {name}{'.' + field if field else ''}: "
                                f"{lib.ssGetLastError().decode('utf-8', 'replace')} (the add-on's "
                                f"{structure.__name__} does not match subsplat.h)", status)
        return offset.value, size.value

    for field, _type in structure._fields_:
        expected = layout(field)
        actual = (getattr(structure, field).offset, getattr(structure, field).size)
        if actual != expected:
            raise SubsplatError(f"native library: {name}.{field} is at offset {expected[0]} with size {expected[1]} "
                                f"in the library but at offset {actual[0]} with size {actual[1]} in the add-on's "
                                f"{structure.__name__} (rebuild the add-on and the library together)")
    expected = layout(None)[1]
    if ctypes.sizeof(structure) != expected:
        raise SubsplatError(f"native library: {name} has {expected} bytes in the library but the add-on's "
                            f"{structure.__name__} has {ctypes.sizeof(structure)} (a field is missing)")


def _declare(lib):
    """Sets the argument and result types of the C API's functions on a loaded library."""
    lib.ssGetApiVersion.restype = ctypes.c_int32
    lib.ssGetLastError.restype = ctypes.c_char_p
    handle = ctypes.c_void_p
    signatures = {
        "ssGetStructLayout": [ctypes.c_char_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_uint32),
                              ctypes.POINTER(ctypes.c_uint32)],
        "ssNewContext": [ctypes.POINTER(handle)],
        "ssReleaseContext": [handle],
        "ssSetMaterial": [handle, ctypes.c_uint32, ctypes.POINTER(MaterialDesc)],
        "ssSetMesh": [handle, ctypes.c_uint32, ctypes.POINTER(MeshDesc)],
        "ssRemoveMesh": [handle, ctypes.c_uint32],
        "ssSetLights": [handle, ctypes.POINTER(LightDesc), ctypes.c_uint32],
        "ssSetCamera": [handle, ctypes.POINTER(CameraDesc)],
        "ssSetSettings": [handle, ctypes.POINTER(Settings)],
        "ssRender": [handle, ctypes.c_int32, ctypes.c_int32, ctypes.POINTER(ctypes.c_float)],
        "ssGetStats": [handle, ctypes.POINTER(Stats)],
        "ssGetPrecomputedObjects": [handle, ctypes.POINTER(PrecomputedObject), ctypes.c_uint32,
                                    ctypes.POINTER(ctypes.c_uint32)],
        "ssSetSplatBudget": [handle, ctypes.c_uint64],
        "ssGetPass": [handle, ctypes.c_int32, ctypes.c_int32, ctypes.c_int32, ctypes.POINTER(ctypes.c_float)],
        "ssSetProgressCallback": [handle, ProgressCallback, ctypes.c_void_p],
        "ssGetProfileInfo": [ctypes.POINTER(MaterialDesc), ctypes.POINTER(ProfileInfo)],
        "ssDipoleTotalReflectance": [ctypes.c_uint64, ctypes.POINTER(ctypes.c_double), ctypes.c_double,
                                     ctypes.POINTER(ctypes.c_double)],
        "ssTotalReflectance": [ctypes.c_int32, ctypes.c_uint64, ctypes.POINTER(ctypes.c_double), ctypes.c_double,
                               ctypes.POINTER(ctypes.c_double)],
        "ssSaveScene": [handle, ctypes.c_char_p],
        "ssNewProfileSet": [ctypes.POINTER(ProfileSetDesc), ctypes.c_float, ctypes.POINTER(handle)],
        "ssNewProfileSetFromDipoles": [ctypes.c_uint32, ctypes.c_uint32, ctypes.POINTER(ctypes.c_float),
                                       ctypes.POINTER(ctypes.c_float), ctypes.c_float, ctypes.c_float,
                                       ctypes.c_int32, ctypes.POINTER(handle)],
        "ssLoadProfileSet": [ctypes.c_char_p, ctypes.c_float, ctypes.POINTER(handle)],
        "ssSaveProfileSet": [handle, ctypes.c_char_p],
        "ssGetProfileSetInfo": [handle, ctypes.POINTER(ProfileSetInfo)],
        "ssReleaseProfileSet": [handle],
        "ssNewImage": [ctypes.POINTER(ImageDesc), ctypes.POINTER(handle)],
        "ssReleaseImage": [handle],
        "ssSetEnvironment": [handle, ctypes.POINTER(EnvironmentDesc)],
        "ssGetResourceCounts": [ctypes.POINTER(ResourceCounts)],
        "ssSetMemoryBudget": [ctypes.c_uint64],
        "ssGetMemoryUsage": [ctypes.POINTER(ctypes.c_uint64), ctypes.POINTER(ctypes.c_uint64)],
        "ssDescribeGlState": [ctypes.c_char_p, ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32)],
    }
    for name, args in signatures.items():
        function = getattr(lib, name)
        function.argtypes = args
        function.restype = ctypes.c_int
    return lib


def _check(status):
    if status != 0:
        message = library().ssGetLastError().decode("utf-8", "replace")
        error = Cancelled if status == SS_CANCELLED else SubsplatError
        raise error(message or _STATUS.get(status, f"status {status}"), status)


def _floats(array):
    return array.ctypes.data_as(ctypes.POINTER(ctypes.c_float))


def _uints(array):
    return array.ctypes.data_as(ctypes.POINTER(ctypes.c_uint32))


def set_memory_budget(bytes_):
    """The GPU memory budget of the whole process, in bytes; 0: automatic (ssSetMemoryBudget)."""
    _check(library().ssSetMemoryBudget(int(bytes_)))


def memory_usage():
    """(bytes held by the library's textures and buffers, the budget: 0 until measured with a GL context)."""
    used, budget = ctypes.c_uint64(), ctypes.c_uint64()
    _check(library().ssGetMemoryUsage(ctypes.byref(used), ctypes.byref(budget)))
    return used.value, budget.value


def resource_counts():
    """Live handles and GL objects the library holds now, over all contexts, as a dict."""
    counts = ResourceCounts()
    _check(library().ssGetResourceCounts(ctypes.byref(counts)))
    return {name: getattr(counts, name) for name, _ in ResourceCounts._fields_}


def gl_state():
    """Test hook: the current GL context's state a host relies on, {name: value text}."""
    length = ctypes.c_uint32()
    text = ctypes.create_string_buffer(1 << 16)
    _check(library().ssDescribeGlState(text, len(text), ctypes.byref(length)))
    lines = text.value.decode("ascii").splitlines()
    return dict(line.split("=", 1) for line in lines)


def changed_gl_state(before, after):
    """The names whose values differ between two gl_state() results, sorted."""
    return sorted(name for name in before if after.get(name) != before[name])


def dipole_total_reflectance(reduced_albedo, eta):
    """Rd_total of a dipole (Jensen et al. 2001) for each reduced albedo (an array of any shape), by
    the library's one implementation (ssDipoleTotalReflectance); no GL needed."""
    albedo = np.ascontiguousarray(reduced_albedo, dtype=np.float64)
    out = np.empty_like(albedo)
    doubles = ctypes.POINTER(ctypes.c_double)
    _check(library().ssDipoleTotalReflectance(albedo.size, albedo.ctypes.data_as(doubles), float(eta),
                                              out.ctypes.data_as(doubles)))
    return out


def total_reflectance(profile_model, albedo, eta):
    """What a homogeneous medium of each single-scattering albedo (an array of any shape) reflects of
    a normal beam under the profile model ("DIPOLE", "TABULATED"), by the library
    (ssTotalReflectance); no GL needed."""
    albedo = np.ascontiguousarray(albedo, dtype=np.float64)
    out = np.empty_like(albedo)
    doubles = ctypes.POINTER(ctypes.c_double)
    _check(library().ssTotalReflectance(PROFILE_MODELS[profile_model], albedo.size, albedo.ctypes.data_as(doubles),
                                        float(eta), out.ctypes.data_as(doubles)))
    return out


def profile_info(material):
    """Rd_total, R_P and support radius of a translucent Material (export.data); no GL needed."""
    info = ProfileInfo()
    _check(library().ssGetProfileInfo(ctypes.byref(_material_desc(material)), ctypes.byref(info)))
    return info


# -- plain data to structs --------------------------------------------------------------------

def _material_desc(material):
    desc = MaterialDesc()
    desc.kind = MATERIAL_KINDS[material.kind]
    desc.base_color = Float3(*material.base_color)
    desc.sigma_a = Float3(*material.sigma_a)
    desc.sigma_s_prime = Float3(*material.sigma_s_prime)
    desc.eta = material.eta
    desc.mm_per_unit = material.mm_per_unit
    desc.roughness = material.roughness
    desc.specular = material.specular
    desc.profile_model = PROFILE_MODELS[material.profile_model]
    if material.profiles is not None:
        desc.profiles = material.profiles.handle
    if material.color_texture is not None:
        desc.color_texture = _texture_desc(material.color_texture)
    if material.normal_texture is not None:
        desc.normal_texture = _texture_desc(material.normal_texture)
        desc.normal_strength = material.normal_strength
    return desc


def _texture_desc(texture):
    """texture: export.data.Texture, whose image is an Image (below)."""
    desc = TextureDesc()
    desc.image = texture.image.handle
    desc.transform = (ctypes.c_float * 6)(*texture.transform)
    desc.extension = TEXTURE_EXTENSIONS[texture.extension]
    desc.interpolation = TEXTURE_INTERPOLATIONS[texture.interpolation]
    return desc


def _light_desc(light):
    desc = LightDesc()
    desc.type = LIGHT_TYPES[light.type]
    desc.color = Float3(*light.color)
    desc.strength = light.strength
    desc.position = Float3(*light.position)
    desc.direction = Float3(*light.direction)
    desc.spot_size = light.spot_size
    desc.spot_blend = light.spot_blend
    desc.world_directions = light.world_directions
    desc.area_shape = AREA_SHAPES[light.area_shape]
    desc.area_axis = Float3(*light.area_axis)
    desc.area_size = (ctypes.c_float * 2)(*light.area_size)
    desc.soft_size = light.soft_size
    desc.world_below = Float3(*light.world_below)
    if light.world_sh:
        desc.world_sh = (ctypes.c_float * 27)(*light.world_sh)
    return desc


def _camera_desc(camera):
    desc = CameraDesc()
    desc.world_to_view = Float16(*camera.world_to_view)
    desc.view_to_clip = Float16(*camera.view_to_clip)
    desc.orthographic = 1 if camera.orthographic else 0
    return desc


def _settings(settings):
    result = Settings()
    result.method = METHODS[settings.method]
    result.irradiance_resolution = settings.irradiance_resolution
    result.background = Float4(*settings.background)
    result.reference_samples = settings.reference_samples
    result.levels = settings.levels
    result.z0_factor = settings.z0_factor
    result.alpha = settings.alpha
    result.epsilon = settings.epsilon
    result.lambda_z = settings.lambda_z
    result.lambda_m = settings.lambda_m
    result.debug_passes = 1 if settings.debug_passes else 0
    result.samples = settings.samples
    result.filter_width = settings.filter_width
    result.first_sample = settings.first_sample
    result.shadow_resolution = settings.shadow_resolution
    result.precomputed_atlas = ATLASES[settings.precomputed_atlas]
    result.forward_shift = 0 if settings.forward_shift else 1  # SS_FORWARD_SHIFT_ON, _OFF
    result.target_error = settings.target_error
    return result


class _Released:
    """A library handle (self._handle, a c_void_p) released once, by release() or when the object is
    collected; RELEASE names the library function that releases it."""
    RELEASE = None

    @property
    def handle(self):
        return self._handle.value

    def release(self):
        if self._handle:
            getattr(library(), self.RELEASE)(self._handle)
            self._handle = ctypes.c_void_p()

    def __del__(self):
        try:
            self.release()
        except Exception:  # interpreter shutdown: the library may be gone
            pass


class ProfileSet(_Released):
    """A heterogeneous material's SubEdit profiles and their UV map (docs/HETEROGENEOUS.md); no GL needed.

    Materials keep their own reference, so a set may be dropped after Context.set_material.
    tolerance: the mean relative energy error the model may make (0: the library's default, 1 %).
    """
    RELEASE = "ssReleaseProfileSet"

    def __init__(self, handle):
        self._handle = handle

    @classmethod
    def load(cls, path, tolerance=0.0):
        """A SubEdit file (OpenEXR, docs/SUBEDIT_FILE.md)."""
        handle = ctypes.c_void_p()
        _check(library().ssLoadProfileSet(os.fsencode(path), tolerance, ctypes.byref(handle)))
        return cls(handle)

    @classmethod
    def from_dipoles(cls, sigma_a, sigma_s_prime, eta, tolerance=0.0, profile_model="DIPOLE"):
        """sigma_a, sigma_s_prime: per mm, shape (height, width, 3), row 0 at v = 0; each texel's
        radial profile from profile_model ("DIPOLE", "TABULATED")."""
        sigma_a = np.ascontiguousarray(sigma_a, dtype=np.float32)
        sigma_s_prime = np.ascontiguousarray(sigma_s_prime, dtype=np.float32)
        if sigma_a.ndim != 3 or sigma_a.shape[2] != 3 or sigma_a.shape != sigma_s_prime.shape:
            raise SubsplatError(f"dipole maps must both be (height, width, 3), got {sigma_a.shape} and "
                                f"{sigma_s_prime.shape}")
        handle = ctypes.c_void_p()
        _check(library().ssNewProfileSetFromDipoles(sigma_a.shape[1], sigma_a.shape[0], _floats(sigma_a),
                                                    _floats(sigma_s_prime), eta, tolerance,
                                                    PROFILE_MODELS[profile_model], ctypes.byref(handle)))
        return cls(handle)

    @classmethod
    def from_profiles(cls, log_profiles, radius_mm, tolerance=0.0):
        """log_profiles: ln P (1/mm^2) at n + 1 knots on [0, radius_mm], shape (height, width, n + 1, 3)."""
        log_profiles = np.ascontiguousarray(log_profiles, dtype=np.float32)
        if log_profiles.ndim != 4 or log_profiles.shape[3] != 3 or log_profiles.shape[2] < 2:
            raise SubsplatError(f"profiles must be (height, width, knots, 3), got {log_profiles.shape}")
        desc = ProfileSetDesc(log_profiles.shape[2] - 1, radius_mm, log_profiles.shape[1], log_profiles.shape[0],
                              _floats(log_profiles))
        handle = ctypes.c_void_p()
        _check(library().ssNewProfileSet(ctypes.byref(desc), tolerance, ctypes.byref(handle)))
        return cls(handle)

    def save(self, path):
        """Writes a SubEdit file, one texel per map texel."""
        _check(library().ssSaveProfileSet(self._handle, os.fsencode(path)))

    def info(self):
        i = ProfileSetInfo()
        _check(library().ssGetProfileSetInfo(self._handle, ctypes.byref(i)))
        return {"segments": i.segments, "profiles": i.profiles, "width": i.width, "height": i.height,
                "radius_mm": i.radius_mm, "fit_error": i.fit_error, "max_fit_error": i.max_fit_error,
                "effective_range_mm": (i.effective_range_mm[0], i.effective_range_mm[1]),
                "gpu_bytes": int(i.gpu_bytes), "source_segments": i.source_segments,
                "source_profiles": i.source_profiles}


class Image(_Released):
    """An image materials read through their meshes' UVs (docs/TEXTURES.md); no GL needed.

    Made from scene-linear RGB values, a (height, width, 3) array, row 0 at v = 0 (Blender's bottom
    row); the library keeps its own copy. Materials keep their own reference, so an image may be
    dropped after Context.set_material.
    """
    RELEASE = "ssReleaseImage"

    def __init__(self, rgb):
        rgb = np.ascontiguousarray(rgb, dtype=np.float32)
        if rgb.ndim != 3 or rgb.shape[2] != 3:
            raise SubsplatError(f"an image must be (height, width, 3), got {rgb.shape}")
        self._handle = ctypes.c_void_p()
        self.width, self.height = rgb.shape[1], rgb.shape[0]
        desc = ImageDesc(self.width, self.height, _floats(rgb))
        _check(library().ssNewImage(ctypes.byref(desc), ctypes.byref(self._handle)))


class Context:
    """One native context: create, use and release it with the same GL context current."""

    def __init__(self):
        self._handle = ctypes.c_void_p()
        _check(library().ssNewContext(ctypes.byref(self._handle)))

    def release(self):
        if self._handle:
            _check(library().ssReleaseContext(self._handle))
            self._handle = ctypes.c_void_p()

    def release_quietly(self):
        """release() where a failure has nowhere to go (cleanup after a render or a viewport)."""
        try:
            self.release()
        except SubsplatError:
            pass

    def set_material(self, material_id, material):
        """material: export.data.Material."""
        _check(library().ssSetMaterial(self._handle, material_id, ctypes.byref(_material_desc(material))))

    def set_mesh(self, object_id, mesh):
        """mesh: export.data.Mesh; errors name its object."""
        try:
            self._set_mesh(object_id, mesh.positions, mesh.normals, mesh.triangles, mesh.triangle_materials,
                           mesh.object_to_world, mesh.uvs)
        except SubsplatError as error:
            raise SubsplatError(f"object '{mesh.name}': {error}", error.status) from error

    def _set_mesh(self, object_id, positions, normals, indices, triangle_materials, object_to_world, uvs):
        positions = np.ascontiguousarray(positions, dtype=np.float32)
        normals = np.ascontiguousarray(normals, dtype=np.float32)
        indices = np.ascontiguousarray(indices, dtype=np.uint32)
        triangle_materials = np.ascontiguousarray(triangle_materials, dtype=np.uint32)
        desc = MeshDesc()
        desc.positions = _floats(positions)
        desc.normals = _floats(normals)
        if uvs is not None:
            uvs = np.ascontiguousarray(uvs, dtype=np.float32)
            desc.uvs = _floats(uvs)
        desc.vertex_count = len(positions)
        desc.indices = _uints(indices)
        desc.triangle_materials = _uints(triangle_materials)
        desc.triangle_count = len(indices)
        desc.object_to_world = Float16(*object_to_world)
        _check(library().ssSetMesh(self._handle, object_id, ctypes.byref(desc)))

    def remove_mesh(self, object_id):
        _check(library().ssRemoveMesh(self._handle, object_id))

    def set_lights(self, lights):
        """lights: export.data.Light list."""
        array = (LightDesc * max(len(lights), 1))(*[_light_desc(light) for light in lights])
        _check(library().ssSetLights(self._handle, array, len(lights)))

    def set_camera(self, camera):
        """camera: export.data.Camera."""
        _check(library().ssSetCamera(self._handle, ctypes.byref(_camera_desc(camera))))

    def set_environment(self, environment):
        """The background image (export.data.Environment), or None: the settings' colour."""
        desc = EnvironmentDesc()
        if environment is not None:
            desc.image = environment.image.handle
            desc.rotation = (ctypes.c_float * 9)(*environment.rotation)
            desc.strength = environment.strength
        _check(library().ssSetEnvironment(self._handle, ctypes.byref(desc)))  # the context keeps the image

    def set_settings(self, settings):
        """settings: export.data.Settings."""
        _check(library().ssSetSettings(self._handle, ctypes.byref(_settings(settings))))

    def set_splat_budget(self, fragments):
        """At most this many splatting fragment invocations per render (0: none); a render that
        stops at it is continued by the next while nothing changes (stats()["splatting_complete"])."""
        _check(library().ssSetSplatBudget(self._handle, int(fragments)))

    def save_scene(self, path):
        """Writes what this context was given to a scene file (docs/SCENE_FILE.md)."""
        _check(library().ssSaveScene(self._handle, os.fsencode(path)))

    def render(self, width, height, progress=None):
        """Linear RGBA float32 pixels, shape (height, width, 4), bottom row first.

        progress(fraction) -> bool is called now and then during long renders
        (REFERENCE) on this thread; returning False stops the render, which
        then raises Cancelled. An exception inside progress also stops it.
        """
        pixels = np.empty((height, width, 4), dtype=np.float32)
        callback = None
        if progress is not None:
            def trampoline(fraction, _user):
                try:
                    return 0 if progress(float(fraction)) else 1
                except BaseException:  # never let an exception unwind through C
                    return 1
            callback = ProgressCallback(trampoline)  # kept alive until the call returns
            _check(library().ssSetProgressCallback(self._handle, callback, None))
        try:
            _check(library().ssRender(self._handle, width, height, _floats(pixels)))
        finally:
            if callback is not None:
                library().ssSetProgressCallback(self._handle, ProgressCallback(), None)
        return pixels

    def exitance_pass(self, width, height):
        """B(x_o) of the last render in rgb, 1 in alpha on translucent pixels; (height, width, 4)."""
        return self.render_pass(SS_PASS_EXITANCE, width, height)

    def render_pass(self, kind, width, height):
        """A pass of the last render (SS_PASS_*; SS_PASS_LEVEL_EXITANCE + k), (height, width, 4)."""
        pixels = np.empty((height, width, 4), dtype=np.float32)
        _check(library().ssGetPass(self._handle, kind, width, height, _floats(pixels)))
        return pixels

    def precomputed_objects(self):
        """PRECOMPUTED's precomputation, per translucent object: a dict per object, by ascending id."""
        count = ctypes.c_uint32(0)
        _check(library().ssGetPrecomputedObjects(self._handle, None, 0, ctypes.byref(count)))
        objects = (PrecomputedObject * max(count.value, 1))()
        _check(library().ssGetPrecomputedObjects(self._handle, objects, count.value, ctypes.byref(count)))
        return [{name: getattr(o, name) for name, _type in PrecomputedObject._fields_} for o in objects[:count.value]]

    def stats(self):
        s = Stats()
        _check(library().ssGetStats(self._handle, ctypes.byref(s)))
        return {
            "width": s.width, "height": s.height, "frame_ms": s.frame_ms,
            "stage_ms": {name: s.stage_ms[i] for i, name in enumerate(STAGES)},
            "fragment_invocations": dict({name: int(s.fragment_invocations[i]) for i, name in enumerate(STAGES)},
                                         total=int(sum(s.fragment_invocations))),
            "splat_count": int(s.splat_count), "light_views": s.light_views,
            "timers_available": bool(s.timers_available), "statistics_available": bool(s.statistics_available),
            "translucent_pixels": int(s.translucent_pixels), "lit_translucent_pixels": int(s.lit_translucent_pixels),
            "nonfinite_pixels": int(s.nonfinite_pixels), "kernel_evaluations": int(s.kernel_evaluations),
            "levels": s.levels, "selected_per_level": [int(s.selected_per_level[k]) for k in range(max(s.levels, 0))],
            "splat_levels": s.splat_levels,
            # the splatting stage's parts: each splatting level, eq. 17's accumulation, and Algorithm 1's
            # sample list (selection_ms, made once per light view)
            "splat_level_ms": [s.splat_level_ms[k] for k in range(max(s.splat_levels, 0))],
            "splat_level_fragments": [int(s.splat_level_fragments[k]) for k in range(max(s.splat_levels, 0))],
            "accumulation_ms": s.accumulation_ms, "accumulation_fragments": int(s.accumulation_fragments),
            "selection_ms": s.selection_ms,
            "irradiance_resolution": s.irradiance_resolution, "texels_per_range": s.texels_per_range,
            "samples": s.samples, "shadow_resolution": s.shadow_resolution,
            "splatting_complete": bool(s.splatting_complete), "splatting_progress": s.splatting_progress,
            "target_reachable": bool(s.target_reachable),
            # MATERIAL_EDIT (docs/MATERIAL_EDIT.md): the render's wall time when it precomputed the transport
            # (0 when it reused it), whether it reused it, and whether a heterogeneous material made it FULL's
            "precompute_ms": s.precompute_ms, "transport_reused": bool(s.transport_reused),
            "transport_full_pipeline": bool(s.transport_full_pipeline),
            # PRECOMPUTED (docs/PRECOMPUTED.md; precompute_ms and transport_reused as above): what its
            # precomputation holds, and the CPU time of this render's relighting
            "precomputed_bytes": int(s.precomputed_bytes), "precomputed_texels": int(s.precomputed_texels),
            "precomputed_factors": int(s.precomputed_factors), "relight_ms": s.relight_ms,
        }
