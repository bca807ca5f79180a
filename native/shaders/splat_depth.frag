// Each splatting level's depth (SplatDepth::prepare, pipeline/splat_depth.h): the view depth of the pixel's surface
// point over depthFar, 1 where no surface is. splat.geom puts each splat's quad at the far side of
// the sphere it bounds, and the depth test (GL_GEQUAL) skips the pixels whose surface lies beyond
// it: every one of them is farther from the sample than the splat reaches, so splat.frag would
// discard it. The splats that are drawn, and so the image, stay the same; the fragments the shader
// runs for become fewer (docs/SPLATTING.md, "Splats stop at their sphere's far side").
layout(binding = UNIT_SPLATTING_POSITION_OBJECT) uniform sampler2D splattingPositionObject;
uniform int splatLevel;
uniform mat4 worldToView;
uniform float depthFar;  // beyond every surface's view depth
void main() {
  vec4 po = texelFetch(splattingPositionObject, ivec2(gl_FragCoord.xy), splatLevel);
  if (po.w < 0.0) {
    gl_FragDepth = 1.0;
    return;
  }
  gl_FragDepth = clamp(-(worldToView * vec4(po.xyz, 1.0)).z / depthFar, 0.0, 1.0);
}
