// Debug pass: the colour of the sample's irradiance level.
flat in int debugLevel;
flat in vec3 debugPosition;
flat in float debugObject;
flat in float debugReach;
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;
layout(location = 0) out vec4 colour;
const vec3 kLevelColours[8] = vec3[8](vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(1, 1, 0),
                                      vec3(1, 0, 1), vec3(0, 1, 1), vec3(1, 1, 1), vec3(1, 0.5, 0));
void main() {
  vec4 po = texelFetch(splattingPositionObject, ivec2(gl_FragCoord.xy), 0);
  if (po.w != debugObject || distance(po.xyz, debugPosition) > max(debugReach, 1e-6)) discard;
  colour = vec4(kLevelColours[clamp(debugLevel, 0, 7)], 1.0);
}
