// PRECOMPUTED's exitance at a pixel: the local response looked up in the atlas (bilinear; a
// chart's border carries its own response, so the lookup does not blend in another chart) plus
// the global response interpolated from the vertices. Only where the camera's buffers see this
// object, so that the exitance has FULL's pixels.
in vec2 uv;
in vec4 globalExitance;
layout(binding = UNIT_EXITANCE_BUFFER) uniform sampler2D localExitance;
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;
uniform float objectIndex;
layout(location = 0) out vec4 exitance;

void main() {
  if (texelFetch(splattingPositionObject, ivec2(gl_FragCoord.xy), 0).w != objectIndex) discard;
  exitance = texture(localExitance, uv) + globalExitance;
}
