// Buffer generation, camera side: the surface point x_o behind each pixel, and what the textures
// say of it (docs/TEXTURES.md).
in vec3 worldPosition;
in vec3 worldNormal;
in vec2 surfaceUv;
layout(binding = UNIT_TRIANGLE_MATERIALS) uniform usamplerBuffer triangleMaterials;
uniform int meshHasUvs;
uniform float objectIndex;
uniform vec3 cameraPosition;
uniform vec3 cameraForward;
uniform int orthographic;
layout(location = 0) out vec4 positionObject;  // xyz, object index (-1 none)
layout(location = 1) out vec4 normalMaterial;  // xyz facing the camera, material
layout(location = 2) out vec4 albedo;          // rgb: the colour texture (opaque albedo, translucent tint)
layout(location = 3) out vec4 shadingNormal;   // xyz: the normal map's (the geometric one without)
void main() {
  vec3 dpdx = dFdx(worldPosition), dpdy = dFdy(worldPosition);  // in uniform control flow
  vec2 duvdx = dFdx(surfaceUv), duvdy = dFdy(surfaceUv);
  int material = profileEntry(int(texelFetch(triangleMaterials, gl_PrimitiveID).r), surfaceUv, meshHasUvs != 0);
  vec3 n = normalize(worldNormal);
  vec3 V = orthographic != 0 ? -cameraForward : normalize(cameraPosition - worldPosition);
  if (dot(n, V) < 0.0) n = -n;
  positionObject = vec4(worldPosition, objectIndex);
  normalMaterial = vec4(n, float(material));
  albedo = vec4(materialColor(material, surfaceUv), 1.0);
  shadingNormal = vec4(mappedNormal(material, n, surfaceUv, dpdx, dpdy, duvdx, duvdy), 0.0);
}
