//VTK::System::Dec
// Stormlight: one plane of the light volume's sweep (render/volume/light_volume.c on the GPU).
// Each texel is a lattice sample of plane slPlaneK along the sun's dominant axis; it takes the
// light state where its sun ray crossed the previous plane (bilinear, blending toward fresh
// sunlight past the plane's edge samples) and applies one light step (eqs. 21, 24/25) over
// the path between the planes. The result is copied into layer slLayer of slLight.
//SL::Physics
uniform int slLayer;       // sweep index of this plane (0: the sunlit face)
uniform float slPlaneK;    // its lattice index along the axis
uniform float slPath;      // path along the sunlight from one plane to the next, m
uniform float slFirstPath; // fresh sunlight's path to the first plane, m
uniform vec2 slShift;      // the in-plane shift (a1, a2) over that path, in samples
uniform vec2 slPlaneN;     // samples along a1 and a2
uniform vec3 slSun;        // unit vector toward the sun
in vec2 texCoord; // unused (pixels come from gl_FragCoord); read once so VTK's quad keeps the attribute
//VTK::Output::Dec

// Bilinear look-up of the previous plane; false outside it.
bool slPlaneLookup(float u, float w, out vec4 prev)
{
  prev = vec4(0.0);
  vec2 n = slPlaneN;
  if (!sl_sweep_in_plane(u, w, n.x, n.y)) return false;
  float fresh = sl_sweep_fresh_weight(u, w, n.x, n.y);
  u = clamp(u, 0.0, n.x - 1.0);
  w = clamp(w, 0.0, n.y - 1.0);
  ivec2 ni = ivec2(n + 0.5);
  int i = min(int(u), max(ni.x - 2, 0)), j = min(int(w), max(ni.y - 2, 0));
  int i1 = min(i + 1, ni.x - 1), j1 = min(j + 1, ni.y - 1);
  float fu = ni.x > 1 ? u - float(i) : 0.0, fw = ni.y > 1 ? w - float(j) : 0.0;
  int k = slLayer - 1;
  prev = (1.0 - fu) * (1.0 - fw) * texelFetch(slLight, ivec3(i, j, k), 0) +
         fu * (1.0 - fw) * texelFetch(slLight, ivec3(i1, j, k), 0) +
         (1.0 - fu) * fw * texelFetch(slLight, ivec3(i, j1, k), 0) + fu * fw * texelFetch(slLight, ivec3(i1, j1, k), 0);
  prev *= 1.0 - fresh; // fresh light: ln I = 0, n = 0
  return true;
}

// Distance from x back toward the sun to the lattice's box (sl__distance_to_box_toward).
float slDistanceToBoxToward(vec3 x, vec3 dir)
{
  float best = 3.0e38;
  for (int a = 0; a < 3; ++a) {
    if (dir[a] > 0.0) best = min(best, (slBoxHi[a] - x[a]) / dir[a]);
    else if (dir[a] < 0.0) best = min(best, (slBoxLo[a] - x[a]) / dir[a]);
  }
  return max(best, 0.0);
}

void main()
{
  if (texCoord.x < -1.0) discard;
  vec2 p = floor(gl_FragCoord.xy);
  vec3 x = (slPlaneK * slAxisE + p.x * slA1E + p.y * slA2E) * slSpacing;
  vec3 prop = -slSun;
  vec4 prev;
  float len = slPath;
  if (slLayer == 0 || !slPlaneLookup(p.x + slShift.x, p.y + slShift.y, prev)) {
    prev = vec4(0.0);
    len = slLayer == 0 ? slFirstPath : min(slPath, slDistanceToBoxToward(x, slSun));
  }
  vec3 lnI = prev.rgb;
  float n = prev.a;
  float beta[SL_MAX_FIELDS];
  slSampleFields(x - 0.5 * len * prop, beta);
  float total = 0.0;
  for (int j = 0; j < SL_MAX_FIELDS; ++j) total += beta[j];
  if (total > 0.0 && len > 0.0) {
    // One light step on ln I (sl_log_light_step_at in C): the log of the kept fraction adds.
    float logKept[SL_MAX_WAVELENGTHS];
    sl_light_fraction_exponents(beta, n, len, logKept);
    lnI += vec3(logKept[0], logKept[1], logKept[2]);
    if (slMode != SL_MODE_LOW_ALBEDO) n = sl_expected_scatter_count(beta, n, len);
  }
  gl_FragData[0] = vec4(max(lnI, vec3(SL_LOG_FLOOR)), n);
}
