/* The light falling on the ground from the clear sky and the sun (sl_sky.h): what a Lambertian
 * ground reflects, a E / pi, before a cloud's shadow. */
#include <math.h>
#include <stddef.h>

#include "sl_quadrature.h"
#include "sl_sky.h"
#include "sl_vec3.h"

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
  double e1[3], e2[3];
  const double east[3] = {1.0, 0.0, 0.0}, north[3] = {0.0, 1.0, 0.0};
  sl_cross3(fabs(up[0]) > 0.9 ? north : east, up, e2);
  sl_normalize3(e2);
  sl_cross3(e2, up, e1);
  /* E_sky = integral over the upper hemisphere of L mu dOmega: 16-point Gauss-Legendre in mu on
   * [0, 1] (the sky's smooth dependence on it, a degree-31 polynomial exactly), the midpoint rule in
   * azimuth (periodic, so spectrally accurate). */
  double mu[16], wmu[16];
  sl_gauss_legendre(16, mu, wmu);
  for (int i = 0; i < 16; ++i) mu[i] = 0.5 * (1.0 + mu[i]), wmu[i] *= 0.5;
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
  const double cos_sun = sl_dot3(sun, up);
  for (int c = 0; c < atm->count; ++c) sun_on_ground[c] = dark || cos_sun <= 0.0 ? 0.0 : E[c] * cos_sun;
  return SL_OK;
}
