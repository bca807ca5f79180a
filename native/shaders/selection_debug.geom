// Debug pass: each selected, lit translucent sample as a point where it
// projects, kept only where it lies on the visible surface of its pixel.
layout(points) in;
layout(points, max_vertices = 1) out;
in SplatSample {
  vec3 position;
  vec3 flux;
  float footprint;
  float object;
  int material;
  int level;
  vec4 split;
  vec4 normalMu0;
  vec2 slab;
  vec3 along;
  vec3 shiftLengths;
  vec3 shiftDrops;
} sampleIn[];
uniform mat4 worldToView;
uniform mat4 viewToClip;
flat out int debugLevel;
flat out vec3 debugPosition;
flat out float debugObject;
flat out float debugReach;
void main() {
  int m = sampleIn[0].material;
  if (m < 0 || !isTranslucent(m)) return;
  vec3 flux = sampleIn[0].flux;
  if (max(flux.r, max(flux.g, flux.b)) <= 0.0) return;
  debugLevel = sampleIn[0].level;
  debugPosition = sampleIn[0].position;
  debugObject = sampleIn[0].object;
  debugReach = 2.0 * sampleIn[0].footprint;
  gl_Position = viewToClip * worldToView * vec4(sampleIn[0].position, 1.0);
  EmitVertex();
  EndPrimitive();
}
