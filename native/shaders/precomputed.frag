// PRECOMPUTED's exitance at a pixel: the local response looked up in the atlas (bilinear; a
// chart's border carries receivers of its own, so the lookup does not blend in another chart) plus
// the global response interpolated from the vertices. The depth test keeps the nearest surface; the
// final shading reads the exitance only where the camera's buffers show a translucent surface.
in vec2 uv;
in vec4 globalExitance;
layout(binding = UNIT_EXITANCE_BUFFER) uniform sampler2D localExitance;
layout(location = 0) out vec4 exitance;

void main() { exitance = texture(localExitance, uv) + globalExitance; }
