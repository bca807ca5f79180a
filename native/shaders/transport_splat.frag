// MATERIAL_EDIT's precomputation (docs/MATERIAL_EDIT.md): the transport of the edit basis,
// T_j(x_o) += K_j(|x_o - x_i|) E(x_i) dA(x_i) per colour channel, for the nine splines of one group
// (layers 0-6: spline s, channel c at component 3 s + c), K_j the spline convolved with the texel's
// footprint (material/profile_basis.h, tabulated as splat kernels three splines a layer, in R_P
// units: K in 1 / R_P^2). Layer 7 holds the means, weighted by splat.frag's exitance of the material
// as precomputed (w, its rgb sum), of what the light that reached x_o met where it entered: w, w mu0,
// w times the slab thickness and w times the slab share (common.glsl: slabGeometry), on this group's
// side of groupSplit. The edit's incidence factors and exit factor take them. TABULATED materials
// weight everything by sideWeight, as splat.frag; compiled with TRANSMISSION 1 where some material
// is TABULATED (pipeline/transport_splatting.h: splatPrograms_).
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
uniform int group;              // 0: splines 0-8, 1: splines 9-17
uniform float layerSupport[3];  // this group's three layers' supports, R_P units
uniform float groupSplit;       // R_P units: layer 7 takes d below it in group 0, from it on in group 1
flat in vec3 layerFootprint[3];  // transport_splat.geom: kernelFootprint of each layer
flat in vec3 ownFootprint;        // and of the material's own kernel
layout(location = 0) out vec4 transport[8];

// Layer t's three splines of this group at distance d (K in 1 / R_P^2, ell the range R_P).
vec3 basisKernel(int t, float d, float ell) {
  float support = layerSupport[t] * ell;
  if (d >= footprintReach * splatFootprint + support) return vec3(0.0);
  return kernelLookupAt(basisKernels, kernelTableSize, float(3 * group + t), layerFootprint[t], d) / (ell * ell);
}

void main() {
  vec4 po = texelFetch(splattingPositionObject, ivec2(gl_FragCoord.xy), splatLevel);
  if (po.w != splatObject) discard;
  float d = distance(po.xyz, splatPosition);
  if (d < splatRange.x || d >= splatRange.y) discard;
  int m = splatMaterial;
  float ell = materials[m].ranges.y;
  vec3 flux = splatFlux;
#if TRANSMISSION
  if (isTabulated(m)) {
    vec3 no = texelFetch(splattingNormalMaterial, ivec2(gl_FragCoord.xy), splatLevel).xyz;
    flux *= sideWeight(dot(splatNormalMu0.xyz, normalize(no)));
  }
#endif
  // Layer t's three splines times the flux, column s = spline s's rgb (outerProduct), packed four
  // floats a layer in the order 9 t + 3 s + c. Written out, not through a local array: llvmpipe
  // gives every fragment of a shader with a run-time indexed array a stack copy of it.
  mat3 a = outerProduct(flux, basisKernel(0, d, ell));
  mat3 b = outerProduct(flux, basisKernel(1, d, ell));
  mat3 c = outerProduct(flux, basisKernel(2, d, ell));
  transport[0] = vec4(a[0], a[1].r);
  transport[1] = vec4(a[1].gb, a[2].rg);
  transport[2] = vec4(a[2].b, b[0]);
  transport[3] = vec4(b[1], b[2].r);
  transport[4] = vec4(b[2].gb, c[0].rg);
  transport[5] = vec4(c[0].b, c[1]);
  transport[6] = vec4(c[2], 0.0);
  bool mine = group == 0 ? d < groupSplit * ell : d >= groupSplit * ell;
  float support = materials[m].ranges.x;
  vec3 own = vec3(0.0);
  if (mine && d < footprintReach * splatFootprint + support)
    own = flux * kernelLookupAt(splatKernels, kernelTableSize, materials[m].optics.w, ownFootprint, d);
  float w = own.r + own.g + own.b;
  transport[7] = w * vec4(1.0, splatNormalMu0.w, splatSlab);
}
