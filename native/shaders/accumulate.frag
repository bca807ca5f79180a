// Splat accumulation (eq. 17): adds the accumulated exitance of level k + 1,
// upsampled with bilinear, depth and material weights, to level k. Pixels of
// another object get no weight (light does not scatter between objects).
// MATERIAL_EDIT's transport (transportLayers 8: transport_splat.frag) is gathered the same way,
// every layer of the coarse level's array with the same weights.
layout(binding = UNIT_COARSE_EXITANCE) uniform sampler2D coarseExitance;           // level k + 1, already accumulated
layout(binding = UNIT_COARSE_TRANSPORT) uniform sampler2DArray coarseTransport;   // transportLayers > 0
uniform int transportLayers;
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;  // the median-depth hierarchy
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
uniform int fineLevel;
uniform ivec2 coarseSize;
uniform vec3 cameraPosition;
uniform vec3 cameraForward;
uniform float lambdaZ, lambdaM;
uniform float boundingDiameter;  // R_w
layout(location = 0) out vec4 exitance[8];

// Eq. 17's material term uses R_P in millimetres, the unit the paper's profiles are measured
// in: a property of the materials, whatever the scene's unit or size (docs/HETEROGENEOUS.md).
float rangeMm(int m) { return materials[m].ranges.y * materials[m].ranges.w; }

// Coarse pixel c's weight for this pixel (at depth z, material m, on object po.w) is its bilinear
// weight times exp(-x), x = lambda_z |z - z_c| / R_w + lambda_m |R_P - R_P,c| (eq. 17); this is x,
// or -1 where c is on another object or not translucent (no weight).
float exponent(ivec2 c, vec4 po, int m, float z) {
  vec4 cpo = texelFetch(splattingPositionObject, c, fineLevel + 1);
  if (cpo.w != po.w) return -1.0;
  int cm = int(texelFetch(splattingNormalMaterial, c, fineLevel + 1).w);
  if (!isTranslucent(cm)) return -1.0;
  float cz = dot(cpo.xyz - cameraPosition, cameraForward);
  return lambdaZ * abs(z - cz) / boundingDiameter + lambdaM * abs(rangeMm(m) - rangeMm(cm));
}

// The candidates: the four bilinear neighbours of the pixel's centre in level k + 1 or, where none
// of them is on this object (a silhouette or thin part narrower than a coarse pixel), the 4 x 4
// ring around them by depth and material alone rather than dropping the coarse levels' light.
ivec2 candidate(ivec2 base, int i, bool ring) {
  ivec2 o = ring ? ivec2(i & 3, i >> 2) - 1 : ivec2(i & 1, i >> 1);
  return clamp(base + o, ivec2(0), coarseSize - 1);
}
float bilinear(vec2 f, int i, bool ring) {
  if (ring) return 1.0;
  return ((i & 1) == 1 ? f.x : 1.0 - f.x) * ((i >> 1) == 1 ? f.y : 1.0 - f.y);
}
float nearestExponent(ivec2 base, bool ring, vec4 po, int m, float z) {
  float nearest = -1.0;
  for (int i = 0; i < (ring ? 16 : 4); ++i) {
    float x = exponent(candidate(base, i, ring), po, m, z);
    if (x >= 0.0 && (nearest < 0.0 || x < nearest)) nearest = x;
  }
  return nearest;
}

vec4 sums[8];
void gather(ivec2 c, float w) {
  if (transportLayers == 0) {
    sums[0] += w * texelFetch(coarseExitance, c, 0);
    return;
  }
  for (int l = 0; l < transportLayers; ++l) sums[l] += w * texelFetch(coarseTransport, ivec3(c, l), 0);
}

// Eq. 17 normalizes the weights, so each is taken relative to the largest exp(-x) (the nearest
// candidate's), and one below a float's resolution of that (x - nearest > 24 ln 2) is none. As
// they stand the weights underflow where every neighbour's material is far from this pixel's
// (lambda_m = 8 per mm: 11 mm of R_P is e^-88, past the smallest normal float), and what a sum
// of denormals gives is the implementation's choice (GLSL lets it flush them or not): llvmpipe
// gave the same frame two answers from one process to the next (docs/ANIMATION.md,
// "Determinism across processes").
const float NEGLIGIBLE_EXPONENT = 24.0 * 0.6931472;

void main() {
  for (int l = 0; l < 8; ++l) sums[l] = vec4(0.0);
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 po = texelFetch(splattingPositionObject, p, fineLevel);
  if (po.w < 0.0) discard;
  int m = int(texelFetch(splattingNormalMaterial, p, fineLevel).w);
  if (!isTranslucent(m)) discard;
  float z = dot(po.xyz - cameraPosition, cameraForward);
  vec2 q = (vec2(p) + 0.5) * 0.5 - 0.5;  // this pixel's centre in level k + 1 pixels
  ivec2 base = ivec2(floor(q));
  vec2 f = q - vec2(base);
  bool ring = false;
  float nearest = nearestExponent(base, false, po, m, z);
  if (nearest < 0.0) {
    ring = true;
    nearest = nearestExponent(base, true, po, m, z);
    if (nearest < 0.0) discard;
  }
  float total = 0.0;
  for (int i = 0; i < (ring ? 16 : 4); ++i) {
    ivec2 c = candidate(base, i, ring);
    float x = exponent(c, po, m, z);
    if (x < 0.0 || x - nearest > NEGLIGIBLE_EXPONENT) continue;
    float w = bilinear(f, i, ring) * exp(nearest - x);
    gather(c, w);
    total += w;
  }
  // (alpha: the TABULATED model's exitance-weighted incidence cosine, gathered alike)
  for (int l = 0; l < max(transportLayers, 1); ++l) exitance[l] = sums[l] / total;
}
