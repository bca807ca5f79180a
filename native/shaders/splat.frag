// Eq. 12: B(x_o) += K(|x_o - x_i|, a) E(x_i) dA(x_i), with K the profile
// convolved with the texel's Gaussian footprint (material/splat_kernel.h).
// Where x_i and x_o have different profiles (heterogeneous materials, eq. 8),
// K = sqrt(K_i K_o), each footprint-averaged on its own. TABULATED materials
// (material/transport_model.h): the splat is weighted out between surfaces that
// face apart (the transmission term carries that light), and alpha gathers
// the incidence cosine weighted by the exitance, for the exit factor.
// Compiled in variants (pipeline/splatting.h: programs_), as direct_lighting.frag is:
// PAIR_PROFILES 1 where some object has several translucent profiles, TRANSMISSION 1 where some
// material is TABULATED; FORWARD_SHIFT 1 where, besides, the forward shift is on (three kernel
// lookups, one per channel); llvmpipe runs a branch's code on every fragment, taken or not.
flat in vec3 splatPosition;
flat in vec3 splatFlux;
flat in float splatFootprint;
flat in float splatObject;
flat in int splatMaterial;
flat in vec4 splatNormalMu0;     // the texel's normal (facing the light) and incidence cosine
flat in float splatKernelRow;
flat in vec2 splatRange;         // [R_min, R_max) of this splatting level
flat in vec3 splatAlong;         // TABULATED: the forward shift (splat.geom); 0 otherwise
flat in vec3 splatShiftLengths;
flat in vec3 splatShiftDrops;    // along the normal, onto the surface (splat.vert: surfaceDrop)
uniform int splatLevel;
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_SPLAT_KERNELS) uniform sampler2DArray splatKernels;
uniform vec2 kernelTableSize;   // (distance samples, footprint samples)
uniform float footprintReach;   // x sigma
uniform vec2 kernelLog2Range;   // table rows: log2(sigma / support) at first and last
layout(location = 0) out vec4 exitance;

// The kernel of a profile of support `support` (table layer `layer`) at distance d, for this
// splat's footprint. Past the table's widest footprint (a texel thousands of times the profile's
// support: a scene in kilometres of millimetre skin) the kernel is the footprint's Gaussian times
// the profile's total, which is self-similar: the widest row, at d scaled down, times the scale
// squared. Clamping the row instead would give a footprint too narrow, and too much energy.
// The table's scale past its widest footprint (1 within it), and the texture coordinates of
// distance d, for this splat's footprint.
float kernelScale(float support) {
  float sigmaMax = support * exp2(kernelLog2Range.y);
  return splatFootprint > sigmaMax ? sigmaMax / splatFootprint : 1.0;
}
vec2 kernelUv(float support, float scale, float d, float row) {
  float reach = footprintReach * splatFootprint * scale + support;
  return (vec2(sqrt(min(d * scale / reach, 1.0)), row) * (kernelTableSize - 1.0) + 0.5) / kernelTableSize;
}
vec3 kernelAt(float layer, float support, float d, float row) {
  float scale = kernelScale(support);
  return texture(splatKernels, vec3(kernelUv(support, scale, d, row), layer)).rgb * (scale * scale);
}
// Each channel at its own distance: three lookups, one scale (in the FORWARD_SHIFT variant only).
vec3 kernelAt3(float layer, float support, vec3 d, float row) {
  float scale = kernelScale(support);
  return vec3(texture(splatKernels, vec3(kernelUv(support, scale, d.r, row), layer)).r,
              texture(splatKernels, vec3(kernelUv(support, scale, d.g, row), layer)).g,
              texture(splatKernels, vec3(kernelUv(support, scale, d.b, row), layer)).b) * (scale * scale);
}

void main() {
  vec4 po = texelFetch(splattingPositionObject, ivec2(gl_FragCoord.xy), splatLevel);
  // Light does not scatter between separate objects.
  if (po.w != splatObject) discard;
  float support = materials[splatMaterial].ranges.x;
  float reach = footprintReach * splatFootprint + support;
  float d = distance(po.xyz, splatPosition);
  // The levels split the distances from the sample itself; the kernel is evaluated from where
  // each channel's reflection is centred (the TABULATED model's forward shift).
  if (d < splatRange.x || d >= splatRange.y) discard;
#if FORWARD_SHIFT
  vec3 dc = vec3(distance(po.xyz, splatPosition + splatAlong * splatShiftLengths.r + splatNormalMu0.xyz * splatShiftDrops.r),
                 distance(po.xyz, splatPosition + splatAlong * splatShiftLengths.g + splatNormalMu0.xyz * splatShiftDrops.g),
                 distance(po.xyz, splatPosition + splatAlong * splatShiftLengths.b + splatNormalMu0.xyz * splatShiftDrops.b));
  if (min(dc.r, min(dc.g, dc.b)) >= reach) discard;
  vec3 kernel = kernelAt3(materials[splatMaterial].optics.w, support, dc, splatKernelRow);
#else
  if (d >= reach) discard;
  vec3 dc = vec3(d);
  vec3 kernel = kernelAt(materials[splatMaterial].optics.w, support, d, splatKernelRow);
#endif
#if PAIR_PROFILES
  {
    int mo = int(texelFetch(splattingNormalMaterial, ivec2(gl_FragCoord.xy), splatLevel).w);
    if (mo != splatMaterial) {
      if (!isTranslucent(mo)) discard;
      float supportO = materials[mo].ranges.x;
      float reachO = footprintReach * splatFootprint + supportO;
      if (min(dc.r, min(dc.g, dc.b)) >= reachO) discard;
      float rowO = clamp((log2(splatFootprint / supportO) - kernelLog2Range.x) / (kernelLog2Range.y - kernelLog2Range.x),
                         0.0, 1.0);
#if FORWARD_SHIFT
      kernel = sqrt(kernel * kernelAt3(materials[mo].optics.w, supportO, dc, rowO));
#else
      kernel = sqrt(kernel * kernelAt(materials[mo].optics.w, supportO, d, rowO));
#endif
    }
  }
#endif
  vec3 b = splatFlux * kernel;
#if TRANSMISSION
  if (isTabulated(splatMaterial)) {
    vec3 no = texelFetch(splattingNormalMaterial, ivec2(gl_FragCoord.xy), splatLevel).xyz;
    b *= sideWeight(dot(splatNormalMu0.xyz, normalize(no)));
    exitance = vec4(b, (b.r + b.g + b.b) * splatNormalMu0.w);
    return;
  }
#endif
  exitance = vec4(b, 0.0);
}
