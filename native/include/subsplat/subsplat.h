/* subsplat: real-time subsurface scattering by multiresolution splatting
 * (Chen, Peers, Zhang, Tong 2012). Plain C API.
 *
 * Conventions
 * - Every entry point returns an SsStatus and never throws or aborts. On
 *   failure ssGetLastError() returns a message for the calling thread.
 * - Handles are opaque. A context owns GL objects and must be created, used
 *   and released with the same OpenGL context current (OpenGL 4.3 core or
 *   newer); the library never creates or switches GL contexts.
 * - Geometry is in scene units (1 Blender unit = 1 m); matrices are 4x4,
 *   column-major (OpenGL / GLM / mathutils-transposed order).
 * - Scattering coefficients are per millimetre; a material's mm_per_unit
 *   converts scene units to millimetres.
 * - Radiance out is scene-linear Rec.709, the same as Cycles.
 */
#ifndef SUBSPLAT_H
#define SUBSPLAT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define SS_API __declspec(dllexport)
#else
#define SS_API __attribute__((visibility("default")))
#endif

#define SS_API_VERSION 25

typedef enum SsStatus {
  SS_OK = 0,
  SS_INVALID_ARGUMENT = 1, /* bad pointer, count, index, non-finite value */
  SS_INVALID_HANDLE = 2,
  SS_OUT_OF_MEMORY = 3,
  SS_GL_ERROR = 4,         /* no GL context, missing features, shader build */
  SS_LIMIT_EXCEEDED = 5,   /* sizes beyond GL limits or the memory budget */
  SS_INTERNAL_ERROR = 6,
  SS_CANCELLED = 7         /* the progress callback asked to stop */
} SsStatus;

typedef struct SsContext_* SsContext;
/* A heterogeneous material's SubEdit profiles and their map (see below). */
typedef struct SsProfileSet_* SsProfileSet;
/* An image that materials read through their meshes' UVs (textures, docs/TEXTURES.md). */
typedef struct SsImage_* SsImage;

typedef enum SsMethod {
  SS_METHOD_BRUTE = 0,    /* every finest-level texel splatted (Shah et al. 2009) */
  SS_METHOD_MULTIRES = 1, /* every finest texel, multiresolution splatting (eq. 12-14, 17) */
  SS_METHOD_ADAPTIVE = 2, /* adaptive sample selection (eq. 10, 11), one splatting level */
  SS_METHOD_FULL = 3,     /* both: the paper's method */
  SS_METHOD_REFERENCE = 4, /* ground truth: eq. 4/5 in object space on the CPU (Embree) */
  /* Material editing by precomputed transport (Xu et al. 2007; API 20, docs/MATERIAL_EDIT.md):
   * FULL's samples splatted once into the transport of a basis of profiles; while meshes, lights,
   * camera, environment, settings and size stay as they were, a material edit only recombines it.
   * A scene with a heterogeneous (SubEdit) material is rendered as FULL. */
  SS_METHOD_MATERIAL_EDIT = 5,
  /* Precomputed transport of rigid objects (Lensch et al. 2002; API 21, docs/PRECOMPUTED.md): per
   * translucent object a texture atlas with per-texel filter kernels (the local response) and
   * vertex-to-vertex throughput factors (the global response), precomputed once for its mesh and
   * materials; each render relights them under the current lights (CPU, with shadow rays). Any
   * change of a translucent mesh or of a material precomputes again. */
  SS_METHOD_PRECOMPUTED = 6
} SsMethod;

typedef enum SsLightType {
  SS_LIGHT_POINT = 0,
  SS_LIGHT_SPOT = 1,
  SS_LIGHT_SUN = 2,
  /* The world: radiance colour x strength (W/m^2/sr per unit colour, as Blender's Background)
   * arriving from above the horizon (z > 0), world_below from below; at most one. Rendered as world_directions shadowed
   * directions that together give an unoccluded surface exactly pi x radiance, or unshadowed
   * (docs/WORLD.md). */
  SS_LIGHT_WORLD = 3,
  /* A one-sided Lambertian emitter of power strength (W) facing `direction`, centred at
   * position: radiance P / (4 A), as Cycles. Shadows are cast from its centre
   * (docs/AREA_LIGHTS.md). */
  SS_LIGHT_AREA = 4
} SsLightType;

typedef enum SsAreaShape {
  SS_AREA_SQUARE = 0,    /* area_size[0] x area_size[0] */
  SS_AREA_RECTANGLE = 1, /* area_size[0] along area_axis x area_size[1] */
  SS_AREA_DISK = 2,      /* diameter area_size[0] */
  SS_AREA_ELLIPSE = 3    /* diameters area_size[0] along area_axis and area_size[1] */
} SsAreaShape;

/* A triangle mesh in object space, indexed by corners. */
typedef struct SsMeshDesc {
  const float* positions;   /* 3 * vertex_count */
  const float* normals;     /* 3 * vertex_count, may be NULL (flat normals) */
  const float* uvs;         /* 2 * vertex_count, may be NULL */
  uint32_t vertex_count;
  const uint32_t* indices;  /* 3 * triangle_count */
  const uint32_t* triangle_materials; /* triangle_count material ids, may be NULL */
  uint32_t triangle_count;
  uint32_t default_material; /* material id of triangles when triangle_materials is NULL */
  float object_to_world[16];
} SsMeshDesc;

typedef enum SsMaterialKind {
  SS_MATERIAL_OPAQUE = 0,  /* diffuse + specular, no subsurface transport */
  SS_MATERIAL_DIPOLE = 1,  /* homogeneous dipole (Jensen et al. 2001) */
  SS_MATERIAL_SUBEDIT = 2, /* heterogeneous: SubEdit profiles mapped by UV (eq. 8, 9) */
  SS_MATERIAL_HOLDOUT = 3  /* Blender's holdout: hides what is behind it and casts shadows, but its own
                            * pixels are transparent black (alpha 0) */
} SsMaterialKind;

/* How a texture reads outside [0, 1] and between texels (Blender's Image Texture node). */
typedef enum SsTextureExtension {
  SS_TEXTURE_REPEAT = 0,
  SS_TEXTURE_EXTEND = 1,  /* the edge texels continue */
  SS_TEXTURE_CLIP = 2     /* black (0, 0, 0) outside */
} SsTextureExtension;
typedef enum SsTextureInterpolation {
  SS_TEXTURE_LINEAR = 0,
  SS_TEXTURE_CLOSEST = 1
} SsTextureInterpolation;

/* One texture of a material: an image read at (u', v') = transform x (u, v, 1), the mesh's UVs
 * through a 2 x 3 affine map (row-major: u' = t[0] u + t[1] v + t[2], v' = t[3] u + t[4] v + t[5];
 * all six 0: the identity). image NULL: none. A mesh without UVs reads it at (0, 0). */
typedef struct SsTextureDesc {
  SsImage image;
  float transform[6];
  int32_t extension;       /* SsTextureExtension */
  int32_t interpolation;   /* SsTextureInterpolation */
} SsTextureDesc;

/* DIPOLE materials: the model their profile comes from (docs/TRANSPORT.md, "The TABULATED model"). */
typedef enum SsProfileModel {
  SS_PROFILE_DIPOLE = 0,    /* the classical dipole (Jensen et al. 2001), the paper's */
  SS_PROFILE_TABULATED = 1  /* exact transport tables: the half-space's profile and angular factors,
                             * thin slabs' reflection and transmission */
} SsProfileModel;

typedef struct SsMaterialDesc {
  int32_t kind;            /* SsMaterialKind */
  float base_color[3];     /* OPAQUE: diffuse albedo */
  float sigma_a[3];        /* DIPOLE: absorption, per mm */
  float sigma_s_prime[3];  /* DIPOLE: reduced scattering, per mm */
  float eta;               /* DIPOLE, SUBEDIT: relative index of refraction */
  float mm_per_unit;       /* DIPOLE, SUBEDIT: millimetres per scene unit */
  float roughness;         /* specular roughness in [0, 1] */
  float specular;          /* Principled-style specular level in [0, 1] */
  int32_t profile_model;   /* DIPOLE: SsProfileModel */
  /* SUBEDIT: the profiles; the material keeps its own reference, so the set may be
   * released after ssSetMaterial. Meshes without UVs get the set's most common profile. */
  SsProfileSet profiles;
  /* Textures (docs/TEXTURES.md); the material keeps its own references to the images.
   * color: OPAQUE: the diffuse albedo is base_color x the texture's rgb, each in [0, 1].
   * DIPOLE, SUBEDIT: a tint T in [0, 1]: the light is multiplied by sqrt(T) where it enters and
   * by sqrt(T) where it leaves (so a uniform tint T scales the material's reflectance by T).
   * normal: a tangent-space normal map (rgb in [0, 1] as 0.5 (n + 1), OpenGL's green up, as
   * Blender's Normal Map node), mixed with the mesh's normal by normal_strength in [0, 10]
   * (0 with an image: 1). The tangent frame is each triangle's, from its UVs. */
  SsTextureDesc color_texture;
  SsTextureDesc normal_texture;
  float normal_strength;
} SsMaterialDesc;

typedef struct SsLightDesc {
  int32_t type;            /* SsLightType */
  float color[3];          /* linear RGB */
  /* POINT, SPOT: power in watts (Blender/Cycles convention, I = P / 4pi W/sr).
   * SUN: irradiance in W/m^2 on a surface facing the sun. WORLD: radiance, W/m^2/sr. */
  float strength;
  float position[3];       /* POINT, SPOT: world position */
  float direction[3];      /* SPOT, SUN: direction the light travels */
  float spot_size;         /* SPOT: full cone angle, radians */
  float spot_blend;        /* SPOT: [0, 1] */
  /* WORLD: shadowed directions in [1, 64]; 0: chosen from the world's share of the scene's
   * light (docs/WORLD.md); -1: none, the world lights every surface unshadowed. */
  int32_t world_directions;
  /* AREA: SsAreaShape, the emitter's local x axis (perpendicular to direction), its sizes in
   * scene units. */
  int32_t area_shape;
  float area_axis[3];
  float area_size[2];
  /* Soft shadows on opaque surfaces (docs/SOFT_SHADOWS.md): SUN: the sun's angular diameter in
   * radians, [0, pi/2]; POINT, SPOT: the light's radius in scene units; 0: hard. AREA: unused
   * (its size). */
  float soft_size;
  /* WORLD: the radiance from below the horizon (z < 0), W/m^2/sr, absolute (not times strength):
   * colour x strength for a uniform world; an environment map's mean below its horizon. */
  float world_below[3];
  /* WORLD (API 17): the radiance as real spherical harmonics to order 2, absolute (W/m^2/sr, not
   * times strength): 9 RGB coefficients, [3 i + c] for basis function i = l^2 + l + m (Y_00 =
   * 1/(2 sqrt(pi)); Y_1-1, Y_10, Y_11 proportional to y, z, x; then xy, yz, 3z^2 - 1, xz, x^2 - y^2),
   * in the scene's frame. All zero: the world of two halves above. Otherwise it replaces colour x
   * strength and world_below: an environment map's light after its suns (docs/WORLD.md). */
  float world_sh[27];
} SsLightDesc;

typedef struct SsCameraDesc {
  float world_to_view[16];
  float view_to_clip[16];  /* OpenGL clip space, as Blender's calc_matrix_camera */
  int32_t orthographic;
} SsCameraDesc;

typedef struct SsSettings {
  int32_t method;                /* SsMethod */
  /* Texels per side of each irradiance view in [16, 8192], or 0: automatic, the
   * cheapest resolution expected to meet target_error (docs/AUTO.md; the stats
   * report the choice). */
  int32_t irradiance_resolution;
  float background[4];           /* RGBA written where no object is hit */
  /* REFERENCE: surface samples over all translucent surfaces together, spread
   * by area (at least one per triangle), in [1e3, 1e8]; 0 for the default, 2e5. */
  uint32_t reference_samples;
  /* MULTIRES, ADAPTIVE, FULL: levels of the irradiance and splatting hierarchies in
   * [1, 8], or 0: chosen per frame from the materials' ranges, the light views and the
   * image (docs/MULTIRES.md; the stats report the choice); the depth-range threshold z0 as a factor of the
   * translucent bounding-sphere radius (0: 0.03); eq. 11's alpha (0: 15); eq. 14's
   * epsilon (0: 0.001); eq. 17's lambda_z and lambda_m (0: 8). */
  int32_t levels;
  float z0_factor;
  float alpha;
  float epsilon;
  float lambda_z;
  float lambda_m;
  /* Non-zero: keep the debug passes (SS_PASS_SELECTION, SS_PASS_LEVEL_EXITANCE). */
  int32_t debug_passes;
  /* Automatic irradiance resolution: the relative RMSE against REFERENCE to aim for,
   * in [1e-3, 0.5], or 0 for the default, 0.01. Unused at a fixed resolution. */
  float target_error;
  /* Anti-aliasing (docs/ANTIALIASING.md): jittered samples per ssRender in [1, 1024]
   * (0: 1), their pixel offsets drawn from Blender's Blackman-Harris pixel filter of
   * filter_width pixels in [0.01, 10] (0: 1.5, Blender's default), and the index of the
   * first in the sequence, in [0, 1e6] (the viewport renders one sample per redraw: sample
   * k of a frame is samples = 1, first_sample = k). Sample 0 is the pixel's centre. The
   * GPU methods splat the first sample only and carry its exitance to the others. */
  int32_t samples;
  float filter_width;
  int32_t first_sample;
  /* Texels per side of each light view's shadow map (hard shadows), in [16, 8192], or 0:
   * automatic, the render's larger side rounded up to a power of two, at most 2048, and never
   * coarser than the irradiance buffer, whose own map it then is (docs/SOFT_SHADOWS.md). */
  int32_t shadow_resolution;
  /* SS_METHOD_PRECOMPUTED's atlas (API 24; docs/PRECOMPUTED.md, "The mesh's own UV map"):
   * SS_ATLAS_UV_MAP (0) takes each island of a mesh's UV map that fits as a chart and charts the
   * rest; SS_ATLAS_MADE (1) charts every mesh as if it had no UV map. */
  int32_t precomputed_atlas;
  /* The TABULATED model's forward shift (API 25; docs/TRANSPORT.md, "The entry's forward shift"):
   * SS_FORWARD_SHIFT_ON (0) centres the light entering at each point ahead of that point along its
   * refracted beam, where a half-space reflects it (every method but MATERIAL_EDIT; PRECOMPUTED
   * moves its illumination map's flux); SS_FORWARD_SHIFT_OFF (1) centres it on the entry point, as
   * MATERIAL_EDIT always does (the add-on says so where a TABULATED material is lit). */
  int32_t forward_shift;
} SsSettings;

typedef enum SsForwardShift { SS_FORWARD_SHIFT_ON = 0, SS_FORWARD_SHIFT_OFF = 1 } SsForwardShift;

typedef enum SsAtlasSource { SS_ATLAS_UV_MAP = 0, SS_ATLAS_MADE = 1 } SsAtlasSource;

/* Per-stage figures of the last render. Times from GL timer queries. */
#define SS_STAGE_COUNT 4
typedef enum SsStage {
  SS_STAGE_BUFFERS = 0,   /* irradiance and splatting buffer generation */
  SS_STAGE_SPLATTING = 1, /* splatting of irradiance samples */
  SS_STAGE_SHADING = 2,   /* direct lighting and final shading (eq. 7) */
  SS_STAGE_READBACK = 3
} SsStage;

typedef struct SsStats {
  double frame_ms;                           /* wall time of ssRender */
  double stage_ms[SS_STAGE_COUNT];           /* GPU time per stage */
  uint64_t fragment_invocations[SS_STAGE_COUNT];
  uint64_t splat_count;                      /* translucent irradiance samples splatted (REFERENCE: surface samples) */
  int32_t width, height;
  int32_t light_views;                       /* irradiance buffers rendered (a MATERIAL_EDIT edit: the
                                                views whose direct light it drew, from the kept
                                                shadow maps; 0 when it kept the direct light) */
  int32_t timers_available, statistics_available;
  uint64_t translucent_pixels;      /* pixels showing a translucent surface */
  uint64_t lit_translucent_pixels;  /* of those, with finite exitance > 0 */
  uint64_t nonfinite_pixels;        /* pixels of the result that are NaN or infinite */
  /* Work of the profile sums: R_d evaluations (REFERENCE; 0 for the GPU methods,
   * whose work is fragment_invocations). For REFERENCE, stage_ms are CPU wall
   * times: BUFFERS = surface samples and their irradiance, SPLATTING = camera
   * rays, exitance sums and shading. */
  uint64_t kernel_evaluations;
  /* Irradiance hierarchy levels used and the samples selected at each level, summed
   * over light views (level-0 texels covered: sum of count * 4^level). */
  int32_t levels;
  uint64_t selected_per_level[8];
  int32_t splat_levels;  /* splatting levels used (1: single resolution) */
  /* SS_STAGE_SPLATTING split into its parts (the paper's Table 2): splatting into
   * level k over all light views, and eq. 17's accumulation (the third part,
   * selection_ms, is at the end). The debug selection pass, when on, is in the
   * stage total only; a budgeted render's measuring of its samples' bounds is in
   * no stage. */
  double splat_level_ms[8];
  uint64_t splat_level_fragments[8];
  double accumulation_ms;
  uint64_t accumulation_fragments;
  /* Irradiance resolution used (the automatic choice, or the one set), and the
   * irradiance texels across the shortest effective scattering range R_P at it,
   * on the light view whose texels on the translucent objects are coarsest. */
  int32_t irradiance_resolution;
  float texels_per_range;
  /* Jittered samples rendered (anti-aliasing); light_views counts every sample's. */
  int32_t samples;
  /* Shadow map resolution used (the automatic choice, or the one set). */
  int32_t shadow_resolution;
  /* With a splatting budget (ssSetSplatBudget): 1 when every splat is in the image, 0 when this
   * render stopped at the budget and the next goes on; and the share of the splats drawn (by light
   * view, level and sample). Without a budget: 1 and 1. */
  int32_t splatting_complete;
  float splatting_progress;
  /* Automatic irradiance resolution (API 19): 0 when the target error needs more texels per R_P
   * than the largest buffer gives (2048, or the GPU's texture limit): the render is at the
   * largest, and the error the resolution adds may exceed the target (docs/AUTO.md). 1 otherwise,
   * and at a fixed resolution. */
  int32_t target_reachable;
  /* SS_METHOD_MATERIAL_EDIT (API 20): the wall time of this render when it precomputed the
   * transport (0 when it reused it, and for the other methods); 1 when it reused the transport
   * of an earlier render; 1 when the scene has a heterogeneous material and the render was FULL's. */
  double precompute_ms;
  int32_t transport_reused;
  int32_t transport_full_pipeline;
  /* SS_METHOD_PRECOMPUTED (API 21; precompute_ms and transport_reused as above): the bytes its
   * precomputation holds (kernels, factors, atlases; counted against the memory budget), the
   * atlas texels and vertex-to-vertex factors over every object, and the CPU time of this
   * render's relighting (illumination maps, global and local response). 0 for other methods. */
  uint64_t precomputed_bytes;
  uint64_t precomputed_texels;
  uint64_t precomputed_factors;
  double relight_ms;
  /* SS_STAGE_SPLATTING's third part (API 23), besides the levels and the accumulation: Algorithm 1
   * run once per light view into the list of samples every level draws (select_samples.comp), over
   * all light views. A compute pass: no fragments. */
  double selection_ms;
} SsStats;

/* SS_METHOD_PRECOMPUTED (API 22): one translucent object of the precomputation the context holds
 * (ssGetPrecomputedObjects). Its bytes are what SsStats.precomputed_bytes sums. */
typedef struct SsPrecomputedObject {
  uint32_t object_id;
  uint32_t vertices;       /* welded vertices: the global response's basis */
  uint64_t bytes;          /* kernels, factors, atlas, outputs: held in memory while it serves */
  uint64_t texels;         /* atlas texels with a surface point (receivers) */
  uint64_t kernel_taps;    /* the local response's taps, over every texel */
  uint64_t factors;        /* vertex-to-vertex factors kept */
  int32_t atlas_width, atlas_height;
  float texel_size;        /* scene units */
  float local_range;       /* the local kernels' reach, scene units */
  double precompute_ms;    /* its share of the precomputation's wall time */
  /* API 24: the atlas's charts, and of them the islands of the mesh's UV map (docs/PRECOMPUTED.md,
   * "The mesh's own UV map"); the islands that are too stretched, fold or overlap themselves are
   * charted as a mesh without UVs is, and counted in uv_islands_refused. */
  int32_t charts, uv_charts, uv_islands_refused;
} SsPrecomputedObject;

/* Images of the last render besides the result, same size, bottom row first. */
typedef enum SsPass {
  SS_PASS_EXITANCE = 0,  /* rgb: B(x_o) of eq. 5 (W / unit^2); a: 1 on translucent pixels */
  /* With debug_passes, GPU methods: */
  SS_PASS_SELECTION = 1, /* selected irradiance samples where they land on visible surfaces, one
                            colour per irradiance level (0 red, 1 green, 2 blue, 3 yellow, 4
                            magenta, 5 cyan, 6 white, 7 orange); a: 1 where a sample landed */
  SS_PASS_LEVEL_EXITANCE = 2 /* + k: splatting level k's own exitance before accumulation,
                                nearest-upsampled to the frame; a: 1 */
} SsPass;

/* Called from the thread that called ssRender while a long render (REFERENCE)
 * runs, with the fraction done; return non-zero to stop it (ssRender then
 * returns SS_CANCELLED). */
typedef int32_t (*SsProgressCallback)(float fraction, void* user);

/* Library */
SS_API int32_t ssGetApiVersion(void);
SS_API const char* ssGetLastError(void);

/* The layout of this header's structs as the library was compiled: with field NULL, *size gets
 * sizeof(type) and *offset 0; otherwise *offset gets offsetof(type, field) and *size the field's
 * size (a whole array for array fields). Names as written here ("SsSettings", "lambda_z").
 * Bindings check their copies of the structs against it when they load the library.
 * Unknown type or field names: SS_INVALID_ARGUMENT. */
SS_API SsStatus ssGetStructLayout(const char* type, const char* field, uint32_t* offset, uint32_t* size);

/* The settings a new context starts with, every field set to its value (no 0 placeholders):
 * SS_METHOD_BRUTE at 512 texels, transparent background, and the defaults documented at
 * SsSettings. Set the fields you need by name on a copy. */
SS_API SsSettings ssDefaultSettings(void);

/* What the library holds now, over every context and thread: live handles and the GL
 * objects it created and has not deleted (leak tests, long sessions). A context released
 * while another OpenGL context (or none) is current cannot delete its GL objects there (their
 * names mean other objects in another context): they wait, counted in orphaned_gl_objects
 * and in no other count, until the next ssNewContext or GL-issuing call made with their own
 * OpenGL context current deletes them. */
typedef struct SsResourceCounts {
  int64_t contexts;
  int64_t profile_sets;
  int64_t images;
  int64_t textures, buffers, framebuffers, vertex_arrays, programs, queries;
  int64_t orphaned_gl_objects;
} SsResourceCounts;
SS_API SsStatus ssGetResourceCounts(SsResourceCounts* out);

/* The GPU memory budget, for all contexts of the process: every texture and buffer the library
 * makes is checked against it first, and a mesh or buffer beyond it fails with SS_LIMIT_EXCEEDED
 * naming what needed the memory (never a GL out-of-memory error). 0 (the default) is automatic:
 * 90 % of the memory the driver reports (GL_NVX_gpu_memory_info, GL_ATI_meminfo), else half of
 * the machine's RAM. Otherwise at least 1 MiB. */
SS_API SsStatus ssSetMemoryBudget(uint64_t bytes);
/* *used: bytes the library's textures and buffers hold now; *budget: the budget in force, or 0
 * while the automatic budget has not been measured (that needs a current OpenGL context). */
SS_API SsStatus ssGetMemoryUsage(uint64_t* used, uint64_t* budget);

/* Test hook: the OpenGL state a host relies on (bindings, blend, depth, cull, scissor, viewport,
 * pixel store, ...) as text, one "name=value" line each, queried from the current context apart
 * from the library's own state saving. Compare it before and after other calls. Writes at most
 * capacity bytes, NUL included; *length (optional) gets the text's length without the NUL;
 * SS_LIMIT_EXCEEDED when capacity is too small. */
SS_API SsStatus ssDescribeGlState(char* buffer, uint32_t capacity, uint32_t* length);

/* Context: needs a current OpenGL 4.3+ core context; GL-issuing calls (materials, meshes,
 * render, passes, scene loading) must be made with that same context current, or fail with
 * SS_GL_ERROR. Release it with that context current, or see SsResourceCounts. */
SS_API SsStatus ssNewContext(SsContext* out);
SS_API SsStatus ssReleaseContext(SsContext context);

/* Scene. Ids are the caller's; setting an existing id replaces it. */
SS_API SsStatus ssSetMaterial(SsContext context, uint32_t material_id, const SsMaterialDesc* material);
SS_API SsStatus ssSetMesh(SsContext context, uint32_t object_id, const SsMeshDesc* mesh);
SS_API SsStatus ssRemoveMesh(SsContext context, uint32_t object_id);
SS_API SsStatus ssClearScene(SsContext context);
SS_API SsStatus ssSetLights(SsContext context, const SsLightDesc* lights, uint32_t count);
SS_API SsStatus ssSetCamera(SsContext context, const SsCameraDesc* camera);
SS_API SsStatus ssSetSettings(SsContext context, const SsSettings* settings);
/* The settings in effect, defaults filled in (0 fields replaced by their values). */
SS_API SsStatus ssGetSettings(SsContext context, SsSettings* out);

/* The environment drawn where the camera sees no object (docs/WORLD.md): an equirectangular image
 * in Blender's convention (a world direction, turned by `rotation`, reads the image at
 * u = 0.5 - atan2(d.y, d.x) / 2 pi, v = atan2(d.z, hypot(d.x, d.y)) / pi + 0.5, bilinear, repeating
 * in u), times strength, alpha 1. It lights nothing itself (send its light as lights); image NULL:
 * none, the settings' background colour. The context keeps its own reference to the image. */
typedef struct SsEnvironmentDesc {
  SsImage image;
  float rotation[9];  /* column-major 3x3 applied to world directions before the look-up; all 0: identity */
  float strength;     /* in [0, 1e6] */
} SsEnvironmentDesc;
SS_API SsStatus ssSetEnvironment(SsContext context, const SsEnvironmentDesc* environment);

/* Renders width x height and writes linear RGBA floats, bottom row first. */
SS_API SsStatus ssRender(SsContext context, int32_t width, int32_t height, float* rgba_out);
SS_API SsStatus ssGetStats(SsContext context, SsStats* out);
/* The objects of the precomputation PRECOMPUTED holds (none before its first render, or after a
 * failed one): *count gets how many there are, and the first min(*count, capacity) are written
 * to out (which may be NULL when capacity is 0), in ascending object_id. */
SS_API SsStatus ssGetPrecomputedObjects(SsContext context, SsPrecomputedObject* out, uint32_t capacity,
                                        uint32_t* count);
/* At most `fragments` splatting fragment invocations per ssRender of a GPU method (0, the
 * default: no budget). A render that reaches it shows the splats drawn so far; the next render
 * goes on where it stopped while nothing was changed since (any ssSet*, ssRemoveMesh,
 * ssClearScene or ssLoadScene call, a different camera or size restarts), until
 * SsStats.splatting_complete is 1: then its image equals one render without a budget. Ignored
 * with debug_passes and where the driver counts no fragments (docs/VIEWPORT.md). */
SS_API SsStatus ssSetSplatBudget(SsContext context, uint64_t fragments);
/* Copies a pass of the last successful render: width * height RGBA floats. */
SS_API SsStatus ssGetPass(SsContext context, int32_t pass, int32_t width, int32_t height, float* rgba_out);
/* NULL callback: none. */
SS_API SsStatus ssSetProgressCallback(SsContext context, SsProgressCallback callback, void* user);

/* Scene files (docs/SCENE_FILE.md): everything the context was given (materials,
 * meshes, lights, camera, settings) and the size of its last frame, for replaying a
 * frame without the host application (subsplat_replay) and for bug reports. Paths
 * are UTF-8. Loading replaces the context's scene and settings through the same
 * checks as the calls above; on failure the scene is left empty. frame_width and
 * frame_height may be NULL; they get 0 when the file holds no frame. */
SS_API SsStatus ssSaveScene(SsContext context, const char* path);
SS_API SsStatus ssLoadScene(SsContext context, const char* path, int32_t* frame_width, int32_t* frame_height);

/* Heterogeneous materials (docs/HETEROGENEOUS.md, docs/SUBEDIT_FILE.md); no GL needed.
 * A profile set models a map of SubEdit profiles with no more than it needs: texels with
 * the same profile share one, more than 64 different profiles are clustered, and the
 * number of segments is the smallest that keeps the profiles within `tolerance`, the
 * relative energy error allowed (mean over texels; in [1e-6, 1], 0 for the default 0.01). */
typedef struct SsProfileSetDesc {
  uint32_t segments;          /* n in [1, 1024]: knots r_k = k r_s / n, k = 0..n */
  float radius_mm;            /* r_s in (0, 1e6] */
  uint32_t width, height;     /* texels in [1, 16384]; texel (x, y) covers u in [x, x+1) / width,
                                 v in [y, y+1) / height (row 0 at v = 0); the map repeats */
  const float* log_profiles;  /* width * height * (n + 1) * 3: ln P(r_k) in 1/mm^2, finite and
                                 in [-1000, 50]; texel-major, then knot, then RGB */
} SsProfileSetDesc;

typedef struct SsProfileSetInfo {
  uint32_t segments;          /* n chosen */
  uint32_t profiles;          /* palette entries (1: homogeneous) */
  uint32_t width, height;     /* the map (1 x 1 when homogeneous) */
  float radius_mm;
  float fit_error;            /* mean relative energy error against the source */
  float max_fit_error;        /* largest, over texels and channels */
  float effective_range_mm[2];/* shortest and longest R_P over profiles and channels */
  uint64_t gpu_bytes;         /* splat kernel tables and map */
  uint32_t source_segments, source_profiles; /* what the source had: n, distinct profiles */
} SsProfileSetInfo;

SS_API SsStatus ssNewProfileSet(const SsProfileSetDesc* desc, float tolerance, SsProfileSet* out);
/* One homogeneous medium per texel: 3 * width * height values each of sigma_a and sigma_s' (per
 * mm), texel-major then RGB, its radial profile from profile_model (SsProfileModel); each profile
 * keeps its model's total reflectance. */
SS_API SsStatus ssNewProfileSetFromDipoles(uint32_t width, uint32_t height, const float* sigma_a,
                                           const float* sigma_s_prime, float eta, float tolerance,
                                           int32_t profile_model, SsProfileSet* out);
/* A SubEdit file (OpenEXR; docs/SUBEDIT_FILE.md). Path in UTF-8. */
SS_API SsStatus ssLoadProfileSet(const char* path, float tolerance, SsProfileSet* out);
/* Writes the set as a SubEdit file, one texel per map texel. */
SS_API SsStatus ssSaveProfileSet(SsProfileSet set, const char* path);
SS_API SsStatus ssGetProfileSetInfo(SsProfileSet set, SsProfileSetInfo* out);
SS_API SsStatus ssReleaseProfileSet(SsProfileSet set);

/* Images (docs/TEXTURES.md); no GL needed until a material that uses one is rendered.
 * Materials keep their own reference, so an image may be released after ssSetMaterial. */
typedef struct SsImageDesc {
  uint32_t width, height;  /* texels in [1, 16384]; row 0 at v = 0 */
  const float* rgb;        /* 3 * width * height scene-linear values, finite, in [0, 1e4] */
} SsImageDesc;
SS_API SsStatus ssNewImage(const SsImageDesc* desc, SsImage* out);
SS_API SsStatus ssReleaseImage(SsImage image);

/* Material model, no GL needed. */
typedef struct SsProfileInfo {
  float total_reflectance[3];  /* Rd_total: integral of R_d over the plane */
  float effective_range[3];    /* R_P: radius keeping 95% of the energy, scene units */
  float support_radius;        /* radius splats reach, scene units */
} SsProfileInfo;
/* DIPOLE materials; SUBEDIT: the set's most common profile. */
SS_API SsStatus ssGetProfileInfo(const SsMaterialDesc* material, SsProfileInfo* out);
/* Rd_total of a dipole (Jensen et al. 2001) for each of `count` reduced albedos in [0, 1] under
 * the relative index eta (positive): the add-on inverts it to read a Principled BSDF's colour. */
SS_API SsStatus ssDipoleTotalReflectance(uint64_t count, const double* reduced_albedo, double eta, double* out);
/* The same for either profile model (SsProfileModel): what a DIPOLE material of that model
 * reflects of a normal beam over the whole plane, per single-scattering albedo in [0, 1]. */
SS_API SsStatus ssTotalReflectance(int32_t profile_model, uint64_t count, const double* albedo, double eta,
                                   double* out);

#ifdef __cplusplus
}
#endif
#endif
