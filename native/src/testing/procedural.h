// Procedural scenes for calibrating and testing the automatic quality (docs/AUTO.md, "Held-out
// scenes"): random closed shapes (blobs, thin plates, rods, tori), sizes from 1 mm to 10 m, every
// measured preset and random media, dipole and tabulated profiles, suns, spots and point lights,
// an opaque floor or none, and a camera from any side. A scene is a function of its set and index.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "subsplat/subsplat.h"

namespace subsplat::testing {

// The two sets are disjoint by construction: a scene's seed carries its set in the top bit
// (sceneSeed), so no calibration scene can be drawn again as a test scene.
// Jensen et al. 2001's measured media (addon/subsplat/presets.py): sigma_s' and sigma_a per mm.
struct PresetMedium {
  const char* name;
  float sigmaSPrime[3], sigmaA[3];
};
constexpr int kPresetMediaCount = 11;
extern const PresetMedium kPresetMedia[kPresetMediaCount];

enum class SceneSet { Calibration = 0, Test = 1 };
uint64_t sceneSeed(SceneSet set, int index);
const char* setName(SceneSet set);

struct ProceduralMesh {
  std::vector<float> positions, normals;
  std::vector<uint32_t> indices;
  uint32_t material = 0;
  SsMeshDesc desc() const;  // identity object_to_world: positions are in the world
};

struct ProceduralScene {
  uint64_t seed = 0;
  std::string description;  // "plate r=0.23 m (0.8 units) Skin1 dipole; sun+spot; floor"
  std::vector<ProceduralMesh> meshes;
  std::vector<SsMaterialDesc> materials;  // id = index
  std::vector<SsLightDesc> lights;
  SsCameraDesc camera{};
  float radius = 0.0f;  // the translucent object's bounding radius, scene units
  float mmPerUnit = 0.0f;
  float pixel = 0.0f;  // a pixel's size at the object's nearest depth, scene units
  // Sends the materials, meshes, lights and camera to the context; the first failure, or SS_OK.
  SsStatus apply(SsContext context) const;
};

// The scene `index` of `set`, for a width x height image (the camera's aspect).
ProceduralScene proceduralScene(SceneSet set, int index, int width, int height);

// The automatic resolution's rungs (native/src/pipeline/auto_quality.cpp).
constexpr int kRungs[] = {128, 192, 256, 384, 512, 768, 1024, 1536, 2048};
// Texels across R_P at which a reference image counts as converged (docs/AUTO.md, "Held-out scenes").
constexpr double kReferenceTexels = 128.0;
// The resolution a render at `resolution` is measured against: the first rung at least four times
// as fine with kReferenceTexels across R_P (texelsPerRange at `resolution` grows with the rung), at
// most 2048.
int referenceResolution(int resolution, double texelsPerRange);

// The error model fitted on the calibration set (bench/auto_sets.sh, bench/auto_fit.py; docs/AUTO.md,
// "Held-out scenes"): the error a resolution adds over a converged buffer's is at most
// kModelError * t^-kModelPower, t the coarsest light texels across max(R, kModelPixels pixels), R the
// radius holding kModelEnergy of the shortest profile's energy.
constexpr double kModelEnergy = 0.25, kModelPixels = 1.0, kModelError = 0.5148, kModelPower = 2.0;

// The shortest radius holding `energy` of a translucent material's channel's profile, scene units
// (procedural_radius.cpp: only for what links the library's code).
double shortestRadius(const ProceduralScene& scene, double energy);

// `method` with automatic levels at an irradiance resolution (0: automatic for targetError) into
// `rgba` (width x height RGBA) and `stats`, hard shadows from 2048-texel maps whatever the
// irradiance resolution (the automatic shadow map follows it: the held-out test measures what the
// irradiance resolution adds, not the opaque surfaces' shadow maps); the first failure, or SS_OK.
SsStatus renderAt(SsContext context, int method, int width, int height, int resolution, float targetError,
                  std::vector<float>& rgba, SsStats& stats);
// Relative RMSE of rgb: |image - reference| / |reference| over every pixel (the background adds
// nothing to either).
double relativeRmse(const std::vector<float>& image, const std::vector<float>& reference);

}  // namespace subsplat::testing
