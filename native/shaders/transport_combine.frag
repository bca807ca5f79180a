// MATERIAL_EDIT's edit (docs/MATERIAL_EDIT.md): a pixel's exitance from its material's
// coefficients and the precomputed transport, B_c = sum_j c_jc T_jc (pipeline/transport_splatting.h),
// times the edited to precomputed incidence factor at the pixel's mean incidence cosine (layer 7 of
// both groups: the precomputed exitance and its incidence cosine). Alpha as FULL's exitance: the
// mean incidence cosine times the rgb sum.
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_NEAR_TRANSPORT) uniform sampler2DArray nearTransport;
layout(binding = UNIT_FAR_TRANSPORT) uniform sampler2DArray farTransport;
struct EditCoefficients {
  vec4 spline[18];     // rgb: c_j per channel
  vec4 incidence[17];  // rgb: the incidence factors' ratio at mu0 = (k / 16)^2
};
layout(std430, binding = STORAGE_EDIT_COEFFICIENTS) readonly buffer Coefficients { EditCoefficients coefficients[]; };
layout(location = 0) out vec4 exitance;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  int m = int(texelFetch(splattingNormalMaterial, p, 0).w);
  if (!isTranslucent(m)) { exitance = vec4(0.0); return; }
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
  vec4 precomputed = texelFetch(nearTransport, ivec3(p, 7), 0) + texelFetch(farTransport, ivec3(p, 7), 0);
  float sum = precomputed.r + precomputed.g + precomputed.b;
  float mu0 = sum > 0.0 ? clamp(precomputed.a / sum, 0.0, 1.0) : 1.0;
  float x = sqrt(mu0) * 16.0;
  int k = min(int(x), 15);
  b *= mix(coefficients[m].incidence[k].rgb, coefficients[m].incidence[k + 1].rgb, x - float(k));
  b = max(b, vec3(0.0));  // a projection may dip below zero where nearly nothing arrives
  exitance = vec4(b, mu0 * (b.r + b.g + b.b));
}
