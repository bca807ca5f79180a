// MATERIAL_EDIT's precomputation (docs/MATERIAL_EDIT.md): the transport of the edit basis,
// T_j(x_o) += K_j(|x_o - x_i|) E(x_i) dA(x_i) per colour channel, for the nine splines of one group
// (layers 0-6: spline s, channel c at component 3 s + c), K_j the spline convolved with the texel's
// footprint (material/profile_basis.h, tabulated as splat kernels three splines a layer, in R_P
// units: K in 1 / R_P^2). Layer 7 holds the means, weighted by splat.frag's exitance of the material
// as precomputed (w, its rgb sum), of what the light that reached x_o met where it entered: w, w mu0,
// w times the slab thickness and w times the slab share (common.glsl: slabGeometry), on this group's
// side of groupSplit. The edit's incidence factors and exit factor take them. TABULATED materials
// weight everything by sideWeight, as splat.frag.
flat in vec2 splatRange;
flat in vec3 splatPosition;
flat in vec3 splatFlux;
flat in float splatFootprint;
flat in float splatObject;
flat in int splatMaterial;
flat in vec4 splatNormalMu0;
flat in vec2 splatSlab;
uniform int splatLevel;
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_SPLAT_KERNELS) uniform sampler2DArray splatKernels;
layout(binding = UNIT_BASIS_KERNELS) uniform sampler2DArray basisKernels;
uniform vec2 kernelTableSize;
uniform float footprintReach;
uniform vec2 kernelLog2Range;
uniform int group;              // 0: splines 0-8, 1: splines 9-17
uniform float layerSupport[3];  // this group's three layers' supports, R_P units
uniform float groupSplit;       // R_P units: layer 7 takes d below it in group 0, from it on in group 1
layout(location = 0) out vec4 transport[8];

void main() {
  vec4 po = texelFetch(splattingPositionObject, ivec2(gl_FragCoord.xy), splatLevel);
  if (po.w != splatObject) discard;
  float d = distance(po.xyz, splatPosition);
  if (d < splatRange.x || d >= splatRange.y) discard;
  int m = splatMaterial;
  float ell = materials[m].ranges.y;
  vec3 flux = splatFlux;
  if (isTabulated(m)) {
    vec3 no = texelFetch(splattingNormalMaterial, ivec2(gl_FragCoord.xy), splatLevel).xyz;
    flux *= sideWeight(dot(splatNormalMu0.xyz, normalize(no)));
  }
  float values[27];
  for (int t = 0; t < 3; ++t) {
    float support = layerSupport[t] * ell;
    vec3 k = vec3(0.0);
    if (d < footprintReach * splatFootprint + support)
      k = kernelLookup(basisKernels, kernelTableSize, kernelLog2Range, footprintReach, float(3 * group + t), support,
                       d, splatFootprint) / (ell * ell);
    for (int s = 0; s < 3; ++s)
      for (int c = 0; c < 3; ++c) values[9 * t + 3 * s + c] = k[s] * flux[c];
  }
  for (int l = 0; l < 7; ++l)
    transport[l] = vec4(values[4 * l], values[4 * l + 1], values[4 * l + 2], l < 6 ? values[4 * l + 3] : 0.0);
  bool mine = group == 0 ? d < groupSplit * ell : d >= groupSplit * ell;
  float support = materials[m].ranges.x;
  vec3 b = vec3(0.0);
  if (mine && d < footprintReach * splatFootprint + support)
    b = flux * kernelLookup(splatKernels, kernelTableSize, kernelLog2Range, footprintReach, materials[m].optics.w,
                            support, d, splatFootprint);
  float w = b.r + b.g + b.b;
  transport[7] = w * vec4(1.0, splatNormalMu0.w, splatSlab);
}
