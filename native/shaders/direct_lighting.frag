// Direct light of one light view: diffuse for opaque surfaces, specular for
// every surface, shadowed by the view's irradiance buffer; and, for TABULATED
// materials, the light that crossed a part to reach a surface the light does
// not reach itself (material/transport_model.h: the slab's T(tau, mu0, mu)).
// With keptThrough (MATERIAL_EDIT, pipeline/shading.h: Shading::keepThrough), that light is not
// added: what it is before the slab's transmission goes to throughEntering (the entering light
// times the exit's factors and the tint, and the thickness) and throughAngles (mu0, mu, 1), which
// direct_through.frag turns into light for the materials as they are.
//
// Compiled in variants (pipeline/shading.h: directPrograms_, a gl::ProgramVariants): SOFT_SHADOWS, how this view's
// shadows are filtered (0 hard, on the shadow map; 1 a sun's soft shadows, on its shadow map; 2 a
// point, spot or area light's, on the irradiance buffer's resolution), TRANSMISSION, 1 where
// some material is TABULATED, and AREA_LIGHT, 1 for an area light (its polygon's irradiance).
// llvmpipe runs both sides of a branch whatever the lanes take, so a uniform's branch cost the whole
// pass the soft filter's, the light through's and the polygon's code on every pixel
// (docs/BENCHMARKS.md, "The direct light's variants" and "Area lights and soft entries").
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_SPLATTING_ALBEDO) uniform sampler2D splattingAlbedo;
layout(binding = UNIT_SPLATTING_SHADING_NORMAL) uniform sampler2D splattingShadingNormal;
layout(binding = UNIT_IRRADIANCE_LIGHT_DEPTH) uniform sampler2D irradianceLightDepth;
// The hard shadows' map at its own resolution (pipeline/shadow_map.h; irradianceLightDepth when the
// same).
layout(binding = UNIT_SHADOW_DEPTH) uniform sampler2D shadowDepth;
uniform int shadowResolution;
// The map of every surface at the irradiance buffer's resolution that point, spot and area lights'
// soft shadows filter: its light depth, or a shadow map when it holds translucent objects only
// (pipeline/irradiance_buffer.h: ShadowInputs).
layout(binding = UNIT_SOFT_DEPTH) uniform sampler2D softDepth;
uniform vec3 cameraPosition;
uniform vec3 cameraForward;
uniform int orthographic;
uniform int resolution;
uniform int unshadowedOutside;   // sun: surfaces outside the view are lit
uniform int keptThrough;
layout(binding = UNIT_IRRADIANCE_POSITION_MATERIAL) uniform sampler2D irradiancePositionMaterial;
layout(binding = UNIT_IRRADIANCE_NORMAL_OBJECT) uniform sampler2D irradianceNormalObject;
layout(location = 0) out vec4 radiance;
layout(location = 1) out vec4 throughEntering;
layout(location = 2) out vec4 throughAngles;
float ggx(float nh, float alpha2) {
  float d = nh * nh * (alpha2 - 1.0) + 1.0;
  return alpha2 / (PI * d * d);
}
float smithG1(float nv, float alpha2) {
  return 2.0 * nv / (nv + sqrt(alpha2 + (1.0 - alpha2) * nv * nv));
}

// Through a part: the light entered where this view's light first meets the object (the
// irradiance buffer's texel over p) and crossed the thickness between there and p. With
// keptThrough, what it is before the slab's transmission goes to throughEntering (times tint) and
// throughAngles instead (and it returns 0; else the caller multiplies by tint).
vec3 transmitted(vec3 p, vec3 n, int m, float object, vec3 V, ivec2 t, vec3 tint) {
  vec4 pe = texelFetch(irradiancePositionMaterial, t, 0);
  vec4 ne = texelFetch(irradianceNormalObject, t, 0);
  if (pe.w < 0.0 || ne.w != object || !isTabulated(int(pe.w))) return vec3(0.0);
  float depth = lightType == LIGHT_SUN ? dot(p, lightDirection) : distance(p, lightPosition);
  float mu0 = clamp(dot(ne.xyz, towardsLight(pe.xyz)), 0.0, 1.0);
  float mu = clamp(dot(n, V), 0.0, 1.0);
  vec2 entryDepth = texelFetch(irradianceLightDepth, t, 0).rg;  // g: the share of the light reaching the entry
#if AREA_LIGHT
  vec3 entering = lightRadiant * polygonIrradiance(pe.xyz, ne.xyz) *
#else
  vec3 entering = irradianceFacingLight(pe.xyz) * mu0 *
#endif
                  lightWeight(ne.xyz) * fresnelTransmittance(materials[m].optics.x, mu0) * entryDepth.g;
  float thickness = max(depth - entryDepth.r, 0.0) * mu0;  // along the entry's normal
  float leaving = fresnelTransmittance(materials[m].optics.x, mu) * slabLikeness(dot(ne.xyz, n));
  if (keptThrough != 0) {
    throughEntering = vec4(entering * leaving * tint, thickness);
    throughAngles = vec4(mu0, mu, 1.0, 0.0);
    return vec3(0.0);
  }
  return entering * transmittedRadiance(m, thickness * materials[m].extinction.rgb, mu0, mu) * leaving;
}

void main() {
  throughEntering = vec4(0.0);
  throughAngles = vec4(0.0);
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 po = texelFetch(splattingPositionObject, pixel, 0);
  if (po.w < 0.0) discard;
  vec4 nm = texelFetch(splattingNormalMaterial, pixel, 0);
  vec3 p = po.xyz, n = normalize(nm.xyz);
  int m = int(nm.w);
  vec3 L = towardsLight(p);
  // The normal map's normal shades; the geometric one places the shadow test and the light through.
  vec3 ns = normalize(texelFetch(splattingShadingNormal, pixel, 0).xyz);
  vec3 tint = texelFetch(splattingAlbedo, pixel, 0).rgb;
  float nl = dot(n, L);
  vec3 V = orthographic != 0 ? -cameraForward : normalize(cameraPosition - p);
  bool tabulated = TRANSMISSION != 0 && isTabulated(m);
  if (nl <= 0.0 && !tabulated) discard;

  // Does this view own the pixel, and does the light reach it?
  float texel = lightType == LIGHT_SUN ? shadowTexelSize
                               : shadowTexelSize * distance(p, lightPosition);
  vec3 offset = p + n * (1.5 * texel);
  vec4 clip = lightViewProj * vec4(offset, 1.0);
  vec3 ndc = clip.xyz / clip.w;
  bool inside = clip.w > 0.0 && all(lessThan(abs(ndc.xy), vec2(1.0)));
  float visibility = 1.0;
#if SOFT_SHADOWS == 1
  if (inside) {  // on the shadow map, its texels and bias its own
    visibility = softVisibilityAt(shadowDepth, shadowResolution, resolution, p, n, nl, -1.0);
#elif SOFT_SHADOWS == 2
  if (inside) {  // on the irradiance buffer's resolution
    visibility = softVisibilityAt(softDepth, resolution, resolution, p, n, nl, -1.0);
#else
  if (inside) {  // on the shadow map, its texels and bias its own
    float fineTexel = texel * float(resolution) / float(shadowResolution);
    vec3 fine = p + n * (1.5 * fineTexel);
    vec4 c = lightViewProj * vec4(fine, 1.0);
    vec2 q = c.xy / c.w;
    ivec2 t = clamp(ivec2((q * 0.5 + 0.5) * float(shadowResolution)), ivec2(0), ivec2(shadowResolution - 1));
    float stored = texelFetch(shadowDepth, t, 0).r;
    float depth = lightType == LIGHT_SUN ? dot(fine, lightDirection) : distance(fine, lightPosition);
    visibility = depth <= stored + 2.0 * fineTexel ? 1.0 : 0.0;
#endif
  } else if (unshadowedOutside == 0) {
    discard;
  }

  vec3 through = vec3(0.0);
#if TRANSMISSION
  if (tabulated && (nl <= 0.0 || visibility == 0.0)) {
    vec4 c = lightViewProj * vec4(p, 1.0);  // the texel over p itself, not over the offset point
    vec2 q = c.xy / c.w;
    if (c.w > 0.0 && all(lessThan(abs(q), vec2(1.0))))
      through = transmitted(p, n, m, po.w, V, clamp(ivec2((q * 0.5 + 0.5) * float(resolution)), ivec2(0),
                                                        ivec2(resolution - 1)), tint) * tint;
  }
#endif
  float nsl = dot(ns, L);
  if (nl <= 0.0 || nsl <= 0.0) {
    radiance = vec4(through, 0.0);
    return;
  }

#if AREA_LIGHT
  vec3 E = lightRadiant * polygonIrradiance(p, ns) * visibility * lightWeight(ns);
#else
  vec3 E = irradianceFacingLight(p) * nsl * visibility * lightWeight(ns);
#endif
  float nv = max(dot(ns, V), 1e-4);
  vec3 H = normalize(L + V);
  float roughness = clamp(materials[m].optics.y, 0.02, 1.0);
  float alpha2 = pow(roughness, 4.0);
  float f0 = 0.08 * materials[m].optics.z;
  float fresnel = f0 + (1.0 - f0) * pow(1.0 - max(dot(H, V), 0.0), 5.0);
  // The world's specular reflection is final_shading.frag's, not K highlights (world_light.h).
  float specular = f0 > 0.0 && worldDirectionCount == 0 ? ggx(max(dot(ns, H), 0.0), alpha2) * smithG1(nsl, alpha2) *
                                  smithG1(nv, alpha2) * fresnel / (4.0 * nsl * nv)
                            : 0.0;
  vec3 diffuse = isTranslucent(m) ? vec3(0.0) : materials[m].baseColorKind.rgb * tint / PI;
  radiance = vec4((diffuse + vec3(specular)) * E + through, 0.0);
}
