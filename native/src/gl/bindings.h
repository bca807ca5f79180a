// The one table of bindings: every texture unit, image unit and shader storage binding the
// passes use, and the enums GLSL shares with the C API. Each row is written once, here; it
// becomes a C++ constant (gl::UNIT_SPLATTING_POSITION_OBJECT) and a GLSL #define of the same
// name that compileShader puts before every shader (layout(binding = UNIT_...)). StateGuard
// saves and restores exactly the units and bindings listed.
//
// One texture unit per sampler of the shaders, one image unit per image: a pass never finds
// another pass's texture on its units, and a program's samplers are bound once, when linked.
#pragma once

#include <epoxy/gl.h>

#include <string>

#include "subsplat/subsplat.h"

// X(name, unit, target): texture units, named as the shaders' samplers.
#define SUBSPLAT_TEXTURE_UNITS(X)                             \
  X(UNIT_IRRADIANCE_POSITION_MATERIAL, 0, GL_TEXTURE_2D)      \
  X(UNIT_IRRADIANCE_FLUX_FOOTPRINT, 1, GL_TEXTURE_2D)         \
  X(UNIT_IRRADIANCE_NORMAL_OBJECT, 2, GL_TEXTURE_2D)          \
  X(UNIT_IRRADIANCE_DEPTH_RANGE, 3, GL_TEXTURE_2D)            \
  X(UNIT_IRRADIANCE_PROFILE_SPLIT, 4, GL_TEXTURE_2D)          \
  X(UNIT_IRRADIANCE_LIGHT_DEPTH, 5, GL_TEXTURE_2D)            \
  X(UNIT_SPLATTING_POSITION_OBJECT, 6, GL_TEXTURE_2D)         \
  X(UNIT_SPLATTING_NORMAL_MATERIAL, 7, GL_TEXTURE_2D)         \
  X(UNIT_SPLAT_KERNELS, 8, GL_TEXTURE_2D_ARRAY)               \
  X(UNIT_MINIMAL_RADIUS, 9, GL_TEXTURE_2D)                    \
  X(UNIT_COARSE_EXITANCE, 10, GL_TEXTURE_2D)                  \
  X(UNIT_EXITANCE_BUFFER, 11, GL_TEXTURE_2D)                  \
  X(UNIT_DIRECT_RADIANCE, 12, GL_TEXTURE_2D)                  \
  X(UNIT_PROFILE_MAPS, 13, GL_TEXTURE_BUFFER)                 \
  X(UNIT_TRIANGLE_MATERIALS, 14, GL_TEXTURE_BUFFER)           \
  X(UNIT_FINE_POSITION_MATERIAL, 15, GL_TEXTURE_2D)           \
  X(UNIT_FINE_FLUX_FOOTPRINT, 16, GL_TEXTURE_2D)              \
  X(UNIT_FINE_NORMAL_OBJECT, 17, GL_TEXTURE_2D)               \
  X(UNIT_FINE_DEPTH_RANGE, 18, GL_TEXTURE_2D)                 \
  X(UNIT_FINE_PROFILE_SPLIT, 19, GL_TEXTURE_2D)               \
  X(UNIT_FINE_POSITION_OBJECT, 20, GL_TEXTURE_2D)             \
  X(UNIT_FINE_NORMAL_MATERIAL, 21, GL_TEXTURE_2D)           \
  X(UNIT_TRANSPORT_TABLES, 22, GL_TEXTURE_2D_ARRAY)         \
  X(UNIT_IRRADIANCE_EXIT_DEPTH, 23, GL_TEXTURE_2D)             \
  X(UNIT_FIRST_SAMPLE_POSITION_OBJECT, 24, GL_TEXTURE_2D)     \
  X(UNIT_SHADOW_DEPTH, 25, GL_TEXTURE_2D)                     \
  X(UNIT_SPLATTING_ALBEDO, 26, GL_TEXTURE_2D)                 \
  X(UNIT_SPLATTING_SHADING_NORMAL, 27, GL_TEXTURE_2D)         \
  X(UNIT_TEXTURE_TEXELS, 28, GL_TEXTURE_BUFFER)               \
  X(UNIT_ENVIRONMENT, 29, GL_TEXTURE_2D)                      \
  X(UNIT_SOFT_DEPTH, 30, GL_TEXTURE_2D)                       \
  X(UNIT_BASIS_KERNELS, 31, GL_TEXTURE_2D_ARRAY)              \
  X(UNIT_COARSE_TRANSPORT, 32, GL_TEXTURE_2D_ARRAY)           \
  X(UNIT_NEAR_TRANSPORT, 33, GL_TEXTURE_2D_ARRAY)             \
  X(UNIT_FAR_TRANSPORT, 34, GL_TEXTURE_2D_ARRAY)              \
  X(UNIT_EDIT_FACTORS, 35, GL_TEXTURE_2D)                     \
  X(UNIT_KEPT_THROUGH, 36, GL_TEXTURE_2D_ARRAY)

// X(name, unit): image units, which the hierarchies' reductions write the coarser level through.
#define SUBSPLAT_IMAGE_UNITS(X)              \
  X(IMAGE_COARSE_POSITION_MATERIAL, 0)       \
  X(IMAGE_COARSE_FLUX_FOOTPRINT, 1)          \
  X(IMAGE_COARSE_NORMAL_OBJECT, 2)           \
  X(IMAGE_COARSE_DEPTH_RANGE, 3)             \
  X(IMAGE_COARSE_PROFILE_SPLIT, 4)           \
  X(IMAGE_COARSE_POSITION_OBJECT, 5)         \
  X(IMAGE_COARSE_NORMAL_MATERIAL, 6)         \
  X(IMAGE_FLUX_FOOTPRINT, 7)

// X(name, binding): indexed shader storage buffer bindings.
#define SUBSPLAT_STORAGE_BINDINGS(X) \
  X(STORAGE_MATERIALS, 0)            \
  X(STORAGE_SELECTION_COUNTS, 1)    \
  X(STORAGE_COVERAGE_COUNTS, 2)      \
  X(STORAGE_SPLAT_BOUNDS, 3)         \
  X(STORAGE_EDIT_COEFFICIENTS, 4)     \
  X(STORAGE_SAMPLE_RANKS, 5)          \
  X(STORAGE_SAMPLE_BLOCKS, 6)         \
  X(STORAGE_SAMPLE_LIST, 7)

// X(name, value): enums the shaders share with the C API (subsplat.h).
#define SUBSPLAT_SHARED_ENUMS(X)    \
  X(LIGHT_POINT, SS_LIGHT_POINT)    \
  X(LIGHT_SPOT, SS_LIGHT_SPOT)      \
  X(LIGHT_SUN, SS_LIGHT_SUN)        \
  X(LIGHT_AREA, SS_LIGHT_AREA)

namespace subsplat::gl {

#define SUBSPLAT_CONSTANT(name, value, ...) constexpr int name = value;
SUBSPLAT_TEXTURE_UNITS(SUBSPLAT_CONSTANT)
SUBSPLAT_IMAGE_UNITS(SUBSPLAT_CONSTANT)
SUBSPLAT_STORAGE_BINDINGS(SUBSPLAT_CONSTANT)
SUBSPLAT_SHARED_ENUMS(SUBSPLAT_CONSTANT)
#undef SUBSPLAT_CONSTANT

#define SUBSPLAT_VALUE(name, value, ...) value,
constexpr int kTextureUnits[] = {SUBSPLAT_TEXTURE_UNITS(SUBSPLAT_VALUE)};
constexpr int kImageUnits[] = {SUBSPLAT_IMAGE_UNITS(SUBSPLAT_VALUE)};
constexpr int kStorageBindings[] = {SUBSPLAT_STORAGE_BINDINGS(SUBSPLAT_VALUE)};
#undef SUBSPLAT_VALUE

// The table as GLSL: one "#define NAME value" line per row.
const std::string& glslBindingDefines();

}  // namespace subsplat::gl
