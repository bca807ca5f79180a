// Anti-aliasing (docs/ANTIALIASING.md): the first sample's exitance at another sample's pixels.
// Exitance varies slowly along a surface (it is light spread by the profile), so a pixel's surface
// point takes it from where that point lies in the first sample's image: bilinearly from the four
// texels around it that show the same object near the same point, else from the nearest such
// texel within two pixels, else none (a sliver the first sample did not see).
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;  // this sample
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_FIRST_SAMPLE_POSITION_OBJECT) uniform sampler2D firstPositionObject;
layout(binding = UNIT_EXITANCE_BUFFER) uniform sampler2D exitanceBuffer;  // the first sample's
uniform mat4 firstViewProj;
uniform vec3 cameraPosition;
uniform vec3 cameraForward;
uniform int orthographic;
uniform float pixelSpread;  // a pixel's world size at distance 1 (orthographic: its size)
layout(location = 0) out vec4 exitance;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  exitance = vec4(0.0);
  vec4 po = texelFetch(splattingPositionObject, pixel, 0);
  if (po.w < 0.0) return;
  vec3 n = texelFetch(splattingNormalMaterial, pixel, 0).xyz;
  vec3 toCamera = orthographic != 0 ? -cameraForward : cameraPosition - po.xyz;
  float distanceHere = orthographic != 0 ? 1.0 : length(toCamera);
  // Neighbouring pixels' points on this surface lie this far apart, and a little more.
  float cosine = max(abs(dot(normalize(n), normalize(toCamera))), 0.1);
  float tolerance = 3.0 * pixelSpread * distanceHere / cosine;
  ivec2 size = textureSize(firstPositionObject, 0);
  vec4 clip = firstViewProj * vec4(po.xyz, 1.0);
  vec2 at = (clip.xy / clip.w * 0.5 + 0.5) * vec2(size) - 0.5;  // in texel centres
  ivec2 base = ivec2(floor(at));
  vec2 f = at - vec2(base);
  vec4 sum = vec4(0.0);
  float weight = 0.0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      ivec2 t = base + ivec2(i, j);
      if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, size))) continue;
      vec4 q = texelFetch(firstPositionObject, t, 0);
      if (q.w != po.w || distance(q.xyz, po.xyz) > tolerance) continue;
      float w = (i == 1 ? f.x : 1.0 - f.x) * (j == 1 ? f.y : 1.0 - f.y) + 1e-6;
      sum += w * texelFetch(exitanceBuffer, t, 0);
      weight += w;
    }
  if (weight > 0.0) {
    exitance = sum / weight;
    return;
  }
  float nearest = 1e30;
  ivec2 centre = ivec2(floor(at + 0.5));
  for (int j = -2; j <= 2; ++j)
    for (int i = -2; i <= 2; ++i) {
      ivec2 t = centre + ivec2(i, j);
      if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, size))) continue;
      vec4 q = texelFetch(firstPositionObject, t, 0);
      float d = distance(q.xyz, po.xyz);
      if (q.w != po.w || d >= nearest || d > 4.0 * tolerance) continue;
      nearest = d;
      exitance = texelFetch(exitanceBuffer, t, 0);
    }
}
