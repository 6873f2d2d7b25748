/* Sky queries for all wavelengths of an sl_atmosphere: transparency (eq. 11), sunlight (eq. 12),
 * in-scattered sky light (eqs. 14-15, corrected) and the direct sun (section 4.2.4). */
#include <math.h>
#include <stddef.h>

#include "sl_sky.h"

static int finite3(const double v[3])
{
  return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* Directions come from callers' arithmetic: accept unit length to 1e-6 and renormalise. */
static int unit_direction(const double v[3], double out[3], const char *what, sl_error *err)
{
  if (!finite3(v)) return sl_fail(err, SL_ERR_ARG, "sky: %s is not finite", what);
  double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(fabs(n - 1.0) <= 1e-6))
    return sl_fail(err, SL_ERR_ARG, "sky: %s has length %g, not 1", what, n);
  for (int i = 0; i < 3; ++i) out[i] = v[i] / n;
  return SL_OK;
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

int sl_sky_transparency(const sl_atmosphere *atm, const double a[3], const double b[3],
                        double *transparency, sl_error *err)
{
  if (!atm || !a || !b || !transparency) return sl_fail(err, SL_ERR_ARG, "sky: NULL argument");
  if (!finite3(a) || !finite3(b)) return sl_fail(err, SL_ERR_ARG, "sky: point is not finite");
  double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  double distance = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  double gamma = 1.0 / atm->scale_height;
  for (int i = 0; i < atm->count; ++i)
    transparency[i] = exp(-sl_sky_optical_depth(atm->beta_sea_level[i], gamma, sl_sky_altitude(atm, a, NULL),
                                                sl_sky_altitude(atm, b, NULL), distance));
  return SL_OK;
}

int sl_sky_sunlight(const sl_atmosphere *atm, const double p[3], const double sun_dir[3],
                    double *irradiance, int *night, sl_error *err)
{
  if (!atm || !p || !sun_dir || !irradiance) return sl_fail(err, SL_ERR_ARG, "sky: NULL argument");
  double sun[3];
  if (!finite3(p)) return sl_fail(err, SL_ERR_ARG, "sky: point is not finite");
  int status = unit_direction(sun_dir, sun, "sun direction", err);
  if (status) return status;
  double up[3];
  const double z = sl_sky_altitude(atm, p, up);
  double airmass = sl_sky_airmass(atm, z, dot3(sun, up));
  double gamma = 1.0 / atm->scale_height;
  for (int i = 0; i < atm->count; ++i)
    irradiance[i] = isinf(airmass) ? 0.0
                                   : atm->sun_irradiance[i] *
                                         exp(-sl_sky_sun_optical_depth(atm->beta_sea_level[i], gamma,
                                                                       z, airmass));
  if (night) *night = isinf(airmass);
  return SL_OK;
}

int sl_sky_segment(const sl_atmosphere *atm, const double eye[3], const double dir[3],
                   double distance, const double sun_dir[3], double *radiance,
                   double *transparency, int *night, sl_error *err)
{
  if (!atm || !eye || !dir || !sun_dir) return sl_fail(err, SL_ERR_ARG, "sky: NULL argument");
  double view[3], sun[3];
  if (!finite3(eye)) return sl_fail(err, SL_ERR_ARG, "sky: eye is not finite");
  int status = unit_direction(dir, view, "view direction", err);
  if (!status) status = unit_direction(sun_dir, sun, "sun direction", err);
  if (status) return status;
  if (!(distance >= 0.0)) return sl_fail(err, SL_ERR_ARG, "sky: segment length %g is negative", distance);

  double gamma = 1.0 / atm->scale_height;
  double up[3];
  const double z_eye = sl_sky_altitude(atm, eye, up);
  double mu = dot3(view, up);
  double length = sl_sky_segment_length(z_eye, mu, distance, atm->ground_radius);
  double airmass = sl_sky_airmass(atm, z_eye, dot3(sun, up));
  double cos_view_sun = view[0] * sun[0] + view[1] * sun[1] + view[2] * sun[2];
  for (int i = 0; i < atm->count; ++i) {
    double beta = atm->beta_sea_level[i];
    if (radiance)
      radiance[i] = atm->sun_irradiance[i] *
                    sl_sky_inscatter(beta, gamma, z_eye, mu, length, airmass, cos_view_sun);
    if (transparency) {
      /* Eq. 11 to distance `length`; an infinite segment upward reaches the top of the
       * atmosphere, horizontally it never leaves the flat atmosphere and is opaque. */
      double beta_eye = beta * exp(-gamma * z_eye);
      double factor = sl_sky_segment_length_factor(gamma, mu, length);
      transparency[i] = !(beta_eye > 0.0) ? 1.0 : isinf(factor) ? 0.0 : exp(-beta_eye * factor);
    }
  }
  if (night) *night = isinf(airmass);
  return SL_OK;
}

int sl_sky_view_init(sl_sky_view *view, const sl_atmosphere *atm, const double eye[3],
                     const double sun_dir[3], sl_error *err)
{
  if (!view || !atm || !eye || !sun_dir) return sl_fail(err, SL_ERR_ARG, "sky: NULL argument");
  if (!finite3(eye)) return sl_fail(err, SL_ERR_ARG, "sky: eye is not finite");
  int status = unit_direction(sun_dir, view->sun, "sun direction", err);
  if (status) return status;
  view->atm = atm;
  for (int i = 0; i < 3; ++i) view->eye[i] = eye[i];
  view->altitude = sl_sky_altitude(atm, eye, view->up);
  view->airmass = sl_sky_airmass(atm, view->altitude, dot3(view->sun, view->up));
  view->night = isinf(view->airmass);
  return SL_OK;
}

void sl_sky_view_segment(const sl_sky_view *view, const double dir[3], double t_near, double t_far,
                         double *radiance, double *transparency)
{
  const sl_atmosphere *atm = view->atm;
  /* The eye's height and vertical from its position (callers may move view->eye). */
  double up[3];
  const double z_eye = sl_sky_altitude(atm, view->eye, up);
  const double gamma = 1.0 / atm->scale_height, mu = dot3(dir, up);
  double phase = sl_sky_rayleigh_phase(dir[0] * view->sun[0] + dir[1] * view->sun[1] + dir[2] * view->sun[2]);
  double g[5]; /* wavelength-independent geometry, once per ray */
  const double near = sl_sky_view_geometry(gamma, z_eye, mu, atm->ground_radius, t_near, t_far, g);
  for (int i = 0; i < atm->count; ++i) {
    if (radiance)
      radiance[i] = sl_sky_segment_radiance(atm->beta_sea_level[i], atm->sun_irradiance[i], phase, gamma, mu, near,
                                            view->airmass, g);
    if (transparency) transparency[i] = sl_sky_segment_transparency(atm->beta_sea_level[i], g);
  }
}

int sl_sky_in_sun_disk(const double dir[3], const double sun_dir[3])
{
  return sl_sky_in_sun_disk_at(dir[0] - sun_dir[0], dir[1] - sun_dir[1], dir[2] - sun_dir[2], sun_dir[2]);
}

int sl_sky_sun_disk_radiance(const sl_atmosphere *atm, const double eye[3], const double dir[3],
                             const double sun_dir[3], double *radiance)
{
  int inside = sl_sky_in_sun_disk(dir, sun_dir);
  double up[3];
  const double z = sl_sky_altitude(atm, eye, up);
  double airmass = inside ? sl_sky_airmass(atm, z, dot3(sun_dir, up)) : INFINITY;
  double gamma = 1.0 / atm->scale_height;
  for (int i = 0; i < atm->count; ++i)
    radiance[i] = sl_sky_sun_disk_light(atm->sun_irradiance[i], atm->beta_sea_level[i], gamma, z, airmass);
  return inside && !isinf(airmass);
}
