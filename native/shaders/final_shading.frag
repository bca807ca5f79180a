// Eq. 7: L = F_t(w_o) / pi * B(x_o) (times the TABULATED model's exit factor) for translucent surfaces, plus the direct
// light gathered before; the background where no surface was hit; transparent black on holdouts.
// Compiled in variants (pipeline/shading.h: finalPrograms_), as direct_lighting.frag is:
// ENVIRONMENT 1 where the background is an environment map, TRANSMISSION 1 where some material is
// TABULATED (its exit factor and the world's H-function), WORLD 0 where the world's remainder is
// black (nothing of worldMix to add), 1 two halves, 2 spherical harmonics.
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_SPLATTING_ALBEDO) uniform sampler2D splattingAlbedo;
layout(binding = UNIT_SPLATTING_SHADING_NORMAL) uniform sampler2D splattingShadingNormal;
layout(binding = UNIT_EXITANCE_BUFFER) uniform sampler2D exitanceBuffer;
layout(binding = UNIT_DIRECT_RADIANCE) uniform sampler2D directRadiance;
uniform vec3 cameraPosition;
uniform vec3 cameraForward;
uniform int orthographic;
uniform vec4 background;
// The environment where no object is (material/texture.h: Environment::radiance): an equirectangular
// map (repeating in u, clamped in v), looked up along the pixel's ray.
layout(binding = UNIT_ENVIRONMENT) uniform sampler2D environmentMap;
uniform mat4 clipToWorld;
uniform vec2 frameSize;
uniform mat3 environmentRotation;
uniform float environmentStrength;
vec3 environmentRadiance() {
  vec2 ndc = gl_FragCoord.xy / frameSize * 2.0 - 1.0;
  vec4 nearH = clipToWorld * vec4(ndc, -1.0, 1.0), farH = clipToWorld * vec4(ndc, 1.0, 1.0);
  vec3 d = environmentRotation * (farH.xyz / farH.w - nearH.xyz / nearH.w);
  vec2 uv = vec2(0.5 - atan(d.y, d.x) / (2.0 * PI), atan(d.z, length(d.xy)) / PI + 0.5);
  return environmentStrength * textureLod(environmentMap, uv, 0.0).rgb;
}
// The world (world_light.h): its radiance above and below the horizon, or its irradiance as
// spherical harmonics, for its specular reflection, and whether it also lights every surface
// unshadowed (not drawn as directions).
uniform vec3 worldAbove;
uniform vec3 worldBelow;
uniform vec3 worldIrradiance[9];  // E(n) / pi, world_light.h: RenderLights
uniform int worldUnshadowed;
// world_light.cpp: worldRemainder, E(n = d) / pi.
vec3 worldMix(vec3 d) {
#if WORLD == 0
  return vec3(0.0);
#elif WORLD == 1
  float up = 0.5 * (1.0 + clamp(d.z, -1.0, 1.0));
  return up * worldAbove + (1.0 - up) * worldBelow;
#else
  vec3 e = worldIrradiance[0] * 0.28209479 + worldIrradiance[1] * (0.48860251 * d.y) +
           worldIrradiance[2] * (0.48860251 * d.z) + worldIrradiance[3] * (0.48860251 * d.x) +
           worldIrradiance[4] * (1.09254843 * d.x * d.y) + worldIrradiance[5] * (1.09254843 * d.y * d.z) +
           worldIrradiance[6] * (0.31539157 * (3.0 * d.z * d.z - 1.0)) + worldIrradiance[7] * (1.09254843 * d.x * d.z) +
           worldIrradiance[8] * (0.54627422 * (d.x * d.x - d.y * d.y));
  return max(e, vec3(0.0));
#endif
}
// The GGX lobe's directional albedo (world_light.cpp: specularAlbedo, Karis 2014).
float specularAlbedo(float roughness, float specular, float cosView) {
  float f0 = 0.08 * specular;
  if (f0 <= 0.0) return 0.0;
  vec4 c = clamp(roughness, 0.02, 1.0) * vec4(-1.0, -0.0275, -0.572, 0.022) + vec4(1.0, 0.0425, 1.04, -0.04);
  float a004 = min(c.x * c.x, exp2(-9.28 * clamp(cosView, 0.0, 1.0))) * c.x + c.y;
  return f0 * (-1.04 * a004 + c.z) + (1.04 * a004 + c.w);
}
layout(location = 0) out vec4 color;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 po = texelFetch(splattingPositionObject, pixel, 0);
  if (po.w < 0.0) {
#if ENVIRONMENT
    color = vec4(environmentRadiance(), 1.0);
#else
    color = background;
#endif
    return;
  }
  vec4 nm = texelFetch(splattingNormalMaterial, pixel, 0);
  int m = int(nm.w);
  if (isHoldout(m)) { color = vec4(0.0); return; }  // a hole in the image, alpha 0
  vec3 L = texelFetch(directRadiance, pixel, 0).rgb;
  vec3 V = orthographic != 0 ? -cameraForward : normalize(cameraPosition - po.xyz);
  vec3 n = normalize(texelFetch(splattingShadingNormal, pixel, 0).xyz);  // the normal map's, if any
  vec3 tint = texelFetch(splattingAlbedo, pixel, 0).rgb;
  float mu = max(dot(n, V), 0.0);
#if WORLD
  L += worldMix(reflect(-V, n)) * specularAlbedo(materials[m].optics.y, materials[m].optics.z, mu);
  vec3 ambient = worldUnshadowed != 0 ? worldMix(n) : vec3(0.0);
#else
  vec3 ambient = vec3(0.0);
#endif
  if (!isTranslucent(m)) L += ambient * materials[m].baseColorKind.rgb * tint;
  if (isTranslucent(m)) {  // the tint: sqrt(T) where the light entered (irradiance_buffer.frag), sqrt(T) here
    float ft = fresnelTransmittance(materials[m].optics.x, mu);
    vec4 b = texelFetch(exitanceBuffer, pixel, 0);
    // TABULATED: the half-space's exit factor for the light's mean incidence cosine here.
    vec3 exitFactorHere = vec3(1.0);
    float sum = b.r + b.g + b.b;
#if TRANSMISSION
    if (isTabulated(m) && sum > 0.0) exitFactorHere = exitFactor(m, b.a / sum, mu);
#endif
    L += ft / PI * b.rgb * exitFactorHere * sqrt(tint);
    vec3 world = ambient * materials[m].world.rgb * ft * tint;  // entered around here: T at both ends
#if TRANSMISSION
    if (isTabulated(m))  // the half-space under uniform light: L (1 - sqrt(1 - a) H(mu))
      world *= 1.0 - sqrt(max(1.0 - materials[m].medium.rgb, 0.0)) * hFunction(m, mu);
#endif
    L += world;
  }
  color = vec4(L, 1.0);
}
