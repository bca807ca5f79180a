// Eq. 12 for a homogeneous material: B(x_o) += K(|x_o - x_i|, a) E(x_i) dA(x_i),
// with K the dipole convolved with the texel's Gaussian footprint
// (material/splat_kernel.h).
flat in vec3 splatPosition;
flat in vec3 splatFlux;
flat in float splatFootprint;
flat in float splatObject;
flat in int splatMaterial;
flat in float splatKernelRow;
flat in vec2 splatRange;         // [R_min, R_max) of this splatting level
uniform int splatLevel;
uniform sampler2D splattingPositionObject;
uniform sampler2DArray splatKernels;
uniform vec2 kernelTableSize;   // (distance samples, footprint samples)
uniform float footprintReach;   // x sigma
layout(location = 0) out vec4 exitance;
void main() {
  vec4 po = texelFetch(splattingPositionObject, ivec2(gl_FragCoord.xy), splatLevel);
  // Light does not scatter between separate objects.
  if (po.w != splatObject) discard;
  float support = materials[splatMaterial].ranges.x;
  float reach = footprintReach * splatFootprint + support;
  float d = distance(po.xyz, splatPosition);
  if (d >= reach || d < splatRange.x || d >= splatRange.y) discard;
  float t = sqrt(d / reach);
  vec2 uv = (vec2(t, splatKernelRow) * (kernelTableSize - 1.0) + 0.5) / kernelTableSize;
  float layer = materials[splatMaterial].optics.w;
  vec3 kernel = texture(splatKernels, vec3(uv, layer)).rgb;
  exitance = vec4(splatFlux * kernel, 0.0);
}
