// A light view's shadow map at its own resolution (docs/SOFT_SHADOWS.md): the light depth of the
// nearest surface, as irradiance_buffer.frag writes it.
in vec3 worldPosition;
in vec3 worldNormal;
in vec2 surfaceUv;
layout(location = 0) out float lightDepth;  // distance along the light's rays
void main() {
  lightDepth = lightType == LIGHT_SUN ? dot(worldPosition, lightDirection) : distance(worldPosition, lightPosition);
}
