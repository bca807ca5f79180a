// MATERIAL_EDIT's precomputation (docs/MATERIAL_EDIT.md): splat.geom's quads for the transport of
// the edit basis (material/profile_basis.h), one group of its splines per draw. Lengths of the
// basis are in units of the material's R_P (materials[m].ranges.y, scene units). A group reaches
// from groupRange.x to groupRange.y of them; splatting level k takes the distances from the first
// knot whose gaps, from there on, are all at least knotPixels of that level's pixels (where the
// splines vary slowly enough to be summed at its resolution) to the next level's.
layout(points) in;
layout(triangle_strip, max_vertices = 4) out;
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
uniform float depthFar;  // splat_depth.frag's: the quad's depth is its sphere's far side over it
uniform float footprintReach;  // x sigma
uniform int splatLevel;
uniform int splatLevels;
uniform float levelHeight[8];
uniform int group;             // 0: the near group (splines 0-8), 1: the far group (9-17)
uniform vec2 groupRange;       // this draw's splines' support, R_P units
uniform int knotCount;
uniform float knots[24];       // the basis's knots, R_P units
uniform float knotPixels;
uniform float supportGrowth;   // the far group reaches this many times the material's support
uniform vec2 viewportSize;     // pixels of the level drawn
flat out vec2 splatRange;      // [R_min, R_max) of this level and group, scene units
flat out vec3 splatPosition;
flat out vec3 splatFlux;
flat out float splatFootprint;
flat out float splatObject;
flat out int splatMaterial;
flat out vec4 splatNormalMu0;
flat out vec2 splatSlab;
// The kernels' footprint terms (common.glsl: kernelFootprint), once a splat rather than once a
// fragment: this group's three layers of splines, each (row, scale, reach), and the material's own
// kernel's.
uniform vec2 kernelLog2Range;
uniform float layerSupport[3];
flat out vec3 layerFootprint[3];
flat out vec3 ownFootprint;

// The first knot (scene units) from which every gap is at least knotPixels pixels of `pixel`.
float smoothFrom(float pixel, float ell) {
  float from = knots[knotCount - 1] * ell;
  for (int i = knotCount - 2; i >= 0; --i) {
    if ((knots[i + 1] - knots[i]) * ell < knotPixels * pixel) break;
    from = knots[i] * ell;
  }
  return from;
}

void main() {
  int m = sampleIn[0].material;
  if (m < 0 || !isTranslucent(m)) return;
  vec3 flux = sampleIn[0].flux;
  if (max(flux.r, max(flux.g, flux.b)) <= 0.0) return;
  float ell = materials[m].ranges.y;
  float footprint = sampleIn[0].footprint;
  float pad = footprintReach * footprint;
  // The far group's splines reach supportGrowth times the material's support
  // (TransportSplatting::kSupportGrowth), up to the basis's end, and its means (layer 7) the
  // material's own support; the near group's splines and means end at groupRange.y R_P.
  float reach = groupRange.y * ell;
  if (group != 0) reach = max(min(reach, supportGrowth * materials[m].ranges.x), materials[m].ranges.x);
  vec2 range = vec2(max(groupRange.x * ell - pad, 0.0), reach + pad);
  vec3 c = (worldToView * vec4(sampleIn[0].position, 1.0)).xyz;
  if (splatLevels > 1) {
    bool orthographic = viewToClip[3][3] > 0.5;
    float extent = orthographic ? 2.0 / viewToClip[1][1] : 2.0 * max(-c.z, 1e-6) / viewToClip[1][1];
    float lo = splatLevel == 0 ? 0.0 : smoothFrom(extent / levelHeight[splatLevel], ell);
    float hi = splatLevel + 1 >= splatLevels ? 1e30 : smoothFrom(extent / levelHeight[splatLevel + 1], ell);
    range = vec2(max(range.x, lo), min(range.y, hi));
    if (range.x >= range.y) return;
  }
  vec2 lo, hi;
  if (!splatQuad(c, range.y, viewToClip, splatLevel > 0 ? 1.0 / viewportSize : vec2(0.0), lo, hi)) return;
  float far = splatFarDepth(c, range.y, depthFar);
  for (int i = 0; i < 4; ++i) {
    splatRange = range;
    splatPosition = sampleIn[0].position;
    splatFlux = flux;
    splatFootprint = footprint;
    splatObject = sampleIn[0].object;
    splatMaterial = m;
    splatNormalMu0 = sampleIn[0].normalMu0;
    splatSlab = sampleIn[0].slab;
    for (int t = 0; t < 3; ++t)
      layerFootprint[t] = kernelFootprint(kernelLog2Range, footprintReach, layerSupport[t] * ell, footprint);
    ownFootprint = kernelFootprint(kernelLog2Range, footprintReach, materials[m].ranges.x, footprint);
    gl_Position = vec4((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y, 2.0 * far - 1.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}
