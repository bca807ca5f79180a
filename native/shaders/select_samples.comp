// Sample selection (paper sec. 4, Algorithm 1), once per light view: which irradiance samples are
// splatted, listed for every splatting draw of the view (splat.vert reads the list). The samples
// are the texels of every level of the irradiance hierarchy, numbered level by level, rows in
// order (levelOffset[k]: level k's first). BRUTE (levels == 1) takes every finest texel. The
// adaptive methods (DESIGN.md's reading of Algorithm 1): a texel is valid at level k when its depth
// range is below z0 and the level's texel, projected onto the surface, is fine enough for the
// material,
//   texel_k / |n.L| < R_P / alpha            (eq. 10, 11 with T^k = R_w / texel_k);
// it is selected when no ancestor is valid and it is valid itself or at level 0. A texel that shows
// two profiles (its split) must be fine enough for both. Each level-0 texel is therefore covered by
// exactly one selected sample. Only texels of a translucent material are listed.
//
// Three passes (pass), over chunks of kChunk consecutive samples, one chunk an invocation:
//   0. each invocation evaluates its chunk (which samples are chosen: a bit mask), the workgroup
//      numbers its chunks' chosen samples in order, and each invocation writes its first number
//      within the workgroup and its mask (ranks); the workgroup writes how many it has (blocks);
//   1. one workgroup turns those counts into each workgroup's first place in the list and writes
//      the total as glDrawArraysIndirect's command;
//   2. each invocation writes its chunk's chosen samples' numbers from its place on.
// The list is in the samples' order whatever order the invocations run in, so splats blend in the
// same order on every run and every driver (docs/ANIMATION.md, "Determinism across processes").
// Chunks, not a sample an invocation: a workgroup's scan costs barriers, which llvmpipe runs by
// switching between its invocations; with 16 samples an invocation a workgroup of 64 lists 1024
// samples in 3 barriers (256 samples took 17 before: docs/BENCHMARKS.md, "The list in chunks").
layout(local_size_x = 64) in;
const int kInvocations = 64;  // local_size_x: SampleList::kGroupInvocations
const int kChunk = 16;        // samples an invocation: SampleList::kChunk
layout(binding = UNIT_IRRADIANCE_POSITION_MATERIAL) uniform sampler2D irradiancePositionMaterial;
layout(binding = UNIT_IRRADIANCE_NORMAL_OBJECT) uniform sampler2D irradianceNormalObject;
layout(binding = UNIT_IRRADIANCE_DEPTH_RANGE) uniform sampler2D irradianceDepthRange;  // levels >= 1
layout(binding = UNIT_IRRADIANCE_PROFILE_SPLIT) uniform sampler2D irradianceProfileSplit;  // when profileSplits != 0 (pipeline/irradiance_buffer.h)
uniform int profileSplits;
uniform int resolution;
uniform int levels;              // 1: BRUTE
uniform int levelOffset[9];      // first sample of each level; levelOffset[levels] = total
uniform float z0;                // depth-range threshold, scene units
uniform float alpha;             // eq. 11's scale
uniform int pass;
uniform int countSelection;      // 1: pass 0 adds the selected samples per level to selected[]
layout(std430, binding = STORAGE_SELECTION_COUNTS) buffer SelectionCounts { uint selected[8]; };
layout(std430, binding = STORAGE_SAMPLE_RANKS) buffer SampleRanks { uint rank[]; };
layout(std430, binding = STORAGE_SAMPLE_BLOCKS) buffer SampleBlocks { uint blocks[]; };
layout(std430, binding = STORAGE_SAMPLE_LIST) buffer SampleList {
  uint command[4];  // glDrawArraysIndirect's: count, instances, first, base instance
  uint samples[];
};
shared uint scan[kInvocations];
shared uint scanTotal;
shared uint groupSelected[8];

bool valid(int level, ivec2 texel) {
  vec4 pm = texelFetch(irradiancePositionMaterial, texel, level);
  int m = int(pm.w);
  if (pm.w < 0.0 || !isTranslucent(m)) return false;
  vec2 range = texelFetch(irradianceDepthRange, texel, level).rg;
  if (range.y - range.x >= z0) return false;
  vec3 n = texelFetch(irradianceNormalObject, texel, level).xyz;
  float nl = max(abs(dot(n, towardsLight(pm.xyz))), 1e-3);  // grazing: finest level, never infinite
  float texel0 = lightType == LIGHT_SUN ? shadowTexelSize : shadowTexelSize * distance(pm.xyz, lightPosition);
  float rangeP = materials[m].ranges.z;
  if (profileSplits != 0) {
    int code = int(texelFetch(irradianceProfileSplit, texel, level).w + 0.5);
    if (code % 32 != 0) rangeP = min(rangeP, materials[int(materials[m].profileMap.w) + code / 32].ranges.z);
  }
  return float(1 << level) * texel0 / nl < rangeP / alpha;
}

// Whether sample i (of levelOffset's numbering) is splatted; its level.
bool isSelected(int i, out int level) {
  level = 0;
  while (level + 1 < levels && i >= levelOffset[level + 1]) ++level;
  int size = max(resolution >> level, 1);
  int index = i - levelOffset[level];
  ivec2 texel = ivec2(index % size, index / size);
  if (levels > 1) {
    for (int k = level + 1; k < levels; ++k)
      if (valid(k, texel >> (k - level))) return false;
    if (level > 0 && !valid(level, texel)) return false;
  }
  vec4 pm = texelFetch(irradiancePositionMaterial, texel, level);
  return pm.w >= 0.0 && isTranslucent(int(pm.w));
}

// Exclusive prefix sums of scan[] across the workgroup, in place; returns the workgroup's total.
// One invocation adds them up: 64 additions cost llvmpipe less than a parallel scan's barriers.
uint scanWorkgroup() {
  barrier();
  if (gl_LocalInvocationID.x == 0u) {
    uint sum = 0u;
    for (int j = 0; j < kInvocations; ++j) {
      uint v = scan[j];
      scan[j] = sum;
      sum += v;
    }
    scanTotal = sum;
  }
  barrier();
  return scanTotal;
}

void main() {
  uint lane = gl_LocalInvocationID.x;
  int total = levelOffset[levels];
  int first = int(gl_GlobalInvocationID.x) * kChunk;
  if (pass == 0) {
    if (lane < 8u) groupSelected[lane] = 0u;
    barrier();
    uint mask = 0u, count = 0u, run = 0u;
    int runLevel = 0;
    for (int j = 0; j < kChunk; ++j) {
      int level = 0;
      if (first + j >= total || !isSelected(first + j, level)) continue;
      mask |= 1u << j;
      ++count;
      if (countSelection == 0) continue;
      if (level != runLevel && run > 0u) {
        atomicAdd(groupSelected[runLevel], run);
        run = 0u;
      }
      runLevel = level;
      ++run;
    }
    if (run > 0u) atomicAdd(groupSelected[runLevel], run);
    scan[lane] = count;
    uint sum = scanWorkgroup();
    rank[gl_GlobalInvocationID.x] = (scan[lane] << 16) | mask;
    if (lane == 0u) blocks[gl_WorkGroupID.x] = sum;
    if (countSelection != 0 && lane < 8u && groupSelected[lane] > 0u) atomicAdd(selected[lane], groupSelected[lane]);
  } else if (pass == 1) {
    uint count = uint((total + kInvocations * kChunk - 1) / (kInvocations * kChunk)), carry = 0u;  // pass 0's workgroups
    for (uint base = 0u; base < count; base += uint(kInvocations)) {
      uint b = base + lane;
      uint v = b < count ? blocks[b] : 0u;
      scan[lane] = v;
      uint sum = scanWorkgroup();
      if (b < count) blocks[b] = carry + scan[lane];
      carry += sum;
      barrier();  // every lane has read scan[] before the next chunk writes it
    }
    if (lane == 0u) {
      command[0] = carry;
      command[1] = 1u;
      command[2] = 0u;
      command[3] = 0u;
    }
  } else {
    if (first >= total) return;
    uint r = rank[gl_GlobalInvocationID.x];
    uint place = blocks[gl_WorkGroupID.x] + (r >> 16);
    for (uint mask = r & 0xFFFFu; mask != 0u; mask &= mask - 1u) samples[place++] = uint(first + findLSB(mask));
  }
}
