// Irradiance buffer hierarchy (paper sec. 4, step 1): level k + 1 from the
// 2 x 2 children at level k. Flux adds up (energy is kept), position and
// normal average, the footprint doubles, and the depth range is the min/max
// of the children (Nichols et al.). A coarse texel whose children are not all
// the same translucent material of the same object is marked mixed (-3):
// adaptive selection never picks it, so it descends to its children. Children
// of one heterogeneous material with different profiles are not mixed (the
// paper's mipmapped texture coordinates): the coarse texel takes the first
// child's profile and, where the children show a second one, the share and
// centroid of the second profile's parts (the split, irradiance_buffer.frag);
// eq. 11 checks the texel against the shorter range of the two (splat.vert).
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = UNIT_FINE_POSITION_MATERIAL) uniform sampler2D finePositionMaterial;
layout(binding = UNIT_FINE_FLUX_FOOTPRINT) uniform sampler2D fineFluxFootprint;
layout(binding = UNIT_FINE_NORMAL_OBJECT) uniform sampler2D fineNormalObject;
layout(binding = UNIT_FINE_DEPTH_RANGE) uniform sampler2D fineDepthRange;  // rg: min, max; at level 0 the light depth (r)
layout(binding = UNIT_FINE_PROFILE_SPLIT) uniform sampler2D fineProfileSplit;  // when profileSplits != 0
uniform int profileSplits;
uniform int fineLevel;
uniform ivec2 coarseSize;
layout(rgba32f, binding = IMAGE_COARSE_POSITION_MATERIAL) writeonly uniform image2D coarsePositionMaterial;
layout(rgba32f, binding = IMAGE_COARSE_FLUX_FOOTPRINT) writeonly uniform image2D coarseFluxFootprint;
layout(rgba32f, binding = IMAGE_COARSE_NORMAL_OBJECT) writeonly uniform image2D coarseNormalObject;
layout(rg32f, binding = IMAGE_COARSE_DEPTH_RANGE) writeonly uniform image2D coarseDepthRange;
layout(rgba16f, binding = IMAGE_COARSE_PROFILE_SPLIT) writeonly uniform image2D coarseProfileSplit;
void main() {
  ivec2 c = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(c, coarseSize))) return;
  vec3 position = vec3(0.0), flux = vec3(0.0), normal = vec3(0.0);
  float footprint = 0.0, material = 0.0, object = 0.0;
  vec2 range = vec2(1e30, -1e30);
  bool same = true;
  int other = -1;               // the second profile's entry
  float otherShare = 0.0;       // its share of the coarse texel
  vec3 otherMoment = vec3(0.0); // share-weighted position of its parts
  for (int i = 0; i < 4; ++i) {
    ivec2 f = 2 * c + ivec2(i & 1, i >> 1);
    vec4 pm = texelFetch(finePositionMaterial, f, fineLevel);
    vec4 ff = texelFetch(fineFluxFootprint, f, fineLevel);
    vec4 no = texelFetch(fineNormalObject, f, fineLevel);
    vec2 dr = texelFetch(fineDepthRange, f, fineLevel).rg;
    if (fineLevel == 0) dr.g = dr.r;
    range = vec2(min(range.x, dr.x), max(range.y, dr.y));
    if (i == 0) {
      material = pm.w;
      object = no.w;
    } else if (no.w != object || (pm.w != material && (pm.w < 0.0 || material < 0.0 ||
               materials[int(pm.w)].profileMap.w != materials[int(material)].profileMap.w))) {
      same = false;
    }
    if (profileSplits != 0 && pm.w >= 0.0) {
      // The child's two parts: its own profile and its split's.
      vec4 split = texelFetch(fineProfileSplit, f, fineLevel);
      int code = int(split.w + 0.5), count = code % 32;
      float share = float(count) / 16.0;
      vec3 offset = split.xyz * ff.a;
      int entries[2] = int[2](int(pm.w), int(materials[int(pm.w)].profileMap.w) + code / 32);
      float shares[2] = float[2](1.0 - share, share);
      vec3 at[2] = vec3[2](pm.xyz - (share < 1.0 ? offset * (share / (1.0 - share)) : vec3(0.0)), pm.xyz + offset);
      for (int j = 0; j < 2; ++j) {
        if (shares[j] <= 0.0 || entries[j] == int(material)) continue;
        if (other < 0) other = entries[j];
        if (entries[j] != other) continue;  // a third profile counts as the first child's
        otherShare += 0.25 * shares[j];
        otherMoment += 0.25 * shares[j] * at[j];
      }
    }
    position += pm.xyz;
    flux += ff.rgb;
    footprint += ff.a;
    normal += no.xyz;
  }
  bool valid = same && material >= 0.0;
  float length2 = dot(normal, normal);
  imageStore(coarsePositionMaterial, c, vec4(0.25 * position, valid ? material : -3.0));
  imageStore(coarseFluxFootprint, c, vec4(flux, 0.5 * footprint));  // 2 x the mean
  imageStore(coarseNormalObject, c, vec4(length2 > 0.0 ? normal * inversesqrt(length2) : vec3(0.0, 0.0, 1.0),
                                         valid ? object : -3.0));
  imageStore(coarseDepthRange, c, vec4(range, 0.0, 0.0));
  if (profileSplits != 0) {
    int count = other >= 0 && valid ? clamp(int(round(16.0 * otherShare)), 1, 16) : 0;
    vec4 split = vec4(0.0);
    if (count > 0)
      split = vec4((otherMoment / otherShare - 0.25 * position) / max(0.5 * footprint, 1e-30),
                   float((other - int(materials[int(material)].profileMap.w)) * 32 + count));
    imageStore(coarseProfileSplit, c, split);
  }
}
