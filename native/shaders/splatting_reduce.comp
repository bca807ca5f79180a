// Splatting buffer hierarchy (paper sec. 4, step 1): each coarse pixel takes
// the surface point of the child with the median view depth of its 2 x 2
// children (the lower median of the surface children), so coarse pixels lie on
// real surfaces and sharp features survive, unlike an average.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = UNIT_FINE_POSITION_OBJECT) uniform sampler2D finePositionObject;
layout(binding = UNIT_FINE_NORMAL_MATERIAL) uniform sampler2D fineNormalMaterial;
uniform int fineLevel;
uniform ivec2 fineSize, coarseSize;
uniform vec3 cameraPosition;
uniform vec3 cameraForward;
layout(rgba32f, binding = IMAGE_COARSE_POSITION_OBJECT) writeonly uniform image2D coarsePositionObject;
layout(rgba32f, binding = IMAGE_COARSE_NORMAL_MATERIAL) writeonly uniform image2D coarseNormalMaterial;
void main() {
  ivec2 c = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(c, coarseSize))) return;
  ivec2 child[4];
  float depth[4];
  int count = 0;
  for (int i = 0; i < 4; ++i) {
    ivec2 f = min(2 * c + ivec2(i & 1, i >> 1), fineSize - 1);
    vec4 po = texelFetch(finePositionObject, f, fineLevel);
    if (po.w < 0.0) continue;
    // Insertion by depth along the view axis.
    float d = dot(po.xyz - cameraPosition, cameraForward);
    int j = count++;
    while (j > 0 && depth[j - 1] > d) {
      depth[j] = depth[j - 1];
      child[j] = child[j - 1];
      --j;
    }
    depth[j] = d;
    child[j] = f;
  }
  if (count == 0) {
    imageStore(coarsePositionObject, c, vec4(0.0, 0.0, 0.0, -1.0));
    imageStore(coarseNormalMaterial, c, vec4(0.0, 0.0, 1.0, -1.0));
    return;
  }
  ivec2 m = child[(count - 1) / 2];
  imageStore(coarsePositionObject, c, texelFetch(finePositionObject, m, fineLevel));
  imageStore(coarseNormalMaterial, c, texelFetch(fineNormalMaterial, m, fineLevel));
}
