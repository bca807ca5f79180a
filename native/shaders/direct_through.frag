// MATERIAL_EDIT (pipeline/shading.h: Shading::addKeptThrough): the direct light without what
// crosses thin parts, plus that light for the materials as they are now, from what each view kept
// of it before the slab's transmission (direct_lighting.frag with keptThrough: two layers a view,
// the entering light times the exit's factors and the tint with the thickness, then mu0, mu and 1
// where the view sent light through).
layout(binding = UNIT_DIRECT_RADIANCE) uniform sampler2D directRadiance;
layout(binding = UNIT_SPLATTING_NORMAL_MATERIAL) uniform sampler2D splattingNormalMaterial;
layout(binding = UNIT_KEPT_THROUGH) uniform sampler2DArray keptThrough;
uniform int views;
layout(location = 0) out vec4 radiance;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  radiance = texelFetch(directRadiance, pixel, 0);
  int m = int(texelFetch(splattingNormalMaterial, pixel, 0).w);
  if (m < 0 || !isTabulated(m)) return;
  vec3 through = vec3(0.0);
  for (int v = 0; v < views; ++v) {
    vec4 angles = texelFetch(keptThrough, ivec3(pixel, 2 * v + 1), 0);
    if (angles.z <= 0.0) continue;
    vec4 entering = texelFetch(keptThrough, ivec3(pixel, 2 * v), 0);
    through += entering.rgb * transmittedRadiance(m, entering.a * materials[m].extinction.rgb, angles.x, angles.y);
  }
  radiance.rgb += through;
}
