// Buffer generation, light side: one texel per surface point the light sees,
// holding the flux E(x_i) dA(x_i) through it (eq. 5, 6) and the standard
// deviation of its Gaussian footprint (material/splat_kernel.h).
in vec3 worldPosition;
in vec3 worldNormal;
in vec2 surfaceUv;
layout(binding = UNIT_TRIANGLE_MATERIALS) uniform usamplerBuffer triangleMaterials;
uniform int meshHasUvs;
uniform float objectIndex;
uniform int resolution;
uniform float orthoTexelArea;   // sun: texel area perpendicular to the light
uniform float tanHalfFov;       // point, spot: half-extent of the view plane at distance 1
uniform float footprintSigma;   // x texel size
uniform int profileSplits;      // non-zero: write profileSplit
// Soft shadows on the light entering translucent objects (docs/SOFT_SHADOWS.md): in the SOFT_ENTRIES
// variant, opaque surfaces are not drawn here, and each translucent texel's flux is scaled by the share
// of the light that reaches it past other objects, filtered on softMap (a shadow map of every surface,
// with object indices) of softMapResolution texels.
// Compiled in variants (pipeline/irradiance_buffer.h: programs_) besides the scene's: SOFT_ENTRIES,
// and AREA_LIGHT, 1 for an area light (its polygon's irradiance on the texel). llvmpipe runs every line
// of a shader on every pixel, taken or not (docs/BENCHMARKS.md, "The direct light's variants"): behind
// uniforms, the soft filter and the polygon cost every view.
layout(binding = UNIT_SHADOW_DEPTH) uniform sampler2D softMap;
uniform int softMapResolution;
layout(location = 0) out vec4 positionMaterial;  // xyz, material (-1 opaque)
layout(location = 1) out vec4 fluxFootprint;     // rgb flux (W), footprint sigma
layout(location = 2) out vec4 normalObject;      // xyz, object index
layout(location = 3) out vec2 lightDepth;        // distance along the light's rays, the share of the light reaching it
layout(location = 4) out vec4 profileSplit;      // pipeline/irradiance_buffer.h: IrradianceBuffer::profileSplit

// Where a profile boundary crosses the texel: the texel's 4 x 4 sub-samples
// (from the UV and position derivatives) whose profile is another one than
// the centre's. Returns the part's middle offset (world units) and, in w,
// (its entry - base) * 32 + its count; w = 0 when the whole texel shows one
// profile. A third profile in one texel counts as the centre's.
vec4 splitOf(int base, int centre, vec2 du, vec2 dv, vec3 dx, vec3 dy) {
  int other = -1, count = 0;
  vec2 middle = vec2(0.0);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      vec2 s = (vec2(i, j) + 0.5) / 4.0 - 0.5;
      int e = profileEntry(base, surfaceUv + s.x * du + s.y * dv, true);
      if (e == centre || (other >= 0 && e != other)) continue;
      other = e;
      ++count;
      middle += s;
    }
  if (count == 0) return vec4(0.0);
  middle /= float(count);
  return vec4(middle.x * dx + middle.y * dy, float((other - base) * 32 + count));
}

void main() {
  int base = int(texelFetch(triangleMaterials, gl_PrimitiveID).r);
  int material = profileEntry(base, surfaceUv, meshHasUvs != 0);
  vec2 du = dFdx(surfaceUv), dv = dFdy(surfaceUv);  // derivatives in uniform control flow
  vec3 dx = dFdx(worldPosition), dy = dFdy(worldPosition);
  vec3 L = towardsLight(worldPosition);
  vec3 geometric = normalize(cross(dx, dy));
  vec3 n = normalize(worldNormal);
  if (dot(n, L) < 0.0) n = -n;  // two-sided, as Cycles
  float cosShading = dot(n, L);
  float cosGeometric = max(abs(dot(geometric, L)), 0.1);

  // Area of the texel projected onto the plane facing the light, and flux.
  vec3 flux;
  float perpendicularArea;  // texel area on the plane facing the light
  if (lightType == LIGHT_SUN) {
    flux = lightRadiant * orthoTexelArea;
    perpendicularArea = orthoTexelArea;
    lightDepth = vec2(dot(worldPosition, lightDirection), 1.0);
  } else {
    vec2 ndc = gl_FragCoord.xy / float(resolution) * 2.0 - 1.0;
    vec2 plane = ndc * tanHalfFov;
    float texelSolidAngle = pow(2.0 * tanHalfFov / float(resolution), 2.0) /
                            pow(1.0 + dot(plane, plane), 1.5);
    float distance2 = dot(lightPosition - worldPosition, lightPosition - worldPosition);
#if AREA_LIGHT
    // An area light: the polygon's irradiance on the texel's surface, times that surface's area.
    flux = lightRadiant * polygonIrradiance(worldPosition, n) * distance2 * texelSolidAngle / max(cosShading, 1e-3);
#else
    flux = irradianceFacingLight(worldPosition) * distance2 * texelSolidAngle;
#endif
    perpendicularArea = texelSolidAngle * distance2;
    lightDepth = vec2(sqrt(distance2), 1.0);
  }
  bool translucent = isTranslucent(material);
#if SOFT_ENTRIES
  if (!translucent) discard;
  lightDepth.g = softVisibilityAt(softMap, softMapResolution, resolution, worldPosition, geometric * sign(dot(geometric, L)),
                                  abs(dot(geometric, L)), objectIndex);
  if (lightDepth.g == 0.0) translucent = false;  // in the umbra: no light enters, nothing to splat
#endif
  if (translucent) {
    // The colour texture's tint, sqrt(T) as the light enters (final_shading.frag: sqrt(T) as it leaves).
    flux *= fresnelTransmittance(materials[material].optics.x, cosShading) * lightWeight(n) *
            sqrt(materialColor(material, surfaceUv)) * lightDepth.g;
  } else {
    material = -1;
    flux = vec3(0.0);
  }
  positionMaterial = vec4(worldPosition, float(material));
  // On a slope the texel grid is stretched by 1 / cos along the slope; the
  // (isotropic) footprint follows the long axis so that it still tiles.
  fluxFootprint = vec4(flux, footprintSigma * sqrt(perpendicularArea) / cosGeometric);
  normalObject = vec4(n, objectIndex);
  profileSplit = vec4(0.0);
  if (profileSplits != 0 && material >= 0 && meshHasUvs != 0 && materials[base].profileMap.y * materials[base].profileMap.z > 1u) {
    vec4 split = splitOf(base, material, du, dv, dx, dy);
    profileSplit = vec4(split.xyz / max(fluxFootprint.a, 1e-30), split.w);
  }
}
