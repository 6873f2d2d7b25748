//VTK::System::Dec
// Stormlight: the eye pass's accumulator resolved on the GPU, per pixel what the CPU's
// sl_renderer_resolve_accumulator and sl_renderer_background compute (render/volume/resolve.c):
// the volume layer with the aerial perspective in front of it (the sky's light and transparency
// from the eye to the content's midplane), and the background (the sky along the whole ray, the
// sun's disk, the view-axis distance to the ground). The layer's split, value and depth are
// render/volume/sl_sample_physics.h's, the sky render/sky/sky_sample_shared.h: the texts the CPU
// compiles. Image row py is written to GL row
// py, so that the read-back lies in the image's order (rows from the top).
//SL::Model
//SL::Sky
//SL::ViewRay
uniform sampler2D slAccColor;  // the eye pass: radiance per wavelength, transparency (GL rows)
uniform sampler2D slAccDepth;  // the eye pass: opacity-weighted depth numerator
uniform float slMidDistance;   // along the view axis from the eye to the content's midplane
uniform vec3 slToRgb[3];       // spectral-to-linear-sRGB rows
uniform int slHaveAir;
uniform vec3 slSkyRadiance;    // the background without air
// The sky as seen from this camera (sl_sky_view_init) and the air's constants.
uniform float slEyeAltitude, slAirmass, slInvScaleHeight, slGroundRadius;
uniform vec3 slVertical, slSkySun, slBeta, slIrradiance;
// The lit ground (render/volume/ground_shadow.h): radiance slGroundSun * shadow + slGroundSky.
uniform int slGroundOn;
uniform vec3 slGroundSun, slGroundSky;
uniform sampler2D slShadow;    // the storm's transparency toward the sun on the ground, cell centres
uniform vec2 slShadowOrigin, slShadowSpacing, slShadowN;
in vec2 texCoord; // unused (pixels come from gl_FragCoord); read once so VTK's quad keeps the attribute
//VTK::Output::Dec

// sl_sky_view_segment: the sky's light and transparency of [t_near, t_far] along d.
void slSkySegment(vec3 d, float t_near, float t_far, out vec3 radiance, out vec3 transparency)
{
  float mu = dot(d, slVertical);
  float g[5];
  float near = sl_sky_view_geometry(slInvScaleHeight, slEyeAltitude, mu, slGroundRadius, t_near, t_far, g);
  float phase = sl_sky_rayleigh_phase(dot(d, slSkySun));
  for (int c = 0; c < 3; ++c) {
    radiance[c] = sl_sky_segment_radiance(slBeta[c], slIrradiance[c], phase, slInvScaleHeight, mu, near, slAirmass, g);
    transparency[c] = sl_sky_segment_transparency(slBeta[c], g);
  }
}

// sl__ground_shadow_at: bilinear between the map's cell centres, 1 off the map.
float slShadowAt(vec2 x)
{
  vec2 u = (x - slShadowOrigin) / slShadowSpacing;
  ivec2 n = ivec2(slShadowN + 0.5);
  if (!(u.x >= 0.0 && u.y >= 0.0 && u.x <= float(n.x - 1) && u.y <= float(n.y - 1))) return 1.0;
  ivec2 i = min(ivec2(u), max(n - 2, ivec2(0)));
  ivec2 i1 = min(i + 1, n - 1);
  vec2 f = u - vec2(i);
  float s00 = texelFetch(slShadow, i, 0).r, s10 = texelFetch(slShadow, ivec2(i1.x, i.y), 0).r;
  float s01 = texelFetch(slShadow, ivec2(i.x, i1.y), 0).r, s11 = texelFetch(slShadow, i1, 0).r;
  return (1.0 - f.y) * ((1.0 - f.x) * s00 + f.x * s10) + f.y * ((1.0 - f.x) * s01 + f.x * s11);
}

vec3 slToLinearRgb(vec3 spectrum)
{
  return vec3(dot(slToRgb[0], spectrum), dot(slToRgb[1], spectrum), dot(slToRgb[2], spectrum));
}

void main()
{
  if (texCoord.x < -1.0) discard;
  float px = floor(gl_FragCoord.x), py = floor(gl_FragCoord.y);
  vec3 d = slPixelRay(px, py);
  ivec2 texel = ivec2(int(px), int(slSize.y - 1.0 - py));
  vec4 acc = texelFetch(slAccColor, texel, 0);
  float T = acc.a, depthNumerator = texelFetch(slAccDepth, texel, 0).r;
  // The volume layer (sl__resolve_pixel): the sky in front of the midplane over the volume.
  float t0, t1;
  if (!(slContentSpan(d, t0, t1) && t1 > t0 && t1 > 0.0)) t0 = t1 = 0.0;
  t0 = max(t0, 0.0);
  float along = dot(slFwd, d);
  float tMid = sl_resolve_split(along, slMidDistance, t0, t1);
  vec3 front = vec3(0.0), frontT = vec3(1.0);
  if (slHaveAir != 0 && T < 1.0) slSkySegment(d, 0.0, tMid, front, frontT);
  float coverage = 1.0 - T;
  vec3 layer;
  for (int c = 0; c < 3; ++c) layer[c] = sl_resolve_layer(acc[c], coverage, front[c], frontT[c]);
  gl_FragData[0] = vec4(slToLinearRgb(layer), coverage);
  float depth = sl_resolve_depth(depthNumerator, coverage, slInfinity);
  // The background (sl_renderer_background).
  vec3 sky = slSkyRadiance;
  float groundDepth = slInfinity;
  if (slHaveAir != 0) {
    vec3 L, skyT;
    slSkySegment(d, 0.0, slInfinity, L, skyT);
    vec3 toSun = d - slSkySun;
    if (sl_sky_in_sun_disk_at(toSun.x, toSun.y, toSun.z, slSkySun.z) != 0)
      for (int c = 0; c < 3; ++c)
        L[c] += sl_sky_sun_disk_light(slIrradiance[c], slBeta[c], slInvScaleHeight, slEyeAltitude, slAirmass);
    float tGround = sl_sky_ground_distance(slEyeAltitude, dot(d, slVertical), slGroundRadius);
    if (slGroundOn != 0 && !isinf(tGround)) {
      float S = slShadowAt((slEye + tGround * d).xy);
      L += skyT * (slGroundSun * S + slGroundSky);
    }
    sky = slToLinearRgb(L);
    groundDepth = tGround * along;
  }
  gl_FragData[1] = vec4(T, depth, groundDepth, 0.0);
  gl_FragData[2] = vec4(sky, 1.0);
}
