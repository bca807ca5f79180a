// Buffer generation, camera side: the surface point x_o behind each pixel.
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
void main() {
  int material = profileEntry(int(texelFetch(triangleMaterials, gl_PrimitiveID).r), surfaceUv, meshHasUvs != 0);
  vec3 n = normalize(worldNormal);
  vec3 V = orthographic != 0 ? -cameraForward : normalize(cameraPosition - worldPosition);
  if (dot(n, V) < 0.0) n = -n;
  positionObject = vec4(worldPosition, objectIndex);
  normalMaterial = vec4(n, float(material));
}
