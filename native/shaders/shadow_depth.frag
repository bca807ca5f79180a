// A light view's shadow map at its own resolution (docs/SOFT_SHADOWS.md): the light depth of the
// nearest surface, as irradiance_buffer.frag writes it, and its object (softVisibility's ignoredObject).
in vec3 worldPosition;
in vec3 worldNormal;
in vec2 surfaceUv;
uniform float objectIndex;
layout(location = 0) out vec2 lightDepthObject;  // distance along the light's rays, the object's index
void main() {
  lightDepthObject = vec2(lightDepthOf(worldPosition), objectIndex);
}
