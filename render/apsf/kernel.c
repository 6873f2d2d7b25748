/* The 2D point spread function on the pixel grid (Narasimhan et al., section 7.2, Fig. 10; and
 * eq. 28 for a camera outside a spherical medium). */
#include <math.h>
#include <stdlib.h>

#include "glow_internal.h"
#include "sl_legendre.h"

double sl_glow_focal_px(int height, double fov_y_rad) { return 0.5 * height / tan(0.5 * fov_y_rad); }

void sl_glow_kernel_free(sl_glow_kernel *k)
{
  free(k->w);
  k->w = NULL;
}

/* Solid angle of a unit pixel at r pixels from the principal point: dA cos / d^2 = f / d^3. */
static double pixel_solid_angle(double f, double r2) { return f / ((f * f + r2) * sqrt(f * f + r2)); }

int sl_glow_model_build(sl_glow_model *km, const sl_apsf_medium *m, double T, double focal_px, int rx, int ry,
                       sl_glow_norm norm, double tolerance, sl_error *err)
{
  if (rx < 0 || ry < 0 || (double)(2 * rx + 1) * (2 * ry + 1) > 1e9)
    return sl_fail(err, SL_ERR_ARG, "glow: kernel size %d x %d is out of range", 2 * rx + 1, 2 * ry + 1);
  if (!(focal_px > 0.0) || !isfinite(focal_px))
    return sl_fail(err, SL_ERR_ARG, "glow: focal length must be > 0 pixels (got %g)", focal_px);
  const double r_max = sqrt((double)rx * rx + (double)ry * ry) + 2.0 * SL_GLOW_NEAR;
  sl_apsf_profile prof;
  if (sl_apsf_profile_build(&prof, m, T, tolerance, atan(r_max / focal_px), 4096, err)) return err->code;
  km->T = T;
  km->blend = prof.blend;
  km->direct = prof.direct;
  km->series_scale = prof.series_scale;
  km->terms = prof.terms;
  km->inv_r_table = 1.0 / r_max;
  for (int i = 0; i < SL_GLOW_NR; ++i) {
    const double u = (double)i / (SL_GLOW_NR - 1), r = r_max * u * u;
    km->radial[i] = sl_apsf_profile_eval(&prof, atan(r / focal_px)) * pixel_solid_angle(focal_px, r * r);
  }
  for (int dy = 0; dy < SL_GLOW_NEAR; ++dy)
    for (int dx = 0; dx < SL_GLOW_NEAR; ++dx) {
      double v = 0.0;
      for (int j = 0; j < SL_GLOW_SUB; ++j)
        for (int i = 0; i < SL_GLOW_SUB; ++i) {
          const double x = dx + (i + 0.5) / SL_GLOW_SUB - 0.5, y = dy + (j + 0.5) / SL_GLOW_SUB - 0.5, s2 = x * x + y * y;
          v += sl_apsf_profile_eval(&prof, atan(sqrt(s2) / focal_px)) * pixel_solid_angle(focal_px, s2);
        }
      km->near[dy][dx] = v / (SL_GLOW_SUB * SL_GLOW_SUB);
    }
  km->near[0][0] += prof.direct; /* eq. 30's Dirac: the unscattered beam */
  sl_apsf_profile_free(&prof);
  km->scale = 1.0;
  if (norm == SL_GLOW_PEAK) {
    if (!(km->near[0][0] > 0.0))
      return sl_fail(err, SL_ERR_DATA, "glow: the PSF at T = %g has no positive centre value", T);
    km->scale = 1.0 / km->near[0][0];
  }
  return SL_OK;
}

int sl_glow_kernel_build(sl_glow_kernel *k, const sl_apsf_medium *m, double T, double focal_px, int rx, int ry,
                         sl_glow_norm norm, double tolerance, sl_error *err)
{
  k->w = NULL;
  sl_glow_model *km = malloc(sizeof *km);
  if (!km) return sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for a kernel");
  int rc = sl_glow_model_build(km, m, T, focal_px, rx, ry, norm, tolerance, err);
  const int nx = 2 * rx + 1, ny = 2 * ry + 1;
  if (rc == SL_OK && !(k->w = malloc(sizeof(double) * (size_t)nx * (size_t)ny)))
    rc = sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for a %d x %d kernel", nx, ny);
  if (rc) {
    free(km);
    return rc;
  }
  k->rx = rx;
  k->ry = ry;
  k->T = T;
  k->blend = km->blend;
  k->direct = km->direct;
  k->series_scale = km->series_scale;
  k->terms = km->terms;
  double sum = 0.0;
  for (int dy = -ry; dy <= ry; ++dy)
    for (int dx = -rx; dx <= rx; ++dx) sum += k->w[(size_t)(dy + ry) * nx + dx + rx] = sl_glow_model_value(km, dx, dy);
  k->sum = sum;
  free(km);
  return SL_OK;
}

int sl_glow_kernel_build_sphere(sl_glow_kernel *k, const sl_apsf_medium *m, double T_radius, double distance_ratio,
                                double focal_px, int rx, int ry, double tolerance, sl_error *err)
{
  k->w = NULL;
  if (!(T_radius >= SL_APSF_BLEND_HI) || !isfinite(T_radius))
    return sl_fail(err, SL_ERR_ARG, "glow: a sphere seen from outside needs its optical radius >= %g (got %g)",
                   SL_APSF_BLEND_HI, T_radius);
  if (!(distance_ratio > 1.0) || !isfinite(distance_ratio))
    return sl_fail(err, SL_ERR_ARG, "glow: the camera must be outside the sphere (distance ratio %g)", distance_ratio);
  if (rx < 0 || ry < 0 || (double)(2 * rx + 1) * (2 * ry + 1) > 1e9 || !(focal_px > 0.0))
    return sl_fail(err, SL_ERR_ARG, "glow: kernel %d x %d or focal length %g out of range", 2 * rx + 1, 2 * ry + 1,
                   focal_px);
  sl_apsf_series s;
  if (sl_apsf_series_init(&s, m, T_radius, tolerance, 0, err)) return err->code;
  const int nx = 2 * rx + 1, ny = 2 * ry + 1;
  k->w = malloc(sizeof(double) * (size_t)nx * (size_t)ny);
  if (!k->w) {
    sl_apsf_series_free(&s);
    return sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for a %d x %d kernel", nx, ny);
  }
  /* The unscattered share as in sl_apsf_profile: a Dirac e^{-T}, the series scaled by s. */
  const double direct = exp(-T_radius), s_frac = fmax(0.0, 1.0 - exp((3.0 * (1.0 - m->albedo) - 1.0) * T_radius));
  const double scale = s_frac * distance_ratio * distance_ratio * T_radius * T_radius / (4.0 * SL_PI);
  double sum = 0.0;
  for (int dy = -ry; dy <= ry; ++dy)
    for (int dx = -rx; dx <= rx; ++dx) {
      const int near = dx * dx + dy * dy < SL_GLOW_NEAR * SL_GLOW_NEAR;
      const int sub = near ? SL_GLOW_SUB : 1;
      double v = 0.0;
      for (int j = 0; j < sub; ++j)
        for (int i = 0; i < sub; ++i) {
          const double x = dx + (near ? (i + 0.5) / sub - 0.5 : 0.0), y = dy + (near ? (j + 0.5) / sub - 0.5 : 0.0);
          const double r2 = x * x + y * y;
          const double mu = sl_apsf_mu_outside(distance_ratio, 1.0, atan(sqrt(r2) / focal_px)); /* eq. 28 */
          if (mu > -1.5) v += scale * sl_apsf_series_eval(&s, mu) * pixel_solid_angle(focal_px, r2);
        }
      v /= sub * sub;
      if (dx == 0 && dy == 0) v += direct;
      k->w[(size_t)(dy + ry) * nx + dx + rx] = v;
      sum += v;
    }
  k->rx = rx;
  k->ry = ry;
  k->T = T_radius;
  k->blend = 1.0;
  k->direct = direct;
  k->series_scale = s_frac;
  k->terms = s.terms;
  k->sum = sum;
  sl_apsf_series_free(&s);
  return SL_OK;
}

