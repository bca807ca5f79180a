// A screen-space quad bounding the sphere of radius (footprint reach + support)
// around the sample: every pixel the kernel can reach.
layout(points) in;
layout(triangle_strip, max_vertices = 4) out;
in SplatSample {
  vec3 position;
  vec3 flux;
  float footprint;
  float object;
  int material;
} sampleIn[];
uniform mat4 worldToView;
uniform mat4 viewToClip;
uniform float footprintReach;  // x sigma
uniform vec2 kernelLog2Range;  // table rows: log2(sigma / support) at first and last
flat out float splatKernelRow; // the footprint's row of the kernel table, in [0, 1]
flat out vec3 splatPosition;
flat out vec3 splatFlux;
flat out float splatFootprint;
flat out float splatObject;
flat out int splatMaterial;
void main() {
  int m = sampleIn[0].material;
  if (m < 0 || !isTranslucent(m)) return;
  vec3 flux = sampleIn[0].flux;
  if (max(flux.r, max(flux.g, flux.b)) <= 0.0) return;
  float radius = footprintReach * sampleIn[0].footprint + materials[m].ranges.x;

  // Bound the sphere by the projections of its view-space box corners.
  vec3 c = (worldToView * vec4(sampleIn[0].position, 1.0)).xyz;
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  bool behind = false;
  for (int i = 0; i < 8; ++i) {
    vec3 corner = c + radius * vec3((i & 1) != 0 ? 1.0 : -1.0, (i & 2) != 0 ? 1.0 : -1.0,
                                    (i & 4) != 0 ? 1.0 : -1.0);
    vec4 clip = viewToClip * vec4(corner, 1.0);
    if (clip.w <= 1e-6) { behind = true; break; }
    lo = min(lo, clip.xy / clip.w);
    hi = max(hi, clip.xy / clip.w);
  }
  if (behind) { lo = vec2(-1.0); hi = vec2(1.0); }
  lo = max(lo, vec2(-1.0));
  hi = min(hi, vec2(1.0));
  if (any(greaterThanEqual(lo, hi))) return;

  float row = (log2(sampleIn[0].footprint / materials[m].ranges.x) - kernelLog2Range.x) /
              (kernelLog2Range.y - kernelLog2Range.x);
  for (int i = 0; i < 4; ++i) {
    splatKernelRow = clamp(row, 0.0, 1.0);
    splatPosition = sampleIn[0].position;
    splatFlux = flux;
    splatFootprint = sampleIn[0].footprint;
    splatObject = sampleIn[0].object;
    splatMaterial = m;
    gl_Position = vec4((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y, 0.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}
