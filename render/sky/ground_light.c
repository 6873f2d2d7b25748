/* The light falling on the ground from the clear sky and the sun (sl_sky.h): what a Lambertian
 * ground reflects, a E / pi, before a cloud's shadow. */
#include <math.h>
#include <stddef.h>

#include "sl_sky.h"

/* Gauss-Legendre nodes and weights on [0, 1] in the cosine of the zenith angle: 16 points integrate
 * the sky's smooth dependence on it (a degree-31 polynomial exactly). */
static void gauss_legendre_16(double x[16], double w[16])
{
  for (int i = 0; i < 8; ++i) {
    /* Newton on P_16 from Tricomi's estimate of the i-th root. */
    double t = cos(M_PI * (i + 0.75) / 16.5), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = t;
      for (int n = 2; n <= 16; ++n) {
        const double p2 = ((2.0 * n - 1.0) * t * p1 - (n - 1.0) * p0) / n;
        p0 = p1, p1 = p2;
      }
      dp = 16.0 * (t * p1 - p0) / (t * t - 1.0);
      const double step = p1 / dp;
      t -= step;
      if (fabs(step) < 1e-15) break;
    }
    const double weight = 2.0 / ((1.0 - t * t) * dp * dp);
    x[i] = 0.5 * (1.0 - t), w[i] = 0.5 * weight;
    x[15 - i] = 0.5 * (1.0 + t), w[15 - i] = 0.5 * weight;
  }
}

int sl_sky_ground_irradiance(const sl_atmosphere *atm, const double sun[3], double *sky, double *sun_on_ground,
                             int *night, sl_error *err)
{
  const double ground[3] = {0.0, 0.0, 0.0};
  sl_sky_view view;
  if (sl_sky_view_init(&view, atm, ground, sun, err)) return err->code;
  *night = view.night;
  for (int c = 0; c < atm->count; ++c) sky[c] = sun_on_ground[c] = 0.0;
  if (view.night) return SL_OK;
  double up[3];
  sl_sky_altitude(atm, ground, up);
  /* A basis with up as its third axis. */
  double e1[3] = {1.0, 0.0, 0.0};
  if (fabs(up[0]) > 0.9) e1[0] = 0.0, e1[1] = 1.0;
  const double k = e1[0] * up[0] + e1[1] * up[1] + e1[2] * up[2];
  for (int a = 0; a < 3; ++a) e1[a] -= k * up[a];
  const double n1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (int a = 0; a < 3; ++a) e1[a] /= n1;
  const double e2[3] = {up[1] * e1[2] - up[2] * e1[1], up[2] * e1[0] - up[0] * e1[2], up[0] * e1[1] - up[1] * e1[0]};
  /* E_sky = integral over the upper hemisphere of L mu dOmega: Gauss in mu, the midpoint rule in
   * azimuth (periodic, so spectrally accurate). */
  double mu[16], wmu[16];
  gauss_legendre_16(mu, wmu);
  const int n_azimuth = 64;
  for (int i = 0; i < 16; ++i) {
    const double s = sqrt(1.0 - mu[i] * mu[i]);
    for (int j = 0; j < n_azimuth; ++j) {
      const double phi = 2.0 * M_PI * (j + 0.5) / n_azimuth;
      double d[3], L[SL_SKY_MAX_WAVELENGTHS];
      for (int a = 0; a < 3; ++a) d[a] = s * cos(phi) * e1[a] + s * sin(phi) * e2[a] + mu[i] * up[a];
      sl_sky_view_segment(&view, d, 0.0, INFINITY, L, NULL);
      for (int c = 0; c < atm->count; ++c) sky[c] += L[c] * mu[i] * wmu[i] * (2.0 * M_PI / n_azimuth);
    }
  }
  double E[SL_SKY_MAX_WAVELENGTHS];
  int dark = 0;
  if (sl_sky_sunlight(atm, ground, sun, E, &dark, err)) return err->code;
  const double cos_sun = sun[0] * up[0] + sun[1] * up[1] + sun[2] * up[2];
  for (int c = 0; c < atm->count; ++c) sun_on_ground[c] = dark || cos_sun <= 0.0 ? 0.0 : E[c] * cos_sun;
  return SL_OK;
}
