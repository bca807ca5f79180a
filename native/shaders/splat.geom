// A screen-space quad bounding the sphere of radius (footprint reach + support)
// around the sample: every pixel the kernel can reach. A level-0 texel that a
// profile boundary crosses (splat.vert's split) is two splats, one per
// profile, each with its share of the flux and of the footprint's area, at the
// centroid of its part: the boundary stays sharper than the texel.
layout(points) in;
layout(triangle_strip, max_vertices = 8) out;
in SplatSample {
  vec3 position;
  vec3 flux;
  float footprint;
  float object;
  int material;
  int level;  // irradiance level the sample was selected at
  vec4 split; // level 0: a second profile's part (splat.vert)
  vec4 normalMu0; // the texel's normal (facing the light) and its cosine to the light
  vec2 slab;
  vec3 along;         // TABULATED: the forward shift (splat.vert)
  vec3 shiftLengths;
  vec3 shiftDrops;
} sampleIn[];
uniform mat4 worldToView;
uniform mat4 viewToClip;
uniform float depthFar;  // splat_depth.frag's: the quad's depth is its sphere's far side over it
uniform float footprintReach;  // x sigma
uniform vec2 kernelLog2Range;  // table rows: log2(sigma / support) at first and last
// Multiresolution splatting (eq. 12-14): level splatLevel of splatLevels takes
// the distances [R_min^k, R_max^k); R_min^k = R_P R-bar(T_k), T_k the pixels
// per R_P at that level; level 0 starts at 0 and the coarsest ends at the reach.
uniform int splatLevel;
uniform int splatLevels;
uniform float levelHeight[8];     // pixel rows of each splatting level
layout(binding = UNIT_MINIMAL_RADIUS) uniform sampler2D minimalRadius;  // R-bar over log2 T, one row per kernel layer
uniform vec2 minimalRadiusLog2T;  // log2 T at the first and last column
uniform float kernelLayers;
// The splatting budget (pipeline/splatting.h): with measureBounds, each sample adds to its slot of
// bounds (the draw's primitive index) an upper bound of the fragment invocations its quads cost,
// and emits nothing. Within the quad's pixels aligned out to 4 x 4 blocks (W x H), every block is
// shaded at most once per triangle, whatever the driver counts of it (llvmpipe shades 4 x 4 blocks;
// GPUs 2 x 2 quads, helpers included), and only those the diagonal crosses (at most W/4 + H/4 - 1)
// by both: W H + 4 (W + H) - 16.
uniform int measureBounds;
uniform vec2 viewportSize;        // pixels of the level drawn (splatQuad's margin, the bounds)
layout(std430, binding = STORAGE_SPLAT_BOUNDS) buffer SplatBounds { uint bounds[]; };
flat out vec2 splatRange;         // [R_min, R_max) of this level
flat out float splatKernelRow; // the footprint's row of the kernel table, in [0, 1]
flat out vec3 splatPosition;
flat out vec3 splatFlux;
flat out float splatFootprint;
flat out float splatObject;
flat out int splatMaterial;
flat out vec4 splatNormalMu0;
flat out vec3 splatAlong;
flat out vec3 splatShiftLengths;
flat out vec3 splatShiftDrops;
// One splat of material entry m at position with the flux and footprint sigma. Under the TABULATED
// model the kernel is centred ahead of the sample along the beam (each channel by its own length),
// so the quad and the last level reach that much further.
void emitSplat(int m, vec3 position, vec3 flux, float footprint) {
  bool shifted = isTabulated(m);
  vec3 along = shifted ? sampleIn[0].along : vec3(0.0), lengths = shifted ? sampleIn[0].shiftLengths : vec3(0.0);
  vec3 drops = shifted ? sampleIn[0].shiftDrops : vec3(0.0);
  float sinT2 = dot(along, along), longest = 0.0;  // the longest shift, the move onto the surface included
  for (int k = 0; k < 3; ++k) longest = max(longest, sqrt(sinT2 * lengths[k] * lengths[k] + drops[k] * drops[k]));
  float reach = footprintReach * footprint + materials[m].ranges.x + longest;
  vec3 c = (worldToView * vec4(position, 1.0)).xyz;
  vec2 range = vec2(0.0, reach);
  if (splatLevels > 1) {
    float rangeP = materials[m].ranges.y;  // the longest channel's R_P, as the R-bar table
    float layer = (materials[m].optics.w + 0.5) / kernelLayers;
    bool orthographic = viewToClip[3][3] > 0.5;
    float extent = orthographic ? 2.0 / viewToClip[1][1] : 2.0 * max(-c.z, 1e-6) / viewToClip[1][1];
    // R_min of level k (k >= 1) from R-bar at that level's resolution.
    float rMin[2];
    for (int j = 0; j < 2; ++j) {
      int k = splatLevel + j;
      if (k == 0 || k >= splatLevels) { rMin[j] = k == 0 ? 0.0 : reach; continue; }
      float T = rangeP / (extent / levelHeight[k]);
      float u = (log2(max(T, 1e-6)) - minimalRadiusLog2T.x) / (minimalRadiusLog2T.y - minimalRadiusLog2T.x);
      rMin[j] = rangeP * texture(minimalRadius, vec2(clamp(u, 0.0, 1.0), layer)).r;
    }
    range = clamp(vec2(rMin[0], rMin[1]), 0.0, reach);
    if (range.x >= range.y) return;
  }
  vec2 lo, hi;
  if (!splatQuad(c, range.y, viewToClip, splatLevel > 0 ? 1.0 / viewportSize : vec2(0.0), lo, hi)) return;
  if (measureBounds != 0) {
    vec2 first = floor((lo * 0.5 + 0.5) * viewportSize * 0.25) * 4.0;
    vec2 last = ceil((hi * 0.5 + 0.5) * viewportSize * 0.25) * 4.0;
    uvec2 size = uvec2(max(last - first, vec2(4.0)));
    atomicAdd(bounds[gl_PrimitiveIDIn], size.x * size.y + 4u * (size.x + size.y) - 16u);
    return;
  }

  float row = (log2(footprint / materials[m].ranges.x) - kernelLog2Range.x) /
              (kernelLog2Range.y - kernelLog2Range.x);
  float far = splatFarDepth(c, range.y, depthFar);
  for (int i = 0; i < 4; ++i) {
    splatKernelRow = clamp(row, 0.0, 1.0);
    splatRange = range;
    splatPosition = position;
    splatFlux = flux;
    splatFootprint = footprint;
    splatObject = sampleIn[0].object;
    splatMaterial = m;
    splatNormalMu0 = sampleIn[0].normalMu0;
    splatAlong = along;
    splatShiftLengths = lengths;
    splatShiftDrops = drops;
    gl_Position = vec4((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y, 2.0 * far - 1.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}

void main() {
  int m = sampleIn[0].material;
  if (m < 0 || !isTranslucent(m)) return;
  vec3 flux = sampleIn[0].flux;
  if (max(flux.r, max(flux.g, flux.b)) <= 0.0) return;
  vec4 split = sampleIn[0].split;
  int code = int(split.w + 0.5);
  int count = code % 32;
  if (count == 0) {
    emitSplat(m, sampleIn[0].position, flux, sampleIn[0].footprint);
    return;
  }
  // The parts' centroids average to the texel centre, weighted by their shares.
  int other = int(materials[m].profileMap.w) + code / 32;
  float share = float(count) / 16.0;
  if (count < 16)
    emitSplat(m, sampleIn[0].position - split.xyz * (share / (1.0 - share)), flux * (1.0 - share),
              sampleIn[0].footprint * sqrt(1.0 - share));
  emitSplat(other, sampleIn[0].position + split.xyz, flux * share, sampleIn[0].footprint * sqrt(share));
}
