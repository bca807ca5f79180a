// Shared by every subsplat shader (prepended after #version).
const float PI = 3.14159265358979;

// One entry per opaque or homogeneous material and per palette entry of a
// heterogeneous one (scene.h: MaterialEntry, MaterialGpu).
struct Material {
  vec4 baseColorKind;  // rgb diffuse albedo (opaque), w: 0 opaque, 1 translucent
  vec4 optics;         // eta, roughness, specular, kernel layer
  vec4 ranges;         // support radius, effective range R_P (max over rgb), R_P (min), mm per scene unit
  uvec4 profileMap;    // heterogeneous: offset into profileMaps, width, height (0: none); the material's first entry
  vec4 medium;         // TABULATED model: rgb single-scattering albedo, w its transport layer (-1: none)
  vec4 extinction;     // TABULATED model: rgb sigma_t per scene unit
  vec4 world;          // translucent: rgb the response to the unshadowed world (world_light.h)
  // Textures (material/texture.h): offset into textureTexels, width, height (0: none), extension |
  // interpolation << 2; the UV transform's two rows (xyz); normalU.w: the normal map's strength.
  uvec4 colorTexture;
  vec4 colorU, colorV;
  uvec4 normalTexture;
  vec4 normalU, normalV;
};
layout(std430, binding = STORAGE_MATERIALS) readonly buffer Materials { Material materials[]; };

bool isTranslucent(int m) { return m >= 0 && materials[m].baseColorKind.w > 0.5; }
bool isHoldout(int m) { return m >= 0 && materials[m].baseColorKind.w < -0.5; }
bool isTabulated(int m) { return m >= 0 && materials[m].medium.w >= 0.0; }

// The TABULATED model's tables (material/transport_model.h: TransportTables, the same layout and
// the same interpolation): row 0 H(mu) at t = k / 32; rows 1 .. nt the incidence factor
// R(tau, mu0) / R(1) over the mu0 index; then T(tau, mu0_i, mu) in rows 1 + nt + 8 tau + i.
layout(binding = UNIT_TRANSPORT_TABLES) uniform sampler2DArray transportTables;
uniform vec3 transportGrid;  // the first slab's thickness, ln of the grid's step, the thickest (mfp)
uniform int transportThicknesses;
const int TRANSPORT_COSINES = 8;
vec3 transportTexel(int m, int x, int y) {
  return texelFetch(transportTables, ivec3(x, y, int(materials[m].medium.w)), 0).rgb;
}
vec3 hFunction(int m, float mu) {
  float x = sqrt(clamp(mu, 0.0, 1.0)) * 32.0;
  int k = min(int(x), 31);
  return mix(transportTexel(m, k, 0), transportTexel(m, k + 1, 0), x - float(k));
}
float thicknessCoordinate(float tau) {
  if (tau <= transportGrid.x) return max(tau, 0.0) / transportGrid.x;
  return min(1.0 + log(tau / transportGrid.x) / transportGrid.y, float(transportThicknesses - 1));
}
float cosineCoordinate(float mu) {
  return clamp(sqrt(clamp(mu, 0.0, 1.0)) * float(TRANSPORT_COSINES) - 1.0, 0.0, float(TRANSPORT_COSINES - 1));
}
// R(tau, mu0) / R(1) per channel, tau in mean free paths (beyond the table: a half-space).
vec3 incidenceFactor(int m, vec3 tau, float mu0) {
  vec3 a = materials[m].medium.rgb, root = sqrt(max(1.0 - a, 0.0));
  vec3 halfSpace = (1.0 - root * hFunction(m, mu0)) / max(1.0 - root * hFunction(m, 1.0), 1e-30);
  float v = cosineCoordinate(mu0);
  int i = min(int(v), TRANSPORT_COSINES - 2);
  float fv = v - float(i);
  vec3 result;
  for (int c = 0; c < 3; ++c) {
    if (!(tau[c] < transportGrid.z)) { result[c] = halfSpace[c]; continue; }
    float u = thicknessCoordinate(tau[c]);
    int k = min(int(u), transportThicknesses - 2);
    float fu = u - float(k);
    float lo = mix(transportTexel(m, i, 1 + k)[c], transportTexel(m, i + 1, 1 + k)[c], fv);
    float hi = mix(transportTexel(m, i, 2 + k)[c], transportTexel(m, i + 1, 2 + k)[c], fv);
    result[c] = mix(lo, hi, fu);
  }
  return mix(result, vec3(0.0), lessThanEqual(a, vec3(0.0)));
}
// The mean distance along a beam entering at mu0 (mean free paths) of the first collision of the
// light the half-space reflects, per channel: 1 + mu0 R'(mu0) / R(mu0) (TransportTables::
// beamCentroid, the same samples and the same interpolation).
float hSlope(int m, int j, int c) {  // dH/dt at sample j of channel c, t = sqrt(mu)
  if (j == 0) return (-3.0 * transportTexel(m, 0, 0)[c] + 4.0 * transportTexel(m, 1, 0)[c] - transportTexel(m, 2, 0)[c]) * 16.0;
  if (j == 32) return (3.0 * transportTexel(m, 32, 0)[c] - 4.0 * transportTexel(m, 31, 0)[c] + transportTexel(m, 30, 0)[c]) * 16.0;
  return (transportTexel(m, j + 1, 0)[c] - transportTexel(m, j - 1, 0)[c]) * 16.0;
}
vec3 beamCentroid(int m, float mu0) {
  vec3 a = materials[m].medium.rgb, root = sqrt(max(1.0 - a, 0.0));
  float t = sqrt(clamp(mu0, 0.0, 1.0)), x = t * 32.0;
  int k = min(int(x), 31);
  float f = x - float(k);
  vec3 r = 1.0 - root * hFunction(m, mu0);
  vec3 s;
  for (int c = 0; c < 3; ++c) {
    float slope = mix(hSlope(m, k, c), hSlope(m, k + 1, c), f);
    s[c] = a[c] > 0.0 && r[c] > 0.0 ? 1.0 - root[c] * 0.5 * t * slope / r[c] : 1.0;
  }
  return s;
}
// X(mu0, mu): the exit radiance over the Lambertian's, for light that entered at mean cosine mu0.
vec3 exitFactor(int m, float mu0, float mu) {
  vec3 a = materials[m].medium.rgb, root = sqrt(max(1.0 - a, 0.0));
  mu0 = clamp(mu0, 1e-3, 1.0);
  vec3 h0 = hFunction(m, mu0);
  vec3 r = 1.0 - root * h0;
  vec3 x = a * h0 * hFunction(m, mu) / (4.0 * (mu0 + clamp(mu, 0.0, 1.0)) * max(r, 1e-30));
  return mix(x, vec3(1.0), lessThanEqual(r, vec3(0.0)));
}
// T(tau, mu0, mu) per channel: radiance scattered through a slab per unit irradiance, 1/sr.
vec3 transmittedRadiance(int m, vec3 tau, float mu0, float mu) {
  float v0 = cosineCoordinate(mu0), v = cosineCoordinate(mu);
  int i = min(int(v0), TRANSPORT_COSINES - 2), j = min(int(v), TRANSPORT_COSINES - 2);
  float f0 = v0 - float(i), fm = v - float(j);
  vec3 result = vec3(0.0);
  for (int c = 0; c < 3; ++c) {
    if (!(tau[c] < transportGrid.z) || !(tau[c] > 0.0)) continue;
    float u = thicknessCoordinate(tau[c]);
    int k = min(int(u), transportThicknesses - 2);
    float fu = u - float(k);
    // Linear in mu at the four (thickness, mu0) nodes, then between them in ln T, as the CPU.
    float logSum = 0.0, linear = 0.0;
    bool positive = true;
    for (int n = 0; n < 4; ++n) {
      int dk = n >> 1, di = n & 1;
      int row = 1 + transportThicknesses + (k + dk) * TRANSPORT_COSINES + i + di;
      float v = mix(transportTexel(m, j, row)[c], transportTexel(m, j + 1, row)[c], fm);
      float w = (dk == 1 ? fu : 1.0 - fu) * (di == 1 ? f0 : 1.0 - f0);
      positive = positive && v > 0.0;
      logSum += w * log(max(v, 1e-30));
      linear += w * v;
    }
    result[c] = positive ? exp(logSum) : linear;
  }
  return result;
}
// The share of the light entering at normal ni that the splatting carries to normal no
// (transport_model.h: sideWeight), and how much of a slab the part between an entry and an exit
// normal is (slabLikeness).
float sideWeight(float cosine) { return smoothstep(0.0, 1.0, cosine + 0.5); }
float slabLikeness(float cosine) { return 1.0 - sideWeight(cosine); }
// A unit vector in two numbers and back (octahedral mapping).
vec2 octEncode(vec3 n) {
  n /= abs(n.x) + abs(n.y) + abs(n.z);
  vec2 e = n.xy;
  if (n.z < 0.0) e = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return e;
}
vec3 octDecode(vec2 e) {
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return normalize(n);
}
// Where light entered an irradiance texel of normal and object `no` at depth `entry` along the light
// and left at `exit` (the exit-depth pass: depth, object, octahedral normal): the part's slab
// thickness along its normal (the distance crossed times mu0, scene units) and the share of a slab
// it is (slabLikeness of the two normals; 0 where the light leaves through another object, or
// nowhere, or the exit is not beyond the entry by more than float depths resolve).
vec2 slabGeometry(vec4 no, float entry, vec4 exit, float mu0) {
  bool through = exit.g == no.w && exit.r - entry > 1e-5 * max(abs(entry), 1e-3);
  if (!through) return vec2(0.0);
  return vec2((exit.r - entry) * mu0, slabLikeness(dot(no.xyz, octDecode(exit.ba))));
}
// The incidence factor of a part of slab geometry g (slabGeometry: thickness along the normal in
// scene units, share of a slab): the slab's in that share, the half-space's in the rest.
vec3 incidenceFactorAt(int m, vec2 g, float mu0) {
  vec3 halfSpace = incidenceFactor(m, vec3(1e30), mu0);
  return g.y > 0.0 ? mix(halfSpace, incidenceFactor(m, g.x * materials[m].extinction.rgb, mu0), g.y) : halfSpace;
}

// The entry of a surface point of material m (its first entry) at texture
// coordinate uv: the nearest texel of the material's profile map, repeating.
layout(binding = UNIT_PROFILE_MAPS) uniform usamplerBuffer profileMaps;
// What a program's variant leaves out (gl::makeProgram's defines; pipeline/pass_helpers.h:
// sceneVariant): TEXTURES 0 where no material reads a texture (Scene::textured), PROFILE_MAPS 0
// where no material has a SubEdit map (Scene::heterogeneous). Without them, everything is in.
#ifndef TEXTURES
#define TEXTURES 1
#endif
#ifndef PROFILE_MAPS
#define PROFILE_MAPS 1
#endif
int profileEntry(int m, vec2 uv, bool hasUv) {
#if !PROFILE_MAPS
  return m;
#endif
  if (m < 0) return m;
  uvec4 map = materials[m].profileMap;
  if (map.y == 0u || !hasUv) return m;
  ivec2 size = ivec2(map.yz);
  ivec2 t = clamp(ivec2(floor(fract(uv) * vec2(size))), ivec2(0), size - 1);
  return m + int(texelFetch(profileMaps, int(map.x) + t.y * size.x + t.x).r);
}

// Textures (material/texture.h: Texture::sample, the same look-up): every image's texels in a row.
layout(binding = UNIT_TEXTURE_TEXELS) uniform samplerBuffer textureTexels;
vec3 textureTexel(uvec4 t, int x, int y) {
  int w = int(t.y), h = int(t.z), extension = int(t.w & 3u);
  if (extension == 0) {  // REPEAT: x in [-1, w] here
    x = x < 0 ? x + w : x >= w ? x - w : x;
    y = y < 0 ? y + h : y >= h ? y - h : y;
  } else if (extension == 1) {
    x = clamp(x, 0, w - 1), y = clamp(y, 0, h - 1);
  } else if (x < 0 || x >= w || y < 0 || y >= h) {
    return vec3(0.0);
  }
  return texelFetch(textureTexels, int(t.x) + y * w + x).rgb;
}
vec3 sampleTexture(uvec4 t, vec4 rowU, vec4 rowV, vec2 uv) {
  if (t.y == 0u) return vec3(1.0);
  vec2 m = vec2(dot(rowU.xyz, vec3(uv, 1.0)), dot(rowV.xyz, vec3(uv, 1.0)));
  int extension = int(t.w & 3u);
  if (extension == 2 && (any(lessThan(m, vec2(0.0))) || any(greaterThan(m, vec2(1.0))))) return vec3(0.0);
  if (extension == 0) m -= floor(m);
  m = clamp(m, vec2(-1.0), vec2(2.0));
  vec2 size = vec2(t.yz);
  if ((t.w & 4u) != 0u) return textureTexel(t, int(floor(m.x * size.x)), int(floor(m.y * size.y)));
  vec2 x = m * size - 0.5;
  ivec2 i = ivec2(floor(x));
  vec2 f = x - vec2(i);
  return mix(mix(textureTexel(t, i.x, i.y), textureTexel(t, i.x + 1, i.y), f.x),
             mix(textureTexel(t, i.x, i.y + 1), textureTexel(t, i.x + 1, i.y + 1), f.x), f.y);
}
// The colour texture of material m at uv (1 without one): opaque albedo, translucent tint.
vec3 materialColor(int m, vec2 uv) {
#if !TEXTURES
  return vec3(1.0);
#endif
  if (m < 0) return vec3(1.0);
  return sampleTexture(materials[m].colorTexture, materials[m].colorU, materials[m].colorV, uv);
}
// The shading normal of material m (material/texture.h: perturbedNormal) from the surface's
// position and UV derivatives across the pixel (the triangle's tangent frame).
vec3 mappedNormal(int m, vec3 n, vec2 uv, vec3 dpdx, vec3 dpdy, vec2 duvdx, vec2 duvdy) {
#if !TEXTURES
  return n;
#endif
  if (m < 0 || materials[m].normalTexture.y == 0u) return n;
  float det = duvdx.x * duvdy.y - duvdy.x * duvdx.y;
  if (det == 0.0) return n;
  vec3 tangent = (dpdx * duvdy.y - dpdy * duvdx.y) / det;
  vec3 bitangent = (dpdy * duvdx.x - dpdx * duvdy.x) / det;
  vec3 t = tangent - n * dot(n, tangent);
  if (!(dot(t, t) > 1e-20)) return n;
  t = normalize(t);
  vec3 b = cross(n, t);
  if (dot(b, bitangent) < 0.0) b = -b;
  vec3 c = sampleTexture(materials[m].normalTexture, materials[m].normalU, materials[m].normalV, uv) * 2.0 - 1.0;
  vec3 p = c.x * t + c.y * b + c.z * n;
  if (!(dot(p, p) > 1e-20)) return n;
  p = normalize(p);
  float strength = materials[m].normalU.w;
  if (strength != 1.0) {
    p = n + (p - n) * max(strength, 0.0);
    if (!(dot(p, p) > 1e-20)) return n;
    p = normalize(p);
  }
  return p;
}

// Unpolarised Fresnel transmittance into a dielectric of relative index eta.
float fresnelTransmittance(float eta, float cosTheta) {
  cosTheta = clamp(cosTheta, 0.0, 1.0);
  float sin2T = (1.0 - cosTheta * cosTheta) / (eta * eta);
  if (sin2T >= 1.0) return 0.0;
  float cosT = sqrt(1.0 - sin2T);
  float rs = (cosTheta - eta * cosT) / (cosTheta + eta * cosT);
  float rp = (eta * cosTheta - cosT) / (eta * cosTheta + cosT);
  return 1.0 - 0.5 * (rs * rs + rp * rp);
}

// One view of a light: what the irradiance buffer was rendered with.
uniform mat4 lightViewProj;
uniform vec3 lightPosition;   // point and spot
uniform vec3 lightDirection;  // direction the light travels (spot axis, sun)
uniform vec3 lightRadiant;    // colour x (intensity W/sr | sun irradiance W/m^2)
uniform int lightType;        // LIGHT_POINT, LIGHT_SPOT, LIGHT_SUN (gl/bindings.h)
uniform float lightCosHalfSpot, lightSpotSmooth;
// An area light (reference/lighting.h: areaCorners): its corners in the world (else 0 of them);
// lightRadiant is then its radiance, lightDirection the way it faces.
uniform int lightAreaCorners;
uniform vec3 lightAreaPolygon[16];

// Lambert's formula for a polygon of unit radiance over a surface at p of normal n, the polygon
// clipped to n's hemisphere; 0 behind the emitter (reference/lighting.cpp: polygonIrradiance).
// The clipped polygon's vertices are taken as they come, each closing the edge from the one
// before it and the last closing to the first (the sum in the same order as the CPU's). They are
// not kept in a local array: llvmpipe gives an array indexed at run time a cost in every fragment
// of every shader that has one, reached or not (docs/BENCHMARKS.md, "The irradiance pass on llvmpipe").
float polygonEdge(vec3 a, vec3 b, vec3 n) {
  if (length(a) < 1e-12 || length(b) < 1e-12) return 0.0;
  a = normalize(a), b = normalize(b);
  vec3 c = cross(a, b);
  float l = length(c);
  if (l < 1e-12) return 0.0;
  return acos(clamp(dot(a, b), -1.0, 1.0)) * dot(n, c / l);
}
void polygonVertex(vec3 v, vec3 n, inout vec3 first, inout vec3 previous, inout int count, inout float sum) {
  if (count == 0)
    first = v;
  else
    sum += polygonEdge(previous, v, n);
  previous = v;
  ++count;
}
float polygonIrradiance(vec3 p, vec3 n) {
  if (dot(p - lightAreaPolygon[0], lightDirection) <= 0.0) return 0.0;
  vec3 first = vec3(0.0), previous = vec3(0.0);
  int count = 0;
  float sum = 0.0;
  for (int i = 0; i < lightAreaCorners; ++i) {
    vec3 a = lightAreaPolygon[i] - p, b = lightAreaPolygon[(i + 1) % lightAreaCorners] - p;
    float da = dot(n, a), db = dot(n, b);
    if (da >= 0.0) polygonVertex(a, n, first, previous, count, sum);
    if ((da >= 0.0) != (db >= 0.0)) polygonVertex(a + (b - a) * (da / (da - db)), n, first, previous, count, sum);
  }
  if (count > 0) sum += polygonEdge(previous, first, n);
  return 0.5 * abs(sum);
}

// One of the world's shadowed directions (world_light.h): the whole set, for D(n); 0 otherwise.
uniform int worldDirectionCount;
uniform vec3 worldDirections[64];

// The irradiance at a surface of normal n over what a surface facing the light gets times
// max(0, n . L): pi / D(n) for a world direction, 1 for every other light.
float lightWeight(vec3 n) {
  if (worldDirectionCount == 0) return 1.0;
  float d = 0.0;
  for (int j = 0; j < worldDirectionCount; ++j) d += max(dot(n, worldDirections[j]), 0.0);
  return PI / max(d, 1e-3);
}

// Direction towards the light and the irradiance a surface facing it gets.
vec3 towardsLight(vec3 p) {
  return lightType == LIGHT_SUN ? -lightDirection : normalize(lightPosition - p);
}
// The TABULATED model's forward shift of the light entering at position p of normal n (facing the
// light, incidence cosine mu0): the refracted beam's direction along the surface (length
// sin theta_t) in xyz, and in `lengths` each channel's mean distance along the beam of its first
// collision (scene units); the reflected light is centred at p + along * lengths[c]
// (docs/TRANSPORT.md, "The entry's forward shift").
vec3 forwardShift(int m, vec3 p, vec3 n, float mu0, out vec3 lengths) {
  vec3 along = (-towardsLight(p) + mu0 * n) / materials[m].optics.x;
  float muT = sqrt(max(1.0 - min(dot(along, along), 1.0), 0.0));
  vec3 extinction = materials[m].extinction.rgb;
  lengths = mix(beamCentroid(m, muT) / max(extinction, vec3(1e-30)), vec3(0.0), lessThanEqual(extinction, vec3(0.0)));
  return along;
}
vec3 irradianceFacingLight(vec3 p) {
  if (lightType == LIGHT_SUN) return lightRadiant;
  vec3 d = lightPosition - p;
  vec3 e = lightRadiant / max(dot(d, d), 1e-20);
  if (lightType == LIGHT_SPOT) {
    // Cycles' spot attenuation (kernel/light/spot.h in 3.x): the cosine to
    // the axis, cut at the cone and smoothed over the blend region.
    float c = dot(-normalize(d), lightDirection);
    float attenuation = c <= lightCosHalfSpot ? 0.0 : c;
    float t = c - lightCosHalfSpot;
    if (attenuation > 0.0 && t < lightSpotSmooth && lightSpotSmooth > 0.0)
      attenuation *= smoothstep(0.0, 1.0, t / lightSpotSmooth);
    e *= attenuation;
  }
  return e;
}

// Soft shadows (docs/SOFT_SHADOWS.md): sun: the tangent of half its angle; point, spot: its radius,
// a disk facing the receiver; area: its own shape (lightSoftAxes, its semi-axes in the world; a
// rectangle or an ellipse); 0: hard. lightNearDepth: the least light depth in the view (the
// search's widest reach).
uniform float lightSoftSize;
uniform vec3 lightSoftAxes[2];
uniform int lightSoftRectangle;
uniform float lightNearDepth;
uniform float shadowTexelSize;  // world size of an irradiance-buffer texel at distance 1 (or absolute, sun)

// How far a penumbra reaches at a receiver at light depth `depth` behind a blocker at `blocker`, per
// unit of the light's extent (similar triangles; the sun's extent is already an angle's tangent).
float penumbraScale(float depth, float blocker) {
  return lightType == LIGHT_SUN ? depth - blocker : (depth - blocker) / max(blocker, 1e-6);
}
// Point k of n spread over the light's shape in its own unit coordinates: the unit square (an R2
// sequence) or the unit disk (a Vogel spiral); and the shape's norm (1 on its edge).
vec2 shapePoint(int k, int n) {
  if (lightSoftRectangle != 0) return fract(vec2(0.7548776662, 0.5698402910) * float(k) + 0.5) * 2.0 - 1.0;
  float r = sqrt((float(k) + 0.5) / float(n)), phi = 2.39996323 * float(k);
  return r * vec2(cos(phi), sin(phi));
}
float shapeNorm(vec2 x) { return lightSoftRectangle != 0 ? max(abs(x.x), abs(x.y)) : length(x); }

// The share of the light that reaches a receiver at light depth `depth` over the view's point
// `ndc`, percentage-closer soft shadows (Fernando 2005) over the light's own shape on a depth map
// of mapResolution texels (the shadow map for suns, the irradiance buffer's light depth for the
// others; docs/SOFT_SHADOWS.md): the blockers' mean depth, then the share of the penumbra's taps
// that do not block. texel: a map texel's world size at the receiver; slope: how fast the
// receiver's depth grows across the map per texel (its bias); p: the receiver. The taps reach at
// most 32 of the irradiance buffer's texels (maxReach map texels, resolution: the irradiance
// buffer's), whatever the map's resolution. ignoredObject >= 0: the map is a shadow map (g: the
// object index, shadow_depth.frag) and that object's own surfaces never block (the light entering
// a translucent object, irradiance_buffer.frag: its own shape shadows it through the depth test).
float softVisibility(sampler2D map, int mapResolution, int resolution, vec2 ndc, float depth, float texel, float slope,
                     vec3 p, float ignoredObject) {
  float maxReach = 32.0 * float(mapResolution) / float(resolution);
  // A blocker counts as in the cone up to one of the irradiance buffer's texels beyond it (the
  // allowance the cone test was made with; one texel of a finer map admits too few, and the
  // blockers' mean then falls back on the first look's, which counts parts of the occluder too far
  // to the side: an area light's penumbra 1.3 times Cycles' at 4 times the resolution).
  float coneAllowance = float(mapResolution) / float(resolution);
  vec2 centre = (ndc * 0.5 + 0.5) * float(mapResolution);
  // The light's extent as two world vectors, and their images in the map at p, in texels (the
  // penumbra is the light's shape scaled by penumbraScale; a perspective map's texels shrink off
  // its axis and stretch across a slope).
  vec3 A = lightSoftAxes[0], B = lightSoftAxes[1];
  if (dot(A, A) == 0.0) {
    vec3 L = towardsLight(p), u = normalize(cross(L, abs(L.z) < 0.9 ? vec3(0, 0, 1) : vec3(1, 0, 0)));
    A = u * lightSoftSize, B = cross(L, u) * lightSoftSize;
  }
  float h = 0.01 * (lightType == LIGHT_SUN ? texel * 100.0 : distance(p, lightPosition));
  vec4 c0 = lightViewProj * vec4(p, 1.0);
  vec4 ca = lightViewProj * vec4(p + A * (h / max(length(A), 1e-20)), 1.0);
  vec4 cb = lightViewProj * vec4(p + B * (h / max(length(B), 1e-20)), 1.0);
  float toTexels = 0.5 * float(mapResolution);
  vec2 ja = (ca.xy / ca.w - c0.xy / c0.w) * toTexels * (length(A) / h);
  vec2 jb = (cb.xy / cb.w - c0.xy / c0.w) * toTexels * (length(B) / h);
  float reach = max(max(length(ja), length(jb)), 1e-6);  // texels per unit of penumbraScale
  // The blockers' mean depth: first over the widest penumbra (the nearest depth in the view), then
  // again over the penumbra of that mean, counting only the blockers that lie in the cone from the
  // receiver to the light (at a blocker's depth the cone is the light's shape scaled by
  // penumbraScale(depth, stored)), so that parts of an occluder too far to the side to hide the
  // light do not count.
  float scale = clamp(penumbraScale(depth, lightNearDepth), 1.0 / reach, maxReach / reach);
  float blockerDepth = 0.0;
  for (int pass = 0; pass < 2; ++pass) {
    float blockers = 0.0, sum = 0.0;
    for (int k = 0; k < 16; ++k) {
      vec2 x = shapePoint(k, 16), offset = scale * (x.x * ja + x.y * jb);
      ivec2 t = clamp(ivec2(centre + offset), ivec2(0), ivec2(mapResolution - 1));
      vec2 stored2 = texelFetch(map, t, 0).rg;
      float stored = stored2.r;
      if (stored < depth - 2.0 * texel - slope * length(offset) * texel && stored2.g != ignoredObject &&
          (pass == 0 || shapeNorm(x) * scale <= penumbraScale(depth, stored) + coneAllowance / reach))
        blockers += 1.0, sum += stored;
    }
    if (blockers == 0.0) {
      if (pass == 0) return 1.0;
      break;  // the second look found none in the cone: keep the first's
    }
    blockerDepth = sum / blockers;
    scale = clamp(penumbraScale(depth, blockerDepth), 1.0 / reach, maxReach / reach);
  }
  float width = clamp(penumbraScale(depth, blockerDepth), 0.5 / reach, maxReach / reach);
  float lit = 0.0;
  for (int k = 0; k < 32; ++k) {
    vec2 x = shapePoint(k, 32), offset = width * (x.x * ja + x.y * jb);
    ivec2 t = clamp(ivec2(centre + offset), ivec2(0), ivec2(mapResolution - 1));
    vec2 stored = texelFetch(map, t, 0).rg;
    if (depth <= stored.r + 2.0 * texel + slope * length(offset) * texel || stored.g == ignoredObject) lit += 1.0;
  }
  return lit / 32.0;
}

float lightDepthOf(vec3 x) { return lightType == LIGHT_SUN ? dot(x, lightDirection) : distance(x, lightPosition); }

// softVisibility for a receiver p of geometric normal n (nl: its cosine to the light) on a map of
// mapResolution texels, the receiver pushed 1.5 of the map's texels along n and the bias counted in
// them (resolution: the irradiance buffer's, whose texel shadowTexelSize gives).
float softVisibilityAt(sampler2D map, int mapResolution, int resolution, vec3 p, vec3 n, float nl, float ignoredObject) {
  float texel = (lightType == LIGHT_SUN ? shadowTexelSize : shadowTexelSize * distance(p, lightPosition)) *
                float(resolution) / float(mapResolution);
  vec3 offset = p + n * (1.5 * texel);
  vec4 c = lightViewProj * vec4(offset, 1.0);
  float slope = min(sqrt(max(1.0 - nl * nl, 0.0)) / max(nl, 1e-3), 8.0);
  return softVisibility(map, mapResolution, resolution, c.xy / c.w, lightDepthOf(offset), texel, slope, p,
                        ignoredObject);
}
// The interval of dot(dir, ndc) over the screen image of the sphere of `radius` around view-space
// point c: the two planes through the eye tangent to the sphere whose screen lines are normal to dir
// (a dir . ndc = h line is the plane (A - h W) . (p, 1) = 0, A = dir's rows of viewToClip, W its w row;
// tangent where (alpha - h beta)^2 = r^2 |A - h W|^2, alpha and beta the centre's A and W values),
// the discriminant written without cancellation. False where part of the sphere is at or behind
// the eye's plane (perspective), where no such line bounds it.
bool sphereScreenInterval(vec3 c, float radius, mat4 viewToClip, vec2 dir, out vec2 interval) {
  vec4 a = dir.x * vec4(viewToClip[0][0], viewToClip[1][0], viewToClip[2][0], viewToClip[3][0]) +
           dir.y * vec4(viewToClip[0][1], viewToClip[1][1], viewToClip[2][1], viewToClip[3][1]);
  vec4 w = vec4(viewToClip[0][3], viewToClip[1][3], viewToClip[2][3], viewToClip[3][3]);
  float alpha = dot(a, vec4(c, 1.0)), beta = dot(w, vec4(c, 1.0));
  float r2 = radius * radius;
  float qa = beta * beta - r2 * dot(w.xyz, w.xyz);
  if (beta - radius * length(w.xyz) <= 1e-6 * max(beta, 1e-6) || qa <= 0.0) return false;
  vec3 across = cross(a.xyz, w.xyz);
  float root = radius * sqrt(max(dot(beta * a.xyz - alpha * w.xyz, beta * a.xyz - alpha * w.xyz) -
                                 r2 * dot(across, across), 0.0));
  float qb = alpha * beta - r2 * dot(a.xyz, w.xyz);
  interval = vec2(qb - root, qb + root) / qa;
  return true;
}
// The screen rectangle (NDC, clipped) bounding the sphere of `radius` around view-space point c:
// its silhouette's extent in x and in y (sphereScreenInterval; the whole screen where part of the
// sphere is at or behind the eye's plane), widened by `margin` (NDC) on each side. False where
// nothing of it is on screen. The splats' quads (splat.geom, transport_splat.geom), whose margin is
// half a pixel of a coarse splatting level: a coarse pixel holds one of its fine pixels' surface
// points (splatting_reduce.comp), up to half a pixel from its centre. Until stop 45 the rectangle
// bounded the projections of the sphere's view-space box's corners, which under perspective reach
// beyond the silhouette: docs/SPLATTING.md, "Quads that fit the sphere".
bool splatQuad(vec3 c, float radius, mat4 viewToClip, vec2 margin, out vec2 lo, out vec2 hi) {
  float r = radius * 1.001;  // for the rounding of the lines against the rasteriser's
  vec2 x, y;
  if (!sphereScreenInterval(c, r, viewToClip, vec2(1.0, 0.0), x) ||
      !sphereScreenInterval(c, r, viewToClip, vec2(0.0, 1.0), y))
    x = y = vec2(-1.0, 1.0);
  lo = max(vec2(x.x, y.x) - margin, vec2(-1.0));
  hi = min(vec2(x.y, y.y) + margin, vec2(1.0));
  return !any(greaterThanEqual(lo, hi));
}
// The depth (over depthFar, splat_depth.frag's) of the far side of the sphere of radius `radius`
// around view-space point c, where a splat's quad lies for the depth test (pipeline/splat_depth.h).
// Every surface point within the sphere is nearer than -c.z + radius; the margins cover the
// rounding of this depth and of the stored one.
float splatFarDepth(vec3 c, float radius, float depthFar) {
  return clamp((-c.z + radius * 1.001) / depthFar + 1e-6, 0.0, 1.0);
}
// A splat kernel table's value (material/splat_kernel.h) for a profile of support `support` in
// layer `layer` at distance d, for a footprint sigma (splat.frag's kernelAt; transport_splat.frag),
// in two parts: what does not depend on d, (row, scale, reach), once a splat (kernelFootprint:
// transport_splat.geom), then the lookup at d (kernelLookupAt). Past the table's widest footprint
// the kernel is self-similar: the widest row at d scaled down, times the scale squared. tableSize:
// (distance samples, footprint samples); log2Range: the rows' log2(sigma / support) at first and
// last; reachFactor: the footprint's cut, x sigma.
vec3 kernelFootprint(vec2 log2Range, float reachFactor, float support, float sigma) {
  float row = clamp((log2(sigma / support) - log2Range.x) / (log2Range.y - log2Range.x), 0.0, 1.0);
  float sigmaMax = support * exp2(log2Range.y);
  float scale = sigma > sigmaMax ? sigmaMax / sigma : 1.0;
  float reach = reachFactor * sigma * scale + support;
  return vec3(row, scale, reach);
}
vec3 kernelLookupAt(sampler2DArray table, vec2 tableSize, float layer, vec3 footprint, float d) {
  vec2 uv = (vec2(sqrt(min(d * footprint.y / footprint.z, 1.0)), footprint.x) * (tableSize - 1.0) + 0.5) / tableSize;
  return texture(table, vec3(uv, layer)).rgb * (footprint.y * footprint.y);
}
