// The TABULATED model's incidence factor (material/transport_model.h) on the irradiance buffer's
// finest level, before its hierarchy is built: each texel's flux times R(tau, mu0) / R(1), with
// tau the slab's thickness there: the distance the light crosses (from the exit depth) times mu0,
// in mean free paths per channel, in the share of a slab the part is between the entry's and the
// exit's normals (slabLikeness); a half-space in the rest, and where the light leaves through
// another object, or nowhere.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = UNIT_IRRADIANCE_POSITION_MATERIAL) uniform sampler2D irradiancePositionMaterial;
layout(binding = UNIT_IRRADIANCE_NORMAL_OBJECT) uniform sampler2D irradianceNormalObject;
layout(binding = UNIT_IRRADIANCE_LIGHT_DEPTH) uniform sampler2D irradianceLightDepth;
layout(binding = UNIT_IRRADIANCE_EXIT_DEPTH) uniform sampler2D irradianceExitDepth;
layout(rgba32f, binding = IMAGE_FLUX_FOOTPRINT) uniform image2D fluxFootprint;
uniform int resolution;
void main() {
  ivec2 t = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(t, ivec2(resolution)))) return;
  vec4 pm = texelFetch(irradiancePositionMaterial, t, 0);
  int m = int(pm.w);
  if (pm.w < 0.0 || !isTabulated(m)) return;
  vec4 no = texelFetch(irradianceNormalObject, t, 0);
  float entry = texelFetch(irradianceLightDepth, t, 0).r;
  vec4 exit = texelFetch(irradianceExitDepth, t, 0);
  // The slab's thickness along its normal (the light crossed it at mu0), in the share of a slab the
  // part is between entry and exit; the half-space in the rest (transport_model.h). An exit not
  // beyond the entry (a back face that is itself the first surface: an open mesh seen from inside)
  // counts as a half-space (common.glsl: slabGeometry).
  float mu0 = clamp(dot(no.xyz, towardsLight(pm.xyz)), 0.0, 1.0);
  vec3 factor = incidenceFactorAt(m, slabGeometry(no, entry, exit, mu0), mu0);
  vec4 ff = imageLoad(fluxFootprint, t);
  imageStore(fluxFootprint, t, vec4(ff.rgb * factor, ff.a));
}
