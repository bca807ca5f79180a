// The frame's coverage figures (SsStats): pixels whose surface is translucent,
// and of those the ones with some finite subsurface exitance. Counted here so
// that the frame reads back only its image.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_EXITANCE_BUFFER) uniform sampler2D exitanceBuffer;
uniform ivec2 size;
uniform int materialCount;
layout(std430, binding = STORAGE_COVERAGE_COUNTS) buffer CoverageCounts {
  uint translucentPixels;
  uint litTranslucentPixels;
};

// By the bits, which no optimisation of isinf or isnan can fold away.
bool finite(float x) { return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u; }

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, size))) return;
  int m = int(texelFetch(splattingNormalMaterial, p, 0).w);
  if (m < 0 || m >= materialCount || materials[m].baseColorKind.w <= 0.5) return;
  atomicAdd(translucentPixels, 1u);
  vec3 b = texelFetch(exitanceBuffer, p, 0).rgb;
  if (finite(b.r) && finite(b.g) && finite(b.b) && b.r + b.g + b.b > 0.0) atomicAdd(litTranslucentPixels, 1u);
}
