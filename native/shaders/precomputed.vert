// PRECOMPUTED's exitance (docs/PRECOMPUTED.md): an object's triangles seen by the camera, each
// corner with its atlas coordinate (the local response) and its vertex's global response.
layout(location = 0) in vec3 position;  // world
layout(location = 1) in vec2 atlasUv;   // 0..1
layout(location = 2) in vec4 global;    // B at the vertex (rgb) and the TABULATED alpha
uniform mat4 viewProj;
out vec2 uv;
out vec4 globalExitance;

void main() {
  uv = atlasUv;
  globalExitance = global;
  gl_Position = viewProj * vec4(position, 1.0);
}
