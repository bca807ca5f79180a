// Splat accumulation (eq. 17): adds the accumulated exitance of level k + 1,
// upsampled with bilinear, depth and material weights, to level k. Pixels of
// another object get no weight (light does not scatter between objects).
// MATERIAL_EDIT's transport (transportLayers 8: transport_splat.frag) is gathered the same way,
// every layer of the coarse level's array with the same weights.
layout(binding = UNIT_COARSE_EXITANCE) uniform sampler2D coarseExitance;           // level k + 1, already accumulated
layout(binding = UNIT_COARSE_TRANSPORT) uniform sampler2DArray coarseTransport;   // transportLayers > 0
uniform int transportLayers;
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;  // the median-depth hierarchy
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
uniform int fineLevel;
uniform ivec2 coarseSize;
uniform vec3 cameraPosition;
uniform vec3 cameraForward;
uniform float lambdaZ, lambdaM;
uniform float boundingDiameter;  // R_w
layout(location = 0) out vec4 exitance[8];

// Eq. 17's material weight, exp(-lambda_m |R_P(x_o) - R_P(x_j)|), with R_P
// in millimetres, the unit the paper's profiles are measured in: a property of
// the materials, whatever the scene's unit or size (docs/HETEROGENEOUS.md).
float materialWeight(int a, int b) {
  float ra = materials[a].ranges.y * materials[a].ranges.w, rb = materials[b].ranges.y * materials[b].ranges.w;
  return exp(-lambdaM * abs(ra - rb));
}

vec4 sums[8];
void gather(ivec2 c, float w) {
  if (transportLayers == 0) {
    sums[0] += w * texelFetch(coarseExitance, c, 0);
    return;
  }
  for (int l = 0; l < transportLayers; ++l) sums[l] += w * texelFetch(coarseTransport, ivec3(c, l), 0);
}

void main() {
  for (int l = 0; l < 8; ++l) sums[l] = vec4(0.0);
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 po = texelFetch(splattingPositionObject, p, fineLevel);
  if (po.w < 0.0) discard;
  int m = int(texelFetch(splattingNormalMaterial, p, fineLevel).w);
  if (!isTranslucent(m)) discard;
  float z = dot(po.xyz - cameraPosition, cameraForward);
  vec2 q = (vec2(p) + 0.5) * 0.5 - 0.5;  // this pixel's centre in level k + 1 pixels
  ivec2 base = ivec2(floor(q));
  vec2 f = q - vec2(base);
  float total = 0.0;  // sums' alpha: the TABULATED model's exitance-weighted incidence cosine
  for (int i = 0; i < 4; ++i) {
    ivec2 o = ivec2(i & 1, i >> 1);
    ivec2 c = clamp(base + o, ivec2(0), coarseSize - 1);
    vec4 cpo = texelFetch(splattingPositionObject, c, fineLevel + 1);
    if (cpo.w != po.w) continue;
    int cm = int(texelFetch(splattingNormalMaterial, c, fineLevel + 1).w);
    if (!isTranslucent(cm)) continue;
    float wp = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
    float cz = dot(cpo.xyz - cameraPosition, cameraForward);
    float wz = exp(-lambdaZ * abs(z - cz) / boundingDiameter);
    float wm = materialWeight(m, cm);
    float w = wp * wz * wm;
    gather(c, w);
    total += w;
  }
  if (total <= 0.0) {
    // No coarse neighbour on this object (a silhouette or thin part narrower
    // than a coarse pixel): take the 3 x 3 ring around it by depth and material
    // alone rather than dropping the coarse levels' light.
    for (int dy = -1; dy <= 2; ++dy)
      for (int dx = -1; dx <= 2; ++dx) {
        ivec2 c = clamp(base + ivec2(dx, dy), ivec2(0), coarseSize - 1);
        vec4 cpo = texelFetch(splattingPositionObject, c, fineLevel + 1);
        if (cpo.w != po.w) continue;
        int cm = int(texelFetch(splattingNormalMaterial, c, fineLevel + 1).w);
        if (!isTranslucent(cm)) continue;
        float cz = dot(cpo.xyz - cameraPosition, cameraForward);
        float w = exp(-lambdaZ * abs(z - cz) / boundingDiameter) * materialWeight(m, cm);
        gather(c, w);
        total += w;
      }
    if (total <= 0.0) discard;
  }
  for (int l = 0; l < max(transportLayers, 1); ++l) exitance[l] = sums[l] / total;
}
