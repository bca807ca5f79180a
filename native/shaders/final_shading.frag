// Eq. 7: L = F_t(w_o) / pi * B(x_o) (times the TABULATED model's exit factor) for translucent surfaces, plus the direct
// light gathered before; the background where no surface was hit; transparent black on holdouts.
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_EXITANCE_BUFFER) uniform sampler2D exitanceBuffer;
layout(binding = UNIT_DIRECT_RADIANCE) uniform sampler2D directRadiance;
uniform vec3 cameraPosition;
uniform vec3 cameraForward;
uniform int orthographic;
uniform vec4 background;
layout(location = 0) out vec4 color;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 po = texelFetch(splattingPositionObject, pixel, 0);
  if (po.w < 0.0) { color = background; return; }
  vec4 nm = texelFetch(splattingNormalMaterial, pixel, 0);
  int m = int(nm.w);
  if (isHoldout(m)) { color = vec4(0.0); return; }  // a hole in the image, alpha 0
  vec3 L = texelFetch(directRadiance, pixel, 0).rgb;
  if (isTranslucent(m)) {
    vec3 V = orthographic != 0 ? -cameraForward : normalize(cameraPosition - po.xyz);
    float mu = dot(normalize(nm.xyz), V);
    float ft = fresnelTransmittance(materials[m].optics.x, mu);
    vec4 b = texelFetch(exitanceBuffer, pixel, 0);
    // TABULATED: the half-space's exit factor for the light's mean incidence cosine here.
    vec3 exitFactorHere = vec3(1.0);
    float sum = b.r + b.g + b.b;
    if (isTabulated(m) && sum > 0.0) exitFactorHere = exitFactor(m, b.a / sum, mu);
    L += ft / PI * b.rgb * exitFactorHere;
  }
  color = vec4(L, 1.0);
}
