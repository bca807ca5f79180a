// Direct light of one light view: diffuse for opaque surfaces, specular for
// every surface, shadowed by the view's irradiance buffer; and, for TABULATED
// materials, the light that crossed a part to reach a surface the light does
// not reach itself (material/transport_model.h: the slab's T(tau, mu0, mu)).
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_SPLATTING_ALBEDO) uniform sampler2D splattingAlbedo;
layout(binding = UNIT_SPLATTING_SHADING_NORMAL) uniform sampler2D splattingShadingNormal;
layout(binding = UNIT_IRRADIANCE_LIGHT_DEPTH) uniform sampler2D irradianceLightDepth;
// The hard shadows' map at its own resolution (pipeline/shadow_map.h; irradianceLightDepth when the
// same).
layout(binding = UNIT_SHADOW_DEPTH) uniform sampler2D shadowDepth;
uniform int shadowResolution;
uniform vec3 cameraPosition;
uniform vec3 cameraForward;
uniform int orthographic;
uniform int resolution;
uniform float shadowTexelSize;   // world size of a texel at distance 1 (or absolute, sun)
uniform int unshadowedOutside;   // sun: surfaces outside the view are lit
uniform int transmission;        // some material is TABULATED
layout(binding = UNIT_IRRADIANCE_POSITION_MATERIAL) uniform sampler2D irradiancePositionMaterial;
layout(binding = UNIT_IRRADIANCE_NORMAL_OBJECT) uniform sampler2D irradianceNormalObject;
layout(location = 0) out vec4 radiance;
// Soft shadows (docs/SOFT_SHADOWS.md): sun: the tangent of half its angle; point, spot: its radius,
// a disk facing the receiver; area: its own shape (lightSoftAxes, its semi-axes in the world; a
// rectangle or an ellipse); 0: hard. lightNearDepth: the least light depth in the view (the
// search's widest reach).
uniform float lightSoftSize;
uniform vec3 lightSoftAxes[2];
uniform int lightSoftRectangle;
uniform float lightNearDepth;

// How far a penumbra reaches at a receiver at light depth `depth` behind a blocker at `blocker`, per
// unit of the light's extent (similar triangles; the sun's extent is already an angle's tangent).
float penumbraScale(float depth, float blocker) {
  return lightType == LIGHT_SUN ? depth - blocker : (depth - blocker) / max(blocker, 1e-6);
}
// Point k of n spread over the light's shape in its own unit coordinates: the unit square (an R2
// sequence) or the unit disk (a Vogel spiral); and the shape's norm (1 on its edge).
vec2 shapePoint(int k, int n) {
  if (lightSoftRectangle != 0) return fract(vec2(0.7548776662, 0.5698402910) * float(k) + 0.5) * 2.0 - 1.0;
  float r = sqrt((float(k) + 0.5) / float(n)), phi = 2.39996323 * float(k);
  return r * vec2(cos(phi), sin(phi));
}
float shapeNorm(vec2 x) { return lightSoftRectangle != 0 ? max(abs(x.x), abs(x.y)) : length(x); }

// The share of the light that reaches a receiver at light depth `depth` over the view's point
// `ndc`, percentage-closer soft shadows (Fernando 2005) over the light's own shape on a depth map
// of mapResolution texels (the shadow map for suns, the irradiance buffer's light depth for the
// others; docs/SOFT_SHADOWS.md): the blockers' mean depth, then the share of the penumbra's taps
// that do not block. texel: a map texel's world size at the receiver; slope: how fast the
// receiver's depth grows across the map per texel (its bias); p: the receiver. The taps reach at
// most 32 of the irradiance buffer's texels (maxReach map texels), whatever the map's resolution.
float softVisibility(sampler2D map, int mapResolution, vec2 ndc, float depth, float texel, float slope, vec3 p) {
  float maxReach = 32.0 * float(mapResolution) / float(resolution);
  // A blocker counts as in the cone up to one of the irradiance buffer's texels beyond it (the
  // allowance the cone test was made with; one texel of a finer map admits too few, and the
  // blockers' mean then falls back on the first look's, which counts parts of the occluder too far
  // to the side: an area light's penumbra 1.3 times Cycles' at 4 times the resolution).
  float coneAllowance = float(mapResolution) / float(resolution);
  vec2 centre = (ndc * 0.5 + 0.5) * float(mapResolution);
  // The light's extent as two world vectors, and their images in the map at p, in texels (the
  // penumbra is the light's shape scaled by penumbraScale; a perspective map's texels shrink off
  // its axis and stretch across a slope).
  vec3 A = lightSoftAxes[0], B = lightSoftAxes[1];
  if (dot(A, A) == 0.0) {
    vec3 L = towardsLight(p), u = normalize(cross(L, abs(L.z) < 0.9 ? vec3(0, 0, 1) : vec3(1, 0, 0)));
    A = u * lightSoftSize, B = cross(L, u) * lightSoftSize;
  }
  float h = 0.01 * (lightType == LIGHT_SUN ? texel * 100.0 : distance(p, lightPosition));
  vec4 c0 = lightViewProj * vec4(p, 1.0);
  vec4 ca = lightViewProj * vec4(p + A * (h / max(length(A), 1e-20)), 1.0);
  vec4 cb = lightViewProj * vec4(p + B * (h / max(length(B), 1e-20)), 1.0);
  float toTexels = 0.5 * float(mapResolution);
  vec2 ja = (ca.xy / ca.w - c0.xy / c0.w) * toTexels * (length(A) / h);
  vec2 jb = (cb.xy / cb.w - c0.xy / c0.w) * toTexels * (length(B) / h);
  float reach = max(max(length(ja), length(jb)), 1e-6);  // texels per unit of penumbraScale
  // The blockers' mean depth: first over the widest penumbra (the nearest depth in the view), then
  // again over the penumbra of that mean, counting only the blockers that lie in the cone from the
  // receiver to the light (at a blocker's depth the cone is the light's shape scaled by
  // penumbraScale(depth, stored)), so that parts of an occluder too far to the side to hide the
  // light do not count.
  float scale = clamp(penumbraScale(depth, lightNearDepth), 1.0 / reach, maxReach / reach);
  float blockerDepth = 0.0;
  for (int pass = 0; pass < 2; ++pass) {
    float blockers = 0.0, sum = 0.0;
    for (int k = 0; k < 16; ++k) {
      vec2 x = shapePoint(k, 16), offset = scale * (x.x * ja + x.y * jb);
      ivec2 t = clamp(ivec2(centre + offset), ivec2(0), ivec2(mapResolution - 1));
      float stored = texelFetch(map, t, 0).r;
      if (stored < depth - 2.0 * texel - slope * length(offset) * texel &&
          (pass == 0 || shapeNorm(x) * scale <= penumbraScale(depth, stored) + coneAllowance / reach))
        blockers += 1.0, sum += stored;
    }
    if (blockers == 0.0) {
      if (pass == 0) return 1.0;
      break;  // the second look found none in the cone: keep the first's
    }
    blockerDepth = sum / blockers;
    scale = clamp(penumbraScale(depth, blockerDepth), 1.0 / reach, maxReach / reach);
  }
  float width = clamp(penumbraScale(depth, blockerDepth), 0.5 / reach, maxReach / reach);
  float lit = 0.0;
  for (int k = 0; k < 32; ++k) {
    vec2 x = shapePoint(k, 32), offset = width * (x.x * ja + x.y * jb);
    ivec2 t = clamp(ivec2(centre + offset), ivec2(0), ivec2(mapResolution - 1));
    float stored = texelFetch(map, t, 0).r;
    if (depth <= stored + 2.0 * texel + slope * length(offset) * texel) lit += 1.0;
  }
  return lit / 32.0;
}

float ggx(float nh, float alpha2) {
  float d = nh * nh * (alpha2 - 1.0) + 1.0;
  return alpha2 / (PI * d * d);
}
float smithG1(float nv, float alpha2) {
  return 2.0 * nv / (nv + sqrt(alpha2 + (1.0 - alpha2) * nv * nv));
}

// Through a part: the light entered where this view's light first meets the object (the
// irradiance buffer's texel over p) and crossed the thickness between there and p.
vec3 transmitted(vec3 p, vec3 n, int m, float object, vec3 V, ivec2 t) {
  vec4 pe = texelFetch(irradiancePositionMaterial, t, 0);
  vec4 ne = texelFetch(irradianceNormalObject, t, 0);
  if (pe.w < 0.0 || ne.w != object || !isTabulated(int(pe.w))) return vec3(0.0);
  float depth = lightType == LIGHT_SUN ? dot(p, lightDirection) : distance(p, lightPosition);
  float mu0 = clamp(dot(ne.xyz, towardsLight(pe.xyz)), 0.0, 1.0);
  float thickness = max(depth - texelFetch(irradianceLightDepth, t, 0).r, 0.0) * mu0;  // along the entry's normal
  float mu = clamp(dot(n, V), 0.0, 1.0);
  vec3 entering = (lightAreaCorners > 0 ? surfaceIrradiance(pe.xyz, ne.xyz) : irradianceFacingLight(pe.xyz) * mu0) *
                  lightWeight(ne.xyz) * fresnelTransmittance(materials[m].optics.x, mu0);
  return entering * transmittedRadiance(m, thickness * materials[m].extinction.rgb, mu0, mu) *
         fresnelTransmittance(materials[m].optics.x, mu) * slabLikeness(dot(ne.xyz, n));
}

void main() {
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
  bool tabulated = transmission != 0 && isTabulated(m);
  if (nl <= 0.0 && !tabulated) discard;

  // Does this view own the pixel, and does the light reach it?
  float texel = lightType == LIGHT_SUN ? shadowTexelSize
                               : shadowTexelSize * distance(p, lightPosition);
  vec3 offset = p + n * (1.5 * texel);
  vec4 clip = lightViewProj * vec4(offset, 1.0);
  vec3 ndc = clip.xyz / clip.w;
  bool inside = clip.w > 0.0 && all(lessThan(abs(ndc.xy), vec2(1.0)));
  float visibility = 1.0;
  if (inside && lightSoftSize > 0.0 && lightType == LIGHT_SUN) {  // on the shadow map, its texels and bias its own
    float fineTexel = texel * float(resolution) / float(shadowResolution);
    vec3 fine = p + n * (1.5 * fineTexel);
    vec4 c = lightViewProj * vec4(fine, 1.0);
    float slope = min(sqrt(max(1.0 - nl * nl, 0.0)) / max(nl, 1e-3), 8.0);
    visibility = softVisibility(shadowDepth, shadowResolution, c.xy / c.w, dot(fine, lightDirection), fineTexel,
                                slope, p);
  } else if (inside && lightSoftSize > 0.0) {  // on the irradiance buffer's map
    float slope = min(sqrt(max(1.0 - nl * nl, 0.0)) / max(nl, 1e-3), 8.0);
    visibility = softVisibility(irradianceLightDepth, resolution, ndc.xy, distance(offset, lightPosition), texel,
                                slope, p);
  } else if (inside) {  // on the shadow map, its texels and bias its own
    float fineTexel = texel * float(resolution) / float(shadowResolution);
    vec3 fine = p + n * (1.5 * fineTexel);
    vec4 c = lightViewProj * vec4(fine, 1.0);
    vec2 q = c.xy / c.w;
    ivec2 t = clamp(ivec2((q * 0.5 + 0.5) * float(shadowResolution)), ivec2(0), ivec2(shadowResolution - 1));
    float stored = texelFetch(shadowDepth, t, 0).r;
    float depth = lightType == LIGHT_SUN ? dot(fine, lightDirection) : distance(fine, lightPosition);
    visibility = depth <= stored + 2.0 * fineTexel ? 1.0 : 0.0;
  } else if (unshadowedOutside == 0) {
    discard;
  }

  vec3 through = vec3(0.0);
  if (tabulated && (nl <= 0.0 || visibility == 0.0)) {
    vec4 c = lightViewProj * vec4(p, 1.0);  // the texel over p itself, not over the offset point
    vec2 q = c.xy / c.w;
    if (c.w > 0.0 && all(lessThan(abs(q), vec2(1.0))))
      through = transmitted(p, n, m, po.w, V, clamp(ivec2((q * 0.5 + 0.5) * float(resolution)), ivec2(0),
                                                        ivec2(resolution - 1))) * tint;
  }
  float nsl = dot(ns, L);
  if (nl <= 0.0 || nsl <= 0.0) {
    radiance = vec4(through, 0.0);
    return;
  }

  vec3 E = (lightAreaCorners > 0 ? surfaceIrradiance(p, ns) : irradianceFacingLight(p) * nsl) * visibility * lightWeight(ns);
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
