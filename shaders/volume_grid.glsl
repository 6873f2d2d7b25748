// Stormlight: look-ups on the volume's lattice, in coordinates relative to sample (0,0,0): the
// fields' extinction (trilinear, zero outside the box: sl__sample_fields) and the light volume
// (trilinear on ln I and n, then exp: light_volume.c). Manual trilinear from texelFetch, in
// the CPU's order of operations.
uniform sampler3D slFields;  // extinction per present field (RGBA = fields 0..3), m^-1
uniform sampler3D slFieldsHi; // fields 4..7 (one zero texel where there are four or fewer)
uniform sampler3D slLight;   // light state (ln I per wavelength, n), axes (a1, a2, sweep order)
uniform vec3 slSpacing;
uniform vec3 slGridN;        // samples along x, y, z
uniform vec3 slBoxLo, slBoxHi; // the lattice's box (half a spacing beyond the outer samples)
uniform vec3 slAxisE, slA1E, slA2E; // unit selectors: sweep axis and the two in-plane axes
uniform sampler3D slSky;     // the skylight's lattice (render/volume/sky_light.h): beta M per wavelength, beta
uniform vec3 slSkyOrigin, slSkySpacing, slSkyN; // its first sample (relative to slFields'), spacing, samples
uniform float slFirst, slStep;      // the sweep's first plane along its axis and its direction

void slLatticeCell(vec3 x, out ivec3 i, out ivec3 i1, out vec3 f)
{
  ivec3 n = ivec3(slGridN + 0.5);
  vec3 u = clamp(x / slSpacing, vec3(0.0), vec3(n - 1));
  i = clamp(ivec3(u), ivec3(0), max(n - 2, ivec3(0)));
  i1 = min(i + 1, n - 1);
  f = mix(vec3(0.0), min(u - vec3(i), vec3(1.0)), greaterThan(n, ivec3(1)));
}

// Trilinear interpolation of a float 3D texture between texels i and i1 at fractions f (texelFetch:
// hardware filtering would round the weights to 8 bits on most GPUs).
vec4 slTrilinear(sampler3D t, ivec3 i, ivec3 i1, vec3 f)
{
  vec4 c000 = texelFetch(t, ivec3(i.x, i.y, i.z), 0), c100 = texelFetch(t, ivec3(i1.x, i.y, i.z), 0);
  vec4 c010 = texelFetch(t, ivec3(i.x, i1.y, i.z), 0), c110 = texelFetch(t, ivec3(i1.x, i1.y, i.z), 0);
  vec4 c001 = texelFetch(t, ivec3(i.x, i.y, i1.z), 0), c101 = texelFetch(t, ivec3(i1.x, i.y, i1.z), 0);
  vec4 c011 = texelFetch(t, ivec3(i.x, i1.y, i1.z), 0), c111 = texelFetch(t, ivec3(i1.x, i1.y, i1.z), 0);
  vec4 c00 = c000 + f.x * (c100 - c000), c10 = c010 + f.x * (c110 - c010);
  vec4 c01 = c001 + f.x * (c101 - c001), c11 = c011 + f.x * (c111 - c011);
  vec4 c0 = c00 + f.y * (c10 - c00), c1 = c01 + f.y * (c11 - c01);
  return c0 + f.z * (c1 - c0);
}

bool slSampleFields(vec3 x, out float beta[SL_MAX_FIELDS])
{
  for (int j = 0; j < SL_MAX_FIELDS; ++j) beta[j] = 0.0;
  if (!(all(greaterThanEqual(x, slBoxLo)) && all(lessThanEqual(x, slBoxHi)))) return false;
  ivec3 i, i1;
  vec3 f;
  slLatticeCell(x, i, i1, f);
  vec4 v = slTrilinear(slFields, i, i1, f);
  beta[0] = v.r;
  if (slNf > 1) beta[1] = v.g;
  if (slNf > 2) beta[2] = v.b;
  if (slNf > 3) beta[3] = v.a;
  if (slNf > 4) {
    vec4 w = slTrilinear(slFieldsHi, i, i1, f);
    beta[4] = w.r;
    if (slNf > 5) beta[5] = w.g;
    if (slNf > 6) beta[6] = w.b;
    if (slNf > 7) beta[7] = w.a;
  }
  return true;
}

// The skylight's diffuse radiance M at x: trilinear on its lattice (clamped into it) weighted by the
// lattice's extinction, as sl__sky_light_at (render/volume/sky_light_gather.h).
vec3 slSampleSky(vec3 x)
{
  ivec3 n = ivec3(slSkyN + 0.5);
  vec3 u = clamp((x - slSkyOrigin) / slSkySpacing, vec3(0.0), vec3(n - 1));
  ivec3 i = clamp(ivec3(u), ivec3(0), max(n - 2, ivec3(0)));
  ivec3 i1 = min(i + 1, n - 1);
  vec3 f = mix(vec3(0.0), min(u - vec3(i), vec3(1.0)), greaterThan(n, ivec3(1)));
  vec4 v = slTrilinear(slSky, i, i1, f);
  return v.a > 0.0 ? v.rgb * (1.0 / v.a) : vec3(0.0);
}

// The light volume's texel of lattice sample g.
ivec3 slLightTexel(ivec3 g)
{
  vec3 gf = vec3(g);
  return ivec3(int(dot(gf, slA1E) + 0.5), int(dot(gf, slA2E) + 0.5), int((dot(gf, slAxisE) - slFirst) * slStep + 0.5));
}

// (I per wavelength relative to the sunlight above the volume, expected scattering count n).
vec4 slSampleLight(vec3 x)
{
  ivec3 i, i1;
  vec3 f;
  slLatticeCell(x, i, i1, f);
  vec4 acc = vec4(0.0);
  for (int c = 0; c < 8; ++c) {
    bvec3 up = bvec3((c & 1) != 0, (c & 2) != 0, (c & 4) != 0);
    ivec3 g = ivec3(up.x ? i1.x : i.x, up.y ? i1.y : i.y, up.z ? i1.z : i.z);
    vec3 w3 = mix(vec3(1.0) - f, f, up);
    acc += w3.x * w3.y * w3.z * texelFetch(slLight, slLightTexel(g), 0);
  }
  return vec4(exp(acc.rgb), acc.a);
}
