// Splatting: one vertex per irradiance texel. BRUTE draws every texel of the
// finest level (Shah et al. 2009). The adaptive methods draw every texel of
// every level and keep those Algorithm 1 selects (DESIGN.md's reading of it):
// a texel is valid at level k when its depth range is below z0 and the level's
// texel, projected onto the surface, is fine enough for the material,
//   texel_k / |n.L| < R_P / alpha            (eq. 10, 11 with T^k = R_w / texel_k);
// it is selected when no ancestor is valid and it is valid itself or at level 0.
// A texel that shows two profiles (its split) must be fine enough for both.
// Each level-0 texel is therefore covered by exactly one selected sample.
layout(binding = UNIT_IRRADIANCE_POSITION_MATERIAL) uniform sampler2D irradiancePositionMaterial;
layout(binding = UNIT_IRRADIANCE_FLUX_FOOTPRINT) uniform sampler2D irradianceFluxFootprint;
layout(binding = UNIT_IRRADIANCE_NORMAL_OBJECT) uniform sampler2D irradianceNormalObject;
layout(binding = UNIT_IRRADIANCE_DEPTH_RANGE) uniform sampler2D irradianceDepthRange;  // levels >= 1
layout(binding = UNIT_IRRADIANCE_PROFILE_SPLIT) uniform sampler2D irradianceProfileSplit;  // when profileSplits != 0 (pipeline/irradiance_buffer.h)
uniform int profileSplits;
uniform int resolution;
uniform int levels;              // 1: BRUTE
uniform int levelOffset[9];      // first vertex of each level; levelOffset[levels] = total
uniform float z0;                // depth-range threshold, scene units
uniform float alpha;             // eq. 11's scale
uniform int splatLevel;          // selections are counted in the pass of splatting level 0
uniform int measureBounds;       // 1: the splatting budget's pass (splat.geom), which counts nothing
// MATERIAL_EDIT's precomputation (transport_splat.geom): each TABULATED sample's slab geometry
// (common.glsl: slabGeometry) from this view's light and exit depths, at the finest texel under it.
uniform int slabGeometries;
layout(binding = UNIT_IRRADIANCE_LIGHT_DEPTH) uniform sampler2D irradianceLightDepth;
layout(binding = UNIT_IRRADIANCE_EXIT_DEPTH) uniform sampler2D irradianceExitDepth;
layout(std430, binding = STORAGE_SELECTION_COUNTS) buffer SelectionCounts { uint selected[8]; };
out SplatSample {
  vec3 position;
  vec3 flux;
  float footprint;
  float object;
  int material;
  int level;  // irradiance level the sample was selected at
  vec4 split; // xyz the offset of a second profile's part, w its entry * 32 + sixteenths (0: none)
  vec4 normalMu0; // the texel's normal (facing the light) and its cosine to the light
  vec2 slab;      // with slabGeometries, TABULATED: slabGeometry at the texel
} sampleOut;

bool valid(int level, ivec2 texel) {
  vec4 pm = texelFetch(irradiancePositionMaterial, texel, level);
  int m = int(pm.w);
  if (pm.w < 0.0 || !isTranslucent(m)) return false;
  vec2 range = texelFetch(irradianceDepthRange, texel, level).rg;
  if (range.y - range.x >= z0) return false;
  vec3 n = texelFetch(irradianceNormalObject, texel, level).xyz;
  float nl = max(abs(dot(n, towardsLight(pm.xyz))), 1e-3);  // grazing: finest level, never infinite
  float texel0 = lightType == LIGHT_SUN ? shadowTexelSize : shadowTexelSize * distance(pm.xyz, lightPosition);
  float rangeP = materials[m].ranges.z;
  if (profileSplits != 0) {
    int code = int(texelFetch(irradianceProfileSplit, texel, level).w + 0.5);
    if (code % 32 != 0) rangeP = min(rangeP, materials[int(materials[m].profileMap.w) + code / 32].ranges.z);
  }
  return float(1 << level) * texel0 / nl < rangeP / alpha;
}

void main() {
  int level = 0;
  while (level + 1 < levels && gl_VertexID >= levelOffset[level + 1]) ++level;
  int size = max(resolution >> level, 1);
  int index = gl_VertexID - levelOffset[level];
  ivec2 texel = ivec2(index % size, index / size);
  sampleOut.material = -1;
  sampleOut.level = level;
  sampleOut.split = vec4(0.0);
  sampleOut.normalMu0 = vec4(0.0);
  sampleOut.slab = vec2(0.0);
  gl_Position = vec4(0.0);
  if (levels > 1) {
    for (int k = level + 1; k < levels; ++k)
      if (valid(k, texel >> (k - level))) return;
    if (level > 0 && !valid(level, texel)) return;
  }
  vec4 pm = texelFetch(irradiancePositionMaterial, texel, level);
  vec4 ff = texelFetch(irradianceFluxFootprint, texel, level);
  int m = int(pm.w);
  if (splatLevel == 0 && measureBounds == 0 && pm.w >= 0.0 && isTranslucent(m)) atomicAdd(selected[level], 1u);
  sampleOut.position = pm.xyz;
  sampleOut.material = m;
  sampleOut.flux = ff.rgb;
  sampleOut.footprint = ff.a;
  vec4 no = texelFetch(irradianceNormalObject, texel, level);
  sampleOut.object = no.w;
  sampleOut.normalMu0 = vec4(no.xyz, clamp(dot(no.xyz, towardsLight(pm.xyz)), 0.0, 1.0));
  if (slabGeometries != 0 && pm.w >= 0.0 && isTabulated(m)) {
    ivec2 fine = texel << level;
    sampleOut.slab = slabGeometry(texelFetch(irradianceNormalObject, fine, 0), texelFetch(irradianceLightDepth, fine, 0).r,
                                  texelFetch(irradianceExitDepth, fine, 0), sampleOut.normalMu0.w);
  }
  if (profileSplits != 0) {
    vec4 split = texelFetch(irradianceProfileSplit, texel, level);
    sampleOut.split = vec4(split.xyz * ff.a, split.w);
  }
}
