/* The bodies of sl_sky_sample.h (Riley et al. 2004, eqs. 1, 9-15; derivations in docs/SKY.md),
 * written once in a subset that compiles as C (sky_sample.c includes this file with double) and
 * as GLSL (the GPU pass embeds this very text, tests/gpu checks both): scalars only, no
 * pointers, no const locals, no literal suffixes, arrays only as fixed-size parameters; the
 * includer defines SL_SKY_REAL, SL_SKY_INFINITY, sl_sky_isinf, sl_sky_abs, SL_SKY_IN_ARRAY and
 * SL_SKY_OUT_ARRAY, and SL_SUN_ANGULAR_DIAMETER_DEG (sl_sky_sample.h). Not a header to include
 * anywhere else. */

SL_SKY_REAL sl_sky_exprel(SL_SKY_REAL x)
{
  /* Below |x| = 0.05 the direct form loses up to 2 digits to cancellation in 1 - exp(-x); the
   * Taylor series to x^7 has a truncation error below 0.05^8 / 9! = 1.1e-16 there. */
  if (x > -0.05 && x < 0.05)
    return 1.0 +
           x * (-1.0 / 2.0 +
                x * (1.0 / 6.0 +
                     x * (-1.0 / 24.0 +
                          x * (1.0 / 120.0 +
                               x * (-1.0 / 720.0 + x * (1.0 / 5040.0 + x * (-1.0 / 40320.0)))))));
  return (1.0 - exp(-x)) / x;
}

SL_SKY_REAL sl_sky_rayleigh_phase(SL_SKY_REAL cos_theta)
{
  /* Riley et al. 2004, eq. 1 */
  return 3.0 / (16.0 * 3.14159265358979323846) * (1.0 + cos_theta * cos_theta);
}

SL_SKY_REAL sl_sky_path_length_factor(SL_SKY_REAL inv_scale_height, SL_SKY_REAL dz, SL_SKY_REAL distance)
{
  return distance * sl_sky_exprel(inv_scale_height * dz);
}

SL_SKY_REAL sl_sky_optical_depth(SL_SKY_REAL beta_sea_level, SL_SKY_REAL inv_scale_height, SL_SKY_REAL z0,
                                 SL_SKY_REAL z1, SL_SKY_REAL distance)
{
  /* Riley et al. 2004, eq. 11, written as beta(z0) * K * exprel(gamma * (z1 - z0)): the printed
   * form divides by p_y = (z1 - z0) / K and is 0/0 for a horizontal segment. */
  return beta_sea_level * exp(-inv_scale_height * z0) *
         sl_sky_path_length_factor(inv_scale_height, z1 - z0, distance);
}

SL_SKY_REAL sl_sky_sun_optical_depth(SL_SKY_REAL beta_sea_level, SL_SKY_REAL inv_scale_height, SL_SKY_REAL z,
                                     SL_SKY_REAL airmass)
{
  /* Riley et al. 2004, eq. 12: beta(z) / (gamma * l_y), with 1 / l_y generalised to an air mass
   * so the round earth (Chapman function) uses the same formula. */
  if (sl_sky_isinf(airmass)) return airmass;
  return beta_sea_level * exp(-inv_scale_height * z) * airmass / inv_scale_height;
}

SL_SKY_REAL sl_sky_ground_distance(SL_SKY_REAL z_eye, SL_SKY_REAL mu, SL_SKY_REAL ground_radius)
{
  if (!(mu < 0.0)) return SL_SKY_INFINITY;
  SL_SKY_REAL h = z_eye > 0.0 ? z_eye : 0.0;
  if (!(ground_radius > 0.0)) return h / -mu; /* the plane z = 0 */
  /* |eye + t dir - centre| = R with the eye at R + h from the centre: t^2 + 2 r0 mu t + h (2R + h) = 0.
   * The near root, written as h (2R + h) / (-r0 mu + sqrt(disc)) so that neither a steep ray
   * (disc ~ r0^2 mu^2) nor a low eye cancels; no real root: the ray passes over the horizon. */
  SL_SKY_REAL r0 = ground_radius + h;
  SL_SKY_REAL c = h * (2.0 * ground_radius + h);
  SL_SKY_REAL disc = r0 * r0 * mu * mu - c;
  if (disc < 0.0) return SL_SKY_INFINITY;
  SL_SKY_REAL q = -r0 * mu + sqrt(disc);
  return q > 0.0 ? c / q : 0.0;
}

SL_SKY_REAL sl_sky_segment_length(SL_SKY_REAL z_eye, SL_SKY_REAL mu, SL_SKY_REAL distance, SL_SKY_REAL ground_radius)
{
  SL_SKY_REAL to_ground = sl_sky_ground_distance(z_eye, mu, ground_radius);
  return distance < to_ground ? distance : to_ground;
}

SL_SKY_REAL sl_sky_segment_length_factor(SL_SKY_REAL inv_scale_height, SL_SKY_REAL mu, SL_SKY_REAL distance)
{
  if (sl_sky_isinf(distance)) return mu > 0.0 ? 1.0 / (inv_scale_height * mu) : distance;
  return distance * sl_sky_exprel(mu == 0.0 ? 0.0 : inv_scale_height * mu * distance);
}

SL_SKY_REAL sl_sky_inscatter_gathered(SL_SKY_REAL beta_eye, SL_SKY_REAL inv_scale_height, SL_SKY_REAL mu,
                                      SL_SKY_REAL length, SL_SKY_REAL far_density, SL_SKY_REAL airmass)
{
  /* Riley et al. 2004, eqs. 14-15, corrected (docs/SKY.md): substituting u = exp(-gamma mu t)
   * into eq. 14 gives exp(-beta_eye / (gamma mu)) * l / (l - mu) * (e^a - e^{a u_K}); the printed
   * eq. 15 drops the first factor. We write the exact result as exp(-min(c, e)) * D *
   * exprel(|e - c|), which has no division by mu or by (mu - l). */
  if (!(beta_eye > 0.0) || !(length > 0.0) || sl_sky_isinf(airmass)) return 0.0;
  SL_SKY_REAL gamma = inv_scale_height;
  SL_SKY_REAL tau = beta_eye * length;
  SL_SKY_REAL sun_depth_eye = beta_eye * airmass / gamma;
  SL_SKY_REAL sun_depth_far = tau + beta_eye * far_density * airmass / gamma;
  SL_SKY_REAL slope = 1.0 - mu * airmass; /* (e - c) / tau */
  SL_SKY_REAL spread = tau * slope;
  SL_SKY_REAL attenuation = spread >= 0.0 ? exp(-sun_depth_eye) : exp(-sun_depth_far);
  SL_SKY_REAL gathered; /* D * exprel(|e - c|) = integral of exp(-|e - c| t / K) dt over the segment */
  if (sl_sky_isinf(length))
    gathered = 1.0 / (beta_eye * sl_sky_abs(slope));
  else
    gathered = length * sl_sky_exprel(sl_sky_abs(spread));
  return beta_eye * attenuation * gathered;
}

SL_SKY_REAL sl_sky_inscatter(SL_SKY_REAL beta_sea_level, SL_SKY_REAL inv_scale_height, SL_SKY_REAL z_eye,
                             SL_SKY_REAL mu, SL_SKY_REAL distance, SL_SKY_REAL airmass, SL_SKY_REAL cos_view_sun)
{
  SL_SKY_REAL gamma = inv_scale_height;
  SL_SKY_REAL beta_eye = beta_sea_level * exp(-gamma * z_eye);
  if (!(distance > 0.0)) return 0.0;
  SL_SKY_REAL length = sl_sky_segment_length_factor(gamma, mu, distance); /* D */
  SL_SKY_REAL far_density = exp(mu == 0.0 ? 0.0 : -gamma * mu * distance); /* beta_K / beta_eye */
  return sl_sky_rayleigh_phase(cos_view_sun) *
         sl_sky_inscatter_gathered(beta_eye, gamma, mu, length, far_density, airmass);
}

/* The wavelength-independent geometry of the stretch [near, end] of a view ray (from an eye at
 * height z_eye, direction cosine mu; end may be infinite, near <= end) that sl_sky_view_segment
 * gathers over: g[0] the path length factor from the eye to near (eq. 11), g[1] and g[2] the air
 * density relative to sea level at the eye and at near, g[3] the stretch's length factor D
 * (sl_sky_segment_length_factor), g[4] the density at its end relative to near. */
void sl_sky_segment_geometry(SL_SKY_REAL inv_scale_height, SL_SKY_REAL z_eye, SL_SKY_REAL mu, SL_SKY_REAL near,
                             SL_SKY_REAL end, SL_SKY_OUT_ARRAY(g, 5))
{
  SL_SKY_REAL gamma = inv_scale_height;
  SL_SKY_REAL z_near = z_eye + mu * near;
  SL_SKY_REAL length = sl_sky_isinf(end) ? end : end - near;
  g[0] = near > 0.0 ? sl_sky_path_length_factor(gamma, z_near - z_eye, near) : 0.0;
  g[1] = exp(-gamma * z_eye);
  g[2] = exp(-gamma * z_near);
  g[3] = length > 0.0 ? sl_sky_segment_length_factor(gamma, mu, length) : 0.0;
  g[4] = length > 0.0 ? exp(mu == 0.0 ? 0.0 : -gamma * mu * length) : 1.0;
}

/* The stretch [t_near, t_far] of a view ray (t_far may be infinite) as sl_sky_view_segment
 * gathers over it: the ray ends where it meets the ground (sl_sky_segment_length), and the
 * stretch starts no earlier than the eye and no later than that end. Writes its geometry g
 * (sl_sky_segment_geometry) and returns its near end. */
SL_SKY_REAL sl_sky_view_geometry(SL_SKY_REAL inv_scale_height, SL_SKY_REAL z_eye, SL_SKY_REAL mu,
                                 SL_SKY_REAL ground_radius, SL_SKY_REAL t_near, SL_SKY_REAL t_far,
                                 SL_SKY_OUT_ARRAY(g, 5))
{
  SL_SKY_REAL end = sl_sky_segment_length(z_eye, mu, t_far, ground_radius);
  SL_SKY_REAL near = t_near < end ? (t_near > 0.0 ? t_near : 0.0) : end;
  sl_sky_segment_geometry(inv_scale_height, z_eye, mu, near, end, g);
  return near;
}

/* Riley et al. 2004, eqs. 14-15 corrected, over that stretch for one wavelength of sea-level
 * extinction beta and top-of-atmosphere irradiance: the sunlight the stretch scatters toward
 * the eye (Rayleigh phase value `phase`), attenuated by the air between the eye and near. */
SL_SKY_REAL sl_sky_segment_radiance(SL_SKY_REAL beta, SL_SKY_REAL irradiance, SL_SKY_REAL phase,
                                    SL_SKY_REAL inv_scale_height, SL_SKY_REAL mu, SL_SKY_REAL near,
                                    SL_SKY_REAL airmass, SL_SKY_IN_ARRAY(g, 5))
{
  SL_SKY_REAL front = near > 0.0 ? exp(-beta * g[1] * g[0]) : 1.0;
  return irradiance * front * phase * sl_sky_inscatter_gathered(beta * g[2], inv_scale_height, mu, g[3], g[4], airmass);
}

/* Riley eq. 11: the stretch's own transparency; an infinite horizontal stretch never leaves the
 * flat atmosphere and is opaque, unless there is no air. */
SL_SKY_REAL sl_sky_segment_transparency(SL_SKY_REAL beta, SL_SKY_IN_ARRAY(g, 5))
{
  SL_SKY_REAL beta_near = beta * g[2];
  return !(beta_near > 0.0) ? 1.0 : sl_sky_isinf(g[3]) ? 0.0 : exp(-beta_near * g[3]);
}

/* Section 4.2.4: the sun's disk. Its solid angle 2 pi (1 - cos r), written with sin^2 to avoid
 * the cancellation of 1 - cos for small r. */
SL_SKY_REAL sl_sun_disk_solid_angle(void)
{
  SL_SKY_REAL radius = 0.5 * SL_SUN_ANGULAR_DIAMETER_DEG * 3.14159265358979323846 / 180.0;
  SL_SKY_REAL s = sin(0.5 * radius);
  return 4.0 * 3.14159265358979323846 * s * s;
}

/* Chord lengths, not the cosine: cos(0.25 deg) = 0.9999905 leaves 5 digits. */
int sl_sky_in_sun_disk_at(SL_SKY_REAL dx, SL_SKY_REAL dy, SL_SKY_REAL dz, SL_SKY_REAL sun_z)
{
  SL_SKY_REAL radius = 0.5 * SL_SUN_ANGULAR_DIAMETER_DEG * 3.14159265358979323846 / 180.0;
  if (!(sun_z > 0.0)) return 0;
  SL_SKY_REAL chord = 2.0 * sin(0.5 * radius);
  return dx * dx + dy * dy + dz * dz <= chord * chord ? 1 : 0;
}

/* The disk's radiance: the sunlight attenuated to height z (Riley eq. 12) over the solid angle. */
SL_SKY_REAL sl_sky_sun_disk_light(SL_SKY_REAL irradiance, SL_SKY_REAL beta_sea_level, SL_SKY_REAL inv_scale_height,
                                  SL_SKY_REAL z, SL_SKY_REAL airmass)
{
  if (sl_sky_isinf(airmass)) return 0.0;
  return irradiance / sl_sun_disk_solid_angle() *
         exp(-sl_sky_sun_optical_depth(beta_sea_level, inv_scale_height, z, airmass));
}
