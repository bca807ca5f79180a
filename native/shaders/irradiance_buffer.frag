// Buffer generation, light side: one texel per surface point the light sees,
// holding the flux E(x_i) dA(x_i) through it (eq. 5, 6) and the standard
// deviation of its Gaussian footprint (material/splat_kernel.h).
in vec3 worldPosition;
in vec3 worldNormal;
in vec2 surfaceUv;
uniform usamplerBuffer triangleMaterials;
uniform int meshHasUvs;
uniform float objectIndex;
uniform int resolution;
uniform float orthoTexelArea;   // sun: texel area perpendicular to the light
uniform float tanHalfFov;       // point, spot: half-extent of the view plane at distance 1
uniform float footprintSigma;   // x texel size
layout(location = 0) out vec4 positionMaterial;  // xyz, material (-1 opaque)
layout(location = 1) out vec4 fluxFootprint;     // rgb flux (W), footprint sigma
layout(location = 2) out vec4 normalObject;      // xyz, object index
layout(location = 3) out float lightDepth;       // distance along the light's rays
void main() {
  int material = profileEntry(int(texelFetch(triangleMaterials, gl_PrimitiveID).r), surfaceUv, meshHasUvs != 0);
  vec3 L = towardsLight(worldPosition);
  vec3 geometric = normalize(cross(dFdx(worldPosition), dFdy(worldPosition)));
  vec3 n = normalize(worldNormal);
  if (dot(n, L) < 0.0) n = -n;  // two-sided, as Cycles
  float cosShading = dot(n, L);
  float cosGeometric = max(abs(dot(geometric, L)), 0.1);

  // Area of the texel projected onto the plane facing the light, and flux.
  vec3 flux;
  float perpendicularArea;  // texel area on the plane facing the light
  if (lightType == 2) {
    flux = lightRadiant * orthoTexelArea;
    perpendicularArea = orthoTexelArea;
    lightDepth = dot(worldPosition, lightDirection);
  } else {
    vec2 ndc = gl_FragCoord.xy / float(resolution) * 2.0 - 1.0;
    vec2 plane = ndc * tanHalfFov;
    float texelSolidAngle = pow(2.0 * tanHalfFov / float(resolution), 2.0) /
                            pow(1.0 + dot(plane, plane), 1.5);
    float distance2 = dot(lightPosition - worldPosition, lightPosition - worldPosition);
    flux = irradianceFacingLight(worldPosition) * distance2 * texelSolidAngle;
    perpendicularArea = texelSolidAngle * distance2;
    lightDepth = sqrt(distance2);
  }
  if (isTranslucent(material)) {
    flux *= fresnelTransmittance(materials[material].optics.x, cosShading);
  } else {
    material = -1;
    flux = vec3(0.0);
  }
  positionMaterial = vec4(worldPosition, float(material));
  // On a slope the texel grid is stretched by 1 / cos along the slope; the
  // (isotropic) footprint follows the long axis so that it still tiles.
  fluxFootprint = vec4(flux, footprintSigma * sqrt(perpendicularArea) / cosGeometric);
  normalObject = vec4(n, objectIndex);
}
