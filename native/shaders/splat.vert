// Splatting: one vertex per listed sample (select_samples.comp: Algorithm 1, run once per light
// view). BRUTE's list is every finest texel of a translucent material (Shah et al. 2009); the
// adaptive methods' is the texels Algorithm 1 selects from every level, in the same order.
layout(binding = UNIT_IRRADIANCE_POSITION_MATERIAL) uniform sampler2D irradiancePositionMaterial;
layout(binding = UNIT_IRRADIANCE_FLUX_FOOTPRINT) uniform sampler2D irradianceFluxFootprint;
layout(binding = UNIT_IRRADIANCE_NORMAL_OBJECT) uniform sampler2D irradianceNormalObject;
layout(binding = UNIT_IRRADIANCE_PROFILE_SPLIT) uniform sampler2D irradianceProfileSplit;  // when profileSplits != 0 (pipeline/irradiance_buffer.h)
uniform int profileSplits;
uniform int resolution;
uniform int levels;              // 1: BRUTE
uniform int levelOffset[9];      // first sample of each level; levelOffset[levels] = total
// MATERIAL_EDIT's precomputation (transport_splat.geom): each TABULATED sample's slab geometry
// (common.glsl: slabGeometry) from this view's light and exit depths, at the finest texel under it.
uniform int slabGeometries;
// The TABULATED model's forward shift (SsSettings::forward_shift; 0 in MATERIAL_EDIT's transport).
uniform int forwardShifts;
layout(binding = UNIT_IRRADIANCE_LIGHT_DEPTH) uniform sampler2D irradianceLightDepth;
layout(binding = UNIT_IRRADIANCE_EXIT_DEPTH) uniform sampler2D irradianceExitDepth;
layout(std430, binding = STORAGE_SAMPLE_LIST) readonly buffer SampleList {
  uint command[4];
  uint samples[];
};
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
  vec3 along;         // TABULATED: the forward shift (common.glsl: forwardShift); 0 otherwise
  vec3 shiftLengths;
} sampleOut;

void main() {
  int i = int(samples[gl_VertexID]);
  int level = 0;
  while (level + 1 < levels && i >= levelOffset[level + 1]) ++level;
  int size = max(resolution >> level, 1);
  int index = i - levelOffset[level];
  ivec2 texel = ivec2(index % size, index / size);
  sampleOut.level = level;
  sampleOut.split = vec4(0.0);
  sampleOut.slab = vec2(0.0);
  gl_Position = vec4(0.0);
  vec4 pm = texelFetch(irradiancePositionMaterial, texel, level);
  vec4 ff = texelFetch(irradianceFluxFootprint, texel, level);
  int m = int(pm.w);
  sampleOut.position = pm.xyz;
  sampleOut.material = m;
  sampleOut.flux = ff.rgb;
  sampleOut.footprint = ff.a;
  vec4 no = texelFetch(irradianceNormalObject, texel, level);
  sampleOut.object = no.w;
  sampleOut.normalMu0 = vec4(no.xyz, clamp(dot(no.xyz, towardsLight(pm.xyz)), 0.0, 1.0));
  sampleOut.along = vec3(0.0);
  sampleOut.shiftLengths = vec3(0.0);
  if (forwardShifts != 0 && pm.w >= 0.0 && isTabulated(m) && dot(no.xyz, no.xyz) > 0.0)
    sampleOut.along = forwardShift(m, pm.xyz, normalize(no.xyz), sampleOut.normalMu0.w, sampleOut.shiftLengths);
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
