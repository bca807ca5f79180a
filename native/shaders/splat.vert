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
  vec3 shiftDrops;    // per channel, along the normal onto the surface (surfaceDrop)
} sampleOut;

// How far along the sample's normal n the forward-shifted centre x + dir s moves onto the surface
// (dir: the shift's unit direction along the surface, s its length). On a curved part the point of
// the tangent plane lies off the surface (above a convex part by about s^2 / 2R), where the
// profile's peak would never be reached; REFERENCE moves it with a ray (reference_renderer.cpp:
// ontoSurface). The GPU has no rays: here the surface is taken as the paraboloid through x, of
// normal n, that holds a surface point the light view sees (the finest level of the irradiance
// buffer) over x + dir s, else over x + dir s / 2, x - dir s / 2 or x - dir s (the points ahead
// fail near the light's silhouette, which the shift moves towards). That point's height z over the
// tangent plane at squared distance u2 along it gives the height z s^2 / u2 at s, within +-s. 0
// where the light view sees no surface of the object at any of them but x's own neighbourhood.
float surfaceDrop(vec3 x, vec3 n, vec3 dir, float s, float object) {
  if (!(s > 0.0)) return 0.0;
  const float ahead[4] = float[4](1.0, 0.5, -0.5, -1.0);
  for (int k = 0; k < 4; ++k) {
    float f = ahead[k];
    vec4 clip = lightViewProj * vec4(x + dir * (f * s), 1.0);
    if (clip.w <= 0.0) continue;
    vec2 q = clip.xy / clip.w;
    if (any(greaterThanEqual(abs(q), vec2(1.0)))) continue;
    ivec2 t = clamp(ivec2((q * 0.5 + 0.5) * float(resolution)), ivec2(0), ivec2(resolution - 1));
    vec4 pm = texelFetch(irradiancePositionMaterial, t, 0);
    vec4 no = texelFetch(irradianceNormalObject, t, 0);
    if (pm.w < 0.0 || no.w != object) continue;
    vec3 d = pm.xyz - x;
    float z = dot(d, n), u2 = dot(d, d) - z * z;
    if (u2 <= 0.0625 * f * f * s * s) continue;  // too near x to tell its curvature
    return clamp(z * s * s / u2, -s, s);
  }
  return 0.0;
}

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
  sampleOut.shiftDrops = vec3(0.0);
  if (forwardShifts != 0 && pm.w >= 0.0 && isTabulated(m) && dot(no.xyz, no.xyz) > 0.0) {
    vec3 n = normalize(no.xyz);
    sampleOut.along = forwardShift(m, pm.xyz, n, sampleOut.normalMu0.w, sampleOut.shiftLengths);
    float sinT = length(sampleOut.along);
    vec3 dir = sinT > 0.0 ? sampleOut.along / sinT : vec3(0.0);
    for (int c = 0; c < 3; ++c)
      sampleOut.shiftDrops[c] = surfaceDrop(pm.xyz, n, dir, sinT * sampleOut.shiftLengths[c], no.w);
  }
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
