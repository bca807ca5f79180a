// PRECOMPUTED with TABULATED materials (docs/PRECOMPUTED.md, "A frame"): of a light view's
// irradiance buffer only where its light enters each texel, which the light through thin parts
// reads (direct_lighting.frag, transmitted): position and material, normal and object, light depth
// and the share of the light reaching it, as irradiance_buffer.frag writes them. No flux: nothing
// is splatted (its target, location 1, is left as it was).
in vec3 worldPosition;
in vec3 worldNormal;
in vec2 surfaceUv;
layout(binding = UNIT_TRIANGLE_MATERIALS) uniform usamplerBuffer triangleMaterials;
uniform int meshHasUvs;
uniform float objectIndex;
uniform int resolution;
uniform int softEntries;
layout(binding = UNIT_SHADOW_DEPTH) uniform sampler2D softMap;
uniform int softMapResolution;
layout(location = 0) out vec4 positionMaterial;  // xyz, material (-1 opaque, or no light enters)
layout(location = 2) out vec4 normalObject;      // xyz (towards the light), object index
layout(location = 3) out vec2 lightDepth;        // distance along the light's rays, the share of the light reaching it

void main() {
  int base = int(texelFetch(triangleMaterials, gl_PrimitiveID).r);
  int material = profileEntry(base, surfaceUv, meshHasUvs != 0);
  vec3 dx = dFdx(worldPosition), dy = dFdy(worldPosition);
  vec3 L = towardsLight(worldPosition);
  vec3 geometric = normalize(cross(dx, dy));
  vec3 n = normalize(worldNormal);
  if (dot(n, L) < 0.0) n = -n;  // two-sided, as Cycles
  lightDepth = vec2(lightDepthOf(worldPosition), 1.0);
  bool translucent = isTranslucent(material);
  if (softEntries != 0 && !translucent) discard;
  if (translucent && softEntries != 0) {
    lightDepth.g = softVisibilityAt(softMap, softMapResolution, resolution, worldPosition, geometric * sign(dot(geometric, L)),
                                    abs(dot(geometric, L)), objectIndex);
    if (lightDepth.g == 0.0) translucent = false;
  }
  positionMaterial = vec4(worldPosition, translucent ? float(material) : -1.0);
  normalObject = vec4(n, objectIndex);
}
