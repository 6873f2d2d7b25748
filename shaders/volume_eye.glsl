//VTK::System::Dec
// Stormlight: the eye pass over the light volume (render/volume/light_volume.c's ray march on the
// GPU): slMarchSamples (1 by default) samples per grid cell along each pixel's ray through the
// content box, thick steps in parts fixed in optical depth, the closed-form gather of eq. 26 over
// each, front-to-back. Writes the accumulator
// that shaders/volume_resolve.glsl (or the CPU) resolves: radiance per wavelength and the
// transparency, then the opacity-weighted depth numerator.
//SL::Physics
//SL::ViewRay
uniform vec3 slSun;            // unit vector toward the sun
uniform float slAngleInvStep;  // the Ams tables' angular grid
uniform int slAngles;
uniform sampler2D slSunlight;  // sunlight at altitudes slSunZ0 + i slSunDz, i < 257
uniform float slSunZ0, slSunDz;
uniform vec3 slOrigin;         // world position of the lattice's sample (0,0,0)
uniform float slGroundRadius;  // 0: altitude is world z; R: above the sphere centred at (0,0,-R)
uniform float slTermination;
uniform float slMarchSamples;  // eye samples per grid cell (light_volume.c's march_samples)
uniform sampler2D slOpaque;    // distance along each pixel's ray to the terrain or the round earth (rows from the top)
uniform int slSkylight;        // 1: add the skylight (slSampleSky, sl_sky_step_light)
in vec2 texCoord; // unused (pixels come from gl_FragCoord); read once so VTK's quad keeps the attribute
//VTK::Output::Dec

// sl_sky_altitude (render/sky): r - R as (x^2 + y^2 + z (z + 2R)) / (r + R), no cancellation.
float slAltitude(vec3 x)
{
  vec3 w = x + slOrigin;
  if (!(slGroundRadius > 0.0)) return w.z;
  float R = slGroundRadius;
  return (w.x * w.x + w.y * w.y + w.z * (w.z + 2.0 * R)) / (length(vec3(w.xy, w.z + R)) + R);
}

vec3 slSunlightAt(vec3 x)
{
  float z = slAltitude(x);
  float u = slSunDz > 0.0 ? (z - slSunZ0) / slSunDz : 0.0;
  u = clamp(u, 0.0, 256.0);
  int i = min(int(u), 255);
  float f = u - float(i);
  vec3 a = texelFetch(slSunlight, ivec2(i, 0), 0).rgb, b = texelFetch(slSunlight, ivec2(i + 1, 0), 0).rgb;
  return a + f * (b - a);
}

// One segment [ta, te] of the ray with fields beta (total b) into the pixel's sums, front to back:
// the light at its ends (the start shared with the segment before where it ends there), eq. 26's
// closed-form gather, the skylight, the depth numerator and the transparency.
void slMarchSegment(vec3 d, float ta, float te, float beta[SL_MAX_FIELDS], float b, int angleIndex,
                    float angleWeight, inout vec4 lPrev, inout float tPrev, inout vec3 radiance, inout float T,
                    inout float depth)
{
  vec4 l0 = ta == tPrev ? lPrev : slSampleLight(slEye + ta * d);
  vec4 l1 = slSampleLight(slEye + te * d);
  float dt = te - ta, tm = ta + 0.5 * dt;
  vec3 x = slEye + tm * d;
  float phase[SL_MAX_WAVELENGTHS], moments[2];
  sl_eye_phase_at(beta, 0.5 * (l0.a + l1.a), angleIndex, angleWeight, phase);
  float opacity = sl_step_opacity(b, dt);
  sl_segment_scatter_moments_exp(b, dt, 1.0, 1.0 - opacity, moments);
  vec3 sun = slSunlightAt(x);
  for (int c = 0; c < 3; ++c)
    radiance[c] += T * sl_march_step_light(l0[c], l1[c], moments[0], moments[1], phase[c], 1.0 / b) * sun[c];
  if (slSkylight != 0) {
    vec3 sky = slSampleSky(x);
    for (int c = 0; c < 3; ++c) radiance[c] += T * sl_sky_step_light(beta, c, opacity, 1.0 / b, sky[c]);
  }
  depth += T * opacity * tm * dot(d, slFwd);
  T *= 1.0 - opacity;
  lPrev = l1;
  tPrev = te;
}

// The fields at x and their total.
float slFieldsTotal(vec3 x, out float beta[SL_MAX_FIELDS])
{
  slSampleFields(x, beta);
  float b = 0.0;
  for (int j = 0; j < SL_MAX_FIELDS; ++j) b += beta[j];
  return b;
}

void main()
{
  if (texCoord.x < -1.0) discard;
  float px = floor(gl_FragCoord.x), py = slSize.y - 1.0 - floor(gl_FragCoord.y); // rows from the top
  vec3 d = slPixelRay(px, py);
  vec3 radiance = vec3(0.0);
  float T = 1.0, depth = 0.0;
  float t0, t1;
  bool hit = slContentSpan(d, t0, t1);
  t1 = min(t1, texelFetch(slOpaque, ivec2(int(px), int(py)), 0).r);
  hit = hit && t1 > t0 && t1 > 0.0;
  t0 = max(t0, 0.0);
  if (hit) {
    int angleIndex = 0;
    float angleWeight = 0.0;
    if (slMode != SL_MODE_LOW_ALBEDO && slNf > 0) {
      float u = sl_angle_grid_position(length(cross(slSun, d)), dot(slSun, d), slAngleInvStep);
      angleIndex = sl_angle_row(u, slAngles);
      angleWeight = sl_angle_weight(u, angleIndex);
    }
    float step = sl_march_max_step(slSpacing, d, slMarchSamples);
    int nsteps = sl_march_steps(t1 - t0, step);
    float tPrev = -1.0;
    vec4 lPrev = vec4(0.0);
    // Each step's fields at its middle, read one step ahead: a step is taken in parts fixed in
    // optical depth (sl_segment_parts, as the CPU's march_batch_steps) where its optical depth or
    // the next step's is SL_PART_THIN or more and the transparency is still SL_PART_DEEP or more.
    float beta[SL_MAX_FIELDS], betaNext[SL_MAX_FIELDS];
    float tb = sl_march_step_end(t0, step, t1, 1, nsteps);
    float bNext = slFieldsTotal(slEye + (t0 + 0.5 * (tb - t0)) * d, betaNext);
    for (int s = 0; s < nsteps && T >= slTermination; ++s) {
      float ta = t0 + float(s) * step;
      tb = sl_march_step_end(t0, step, t1, s + 1, nsteps);
      float dt = tb - ta;
      for (int j = 0; j < SL_MAX_FIELDS; ++j) beta[j] = betaNext[j];
      float b = bNext, depthHere = b * dt;
      float depthNext = 0.0;
      if (s + 1 < nsteps) {
        float tc = sl_march_step_end(t0, step, t1, s + 2, nsteps);
        bNext = slFieldsTotal(slEye + (tb + 0.5 * (tc - tb)) * d, betaNext);
        depthNext = bNext * (tc - tb);
      }
      bool thick = T >= SL_PART_DEEP && (depthHere >= SL_PART_THIN || depthNext >= SL_PART_THIN);
      if (!thick) {
        if (b > 0.0) slMarchSegment(d, ta, tb, beta, b, angleIndex, angleWeight, lPrev, tPrev, radiance, T, depth);
        continue;
      }
      float pstep = dt / float(SL_PART_PROFILE);
      float stepBeta[SL_PART_PROFILE], tau[SL_PART_PROFILE + 1];
      float profile[SL_MAX_FIELDS];
      tau[0] = 0.0;
      for (int k = 0; k < SL_PART_PROFILE; ++k) {
        stepBeta[k] = slFieldsTotal(slEye + (ta + (float(k) + 0.5) * pstep) * d, profile);
        tau[k + 1] = tau[k] + pstep * stepBeta[k];
      }
      if (!(tau[SL_PART_PROFILE] > 0.0)) continue;
      float tAt[SL_PARTS_MAX + 1], tauAt[SL_PARTS_MAX + 1];
      int parts = sl_segment_parts(tau, ta, pstep, tb, tAt, tauAt);
      for (int p = 0; p < parts; ++p) {
        float len = tAt[p + 1] - tAt[p];
        if (!(len > 0.0 && tauAt[p + 1] > tauAt[p])) continue;
        int kMix = sl_segment_part_mix_step(tau, stepBeta, 0.5 * (tauAt[p] + tauAt[p + 1]));
        float mixed = slFieldsTotal(slEye + (ta + (float(kMix) + 0.5) * pstep) * d, profile);
        if (!(mixed > 0.0)) continue;
        float mean = (tauAt[p + 1] - tauAt[p]) / len, scale = mean / mixed;
        for (int j = 0; j < SL_MAX_FIELDS; ++j) profile[j] *= scale;
        slMarchSegment(d, tAt[p], tAt[p + 1], profile, mean, angleIndex, angleWeight, lPrev, tPrev, radiance, T,
                       depth);
      }
    }
  }
  gl_FragData[0] = vec4(radiance, T);
  gl_FragData[1] = vec4(depth, 0.0, 0.0, 1.0);
}
