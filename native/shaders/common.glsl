// Shared by every subsplat shader (prepended after #version).
const float PI = 3.14159265358979;

// One entry per opaque or homogeneous material and per palette entry of a
// heterogeneous one (scene.h: MaterialEntry, MaterialGpu).
struct Material {
  vec4 baseColorKind;  // rgb diffuse albedo (opaque), w: 0 opaque, 1 translucent
  vec4 optics;         // eta, roughness, specular, kernel layer
  vec4 ranges;         // support radius, effective range R_P (max over rgb), R_P (min), mm per scene unit
  uvec4 profileMap;    // heterogeneous: offset into profileMaps, width, height (0: none); the material's first entry
};
layout(std430, binding = STORAGE_MATERIALS) readonly buffer Materials { Material materials[]; };

bool isTranslucent(int m) { return m >= 0 && materials[m].baseColorKind.w > 0.5; }

// The entry of a surface point of material m (its first entry) at texture
// coordinate uv: the nearest texel of the material's profile map, repeating.
layout(binding = UNIT_PROFILE_MAPS) uniform usamplerBuffer profileMaps;
int profileEntry(int m, vec2 uv, bool hasUv) {
  if (m < 0) return m;
  uvec4 map = materials[m].profileMap;
  if (map.y == 0u || !hasUv) return m;
  ivec2 size = ivec2(map.yz);
  ivec2 t = clamp(ivec2(floor(fract(uv) * vec2(size))), ivec2(0), size - 1);
  return m + int(texelFetch(profileMaps, int(map.x) + t.y * size.x + t.x).r);
}

// Unpolarised Fresnel transmittance into a dielectric of relative index eta.
float fresnelTransmittance(float eta, float cosTheta) {
  cosTheta = clamp(cosTheta, 0.0, 1.0);
  float sin2T = (1.0 - cosTheta * cosTheta) / (eta * eta);
  if (sin2T >= 1.0) return 0.0;
  float cosT = sqrt(1.0 - sin2T);
  float rs = (cosTheta - eta * cosT) / (cosTheta + eta * cosT);
  float rp = (eta * cosTheta - cosT) / (eta * cosTheta + cosT);
  return 1.0 - 0.5 * (rs * rs + rp * rp);
}

// One view of a light: what the irradiance buffer was rendered with.
uniform mat4 lightViewProj;
uniform vec3 lightPosition;   // point and spot
uniform vec3 lightDirection;  // direction the light travels (spot axis, sun)
uniform vec3 lightRadiant;    // colour x (intensity W/sr | sun irradiance W/m^2)
uniform int lightType;        // LIGHT_POINT, LIGHT_SPOT, LIGHT_SUN (gl/bindings.h)
uniform float lightCosHalfSpot, lightSpotSmooth;

// Direction towards the light and the irradiance a surface facing it gets.
vec3 towardsLight(vec3 p) {
  return lightType == LIGHT_SUN ? -lightDirection : normalize(lightPosition - p);
}
vec3 irradianceFacingLight(vec3 p) {
  if (lightType == LIGHT_SUN) return lightRadiant;
  vec3 d = lightPosition - p;
  vec3 e = lightRadiant / max(dot(d, d), 1e-20);
  if (lightType == LIGHT_SPOT) {
    // Cycles' spot attenuation (kernel/light/spot.h in 3.x): the cosine to
    // the axis, cut at the cone and smoothed over the blend region.
    float c = dot(-normalize(d), lightDirection);
    float attenuation = c <= lightCosHalfSpot ? 0.0 : c;
    float t = c - lightCosHalfSpot;
    if (attenuation > 0.0 && t < lightSpotSmooth && lightSpotSmooth > 0.0)
      attenuation *= smoothstep(0.0, 1.0, t / lightSpotSmooth);
    e *= attenuation;
  }
  return e;
}
