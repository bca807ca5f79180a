// Object to world, then the view (camera or light) being rendered.
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 objectToWorld;
uniform mat3 normalToWorld;
uniform mat4 viewProj;
out vec3 worldPosition;
out vec3 worldNormal;
void main() {
  vec4 p = objectToWorld * vec4(position, 1.0);
  worldPosition = p.xyz;
  worldNormal = normalToWorld * normal;
  gl_Position = viewProj * p;
}
