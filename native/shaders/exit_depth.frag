// Thin parts (TABULATED model, material/transport_model.h): where the light leaves what it
// entered. The nearest surface facing away from the light along each of the view's rays, with
// its object: the exit of the first surface's object when the object is closed (its normals point
// out). IrradianceBuffer::applyIncidence takes the thickness from it.
in vec3 worldPosition;
in vec3 worldNormal;
in vec2 surfaceUv;
uniform float objectIndex;
// Set when the irradiance buffer holds translucent surfaces only (irradiance_buffer.frag: softEntries):
// opaque surfaces are not exits either.
uniform int translucentOnly;
layout(binding = UNIT_TRIANGLE_MATERIALS) uniform usamplerBuffer triangleMaterials;
// Distance along the light's rays, object index, the surface's normal (octahedral: octEncode).
layout(location = 0) out vec4 exitDepthObject;
void main() {
  if (dot(worldNormal, towardsLight(worldPosition)) >= 0.0) discard;  // faces the light: an entry
  if (translucentOnly != 0 && !isTranslucent(int(texelFetch(triangleMaterials, gl_PrimitiveID).r))) discard;
  float depth = lightType == LIGHT_SUN ? dot(worldPosition, lightDirection) : distance(worldPosition, lightPosition);
  exitDepthObject = vec4(depth, objectIndex, octEncode(normalize(worldNormal)));
}
