// Splatting: one vertex per irradiance texel (Shah et al. 2009, BRUTE).
uniform sampler2D irradiancePositionMaterial;
uniform sampler2D irradianceFluxFootprint;
uniform sampler2D irradianceNormalObject;
uniform int resolution;
out SplatSample {
  vec3 position;
  vec3 flux;
  float footprint;
  float object;
  int material;
} sampleOut;
void main() {
  ivec2 texel = ivec2(gl_VertexID % resolution, gl_VertexID / resolution);
  vec4 pm = texelFetch(irradiancePositionMaterial, texel, 0);
  vec4 ff = texelFetch(irradianceFluxFootprint, texel, 0);
  sampleOut.position = pm.xyz;
  sampleOut.material = int(pm.w);
  sampleOut.flux = ff.rgb;
  sampleOut.footprint = ff.a;
  sampleOut.object = texelFetch(irradianceNormalObject, texel, 0).w;
  gl_Position = vec4(0.0);
}
