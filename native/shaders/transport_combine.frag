// MATERIAL_EDIT's edit (docs/MATERIAL_EDIT.md): a pixel's exitance from its material's
// coefficients and the precomputed transport, B_c = sum_j c_jc T_jc (pipeline/transport_splatting.h),
// times the edited material's incidence factor over the precomputed one's. Both are taken at the
// means of what the pixel's light met where it entered (layer 7 of both groups: weight, cosine,
// slab thickness and share; transport_splat.frag), the precomputed one kept per pixel by this pass
// with storeFactors (1 for the dipole). Alpha as FULL's exitance: the mean incidence cosine times
// the rgb sum.
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_NEAR_TRANSPORT) uniform sampler2DArray nearTransport;
layout(binding = UNIT_FAR_TRANSPORT) uniform sampler2DArray farTransport;
layout(binding = UNIT_EDIT_FACTORS) uniform sampler2D precomputedFactors;
uniform int storeFactors;  // 1: write the precomputed material's incidence factor, not the exitance
struct EditCoefficients {
  vec4 spline[18];  // rgb: c_j per channel
};
layout(std430, binding = STORAGE_EDIT_COEFFICIENTS) readonly buffer Coefficients { EditCoefficients coefficients[]; };
layout(location = 0) out vec4 result;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  int m = int(texelFetch(splattingNormalMaterial, p, 0).w);
  if (!isTranslucent(m)) { result = storeFactors != 0 ? vec4(1.0) : vec4(0.0); return; }
  vec4 means = texelFetch(nearTransport, ivec3(p, 7), 0) + texelFetch(farTransport, ivec3(p, 7), 0);
  means = means.x > 0.0 ? means / means.x : vec4(1.0, 1.0, 0.0, 0.0);
  float mu0 = clamp(means.y, 0.0, 1.0);
  vec3 factor = isTabulated(m) ? incidenceFactorAt(m, means.zw, mu0) : vec3(1.0);
  if (storeFactors != 0) { result = vec4(factor, 1.0); return; }
  float t[54];
  for (int l = 0; l < 7; ++l) {
    vec4 near = texelFetch(nearTransport, ivec3(p, l), 0), far = texelFetch(farTransport, ivec3(p, l), 0);
    for (int i = 0; i < 4 && 4 * l + i < 27; ++i) {
      t[4 * l + i] = near[i];
      t[27 + 4 * l + i] = far[i];
    }
  }
  vec3 b = vec3(0.0);
  for (int j = 0; j < 18; ++j) b += coefficients[m].spline[j].rgb * vec3(t[3 * j], t[3 * j + 1], t[3 * j + 2]);
  vec3 before = texelFetch(precomputedFactors, p, 0).rgb;
  b *= mix(factor / max(before, vec3(1e-30)), vec3(1.0), lessThanEqual(before, vec3(0.0)));
  b = max(b, vec3(0.0));  // a projection may dip below zero where nearly nothing arrives
  result = vec4(b, mu0 * (b.r + b.g + b.b));
}
