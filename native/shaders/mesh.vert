// Object to world, then the view (camera or light) being rendered.
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec2 uv;  // (0, 0) when the mesh has none
uniform mat4 objectToWorld;
uniform mat3 normalToWorld;
uniform mat4 viewProj;
out vec3 worldPosition;
out vec3 worldNormal;
out vec2 surfaceUv;
void main() {
  vec4 p = objectToWorld * vec4(position, 1.0);
  worldPosition = p.xyz;
  worldNormal = normalToWorld * normal;
  surfaceUv = uv;
  gl_Position = viewProj * p;
}
