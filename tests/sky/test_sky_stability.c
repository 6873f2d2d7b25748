/* Stability sweep (issue 5, item 2): eye from sea level to 100 km, every view elevation (with
 * exact and near-exact horizontal and sun-elevation rays), the sun from below the horizon to the
 * zenith, segments from 0 to 1000 km and infinite, both earth models, 16 wavelengths. Every
 * output is finite, transparency lies in [0, 1], and single scattering obeys its physical
 * bound L <= P(theta) I (1 - T): no more light is scattered than the segment removes. */
#include <math.h>
#include <stdio.h>

#include "sl_sky.h"
#include "sl_testing.h"

int main(void)
{
  double wl[SL_SKY_SPECTRAL_COUNT];
  sl_sky_spectral_wavelengths(wl);
  const double eyes[] = {0.0, 1.0, 1e3, 1e4, 1e5};
  const double suns[] = {-5.0, -1e-9, 0.0, 1e-12, 1e-6, 0.01, 0.5, 2.0, 10.0, 45.0, 90.0};
  const double distances[] = {0.0, 1.0, 1e3, 1e6, INFINITY};
  long evaluations = 0, bad = 0, night_ok = 1;
  for (int model = 0; model < 2; ++model) {
    sl_atmosphere atm;
    sl_atmosphere_init(&atm, wl, SL_SKY_SPECTRAL_COUNT, model ? SL_EARTH_ROUND : SL_EARTH_FLAT,
                       SL_RAYLEIGH_BODHAINE1999, NULL);
    for (int e = 0; e < 5; ++e)
      for (int s = 0; s < 11; ++s) {
        const double eye[3] = {10.0, -20.0, eyes[e]};
        double sun[3];
        sl_sun_direction(suns[s], 123.0, sun);
        sl_sky_view view;
        if (sl_sky_view_init(&view, &atm, eye, sun, NULL) != SL_OK) {
          ++bad;
          continue;
        }
        if (view.night != !(sun[2] > 0.0)) night_ok = 0;
        for (int v = -182; v <= 182; ++v) {
          /* -90..90 in half degrees, plus exact/near horizontal and the sun's own elevation */
          double el = v == -182 ? 1e-10 : v == 182 ? -1e-10 : v == -181 ? suns[s] : 0.5 * v;
          if (el < -90.0 || el > 90.0) continue;
          double dir[3];
          sl_sun_direction(el, 123.0 + (v % 7) * 25.0, dir);
          double cos_vs = dir[0] * sun[0] + dir[1] * sun[1] + dir[2] * sun[2];
          double phase = sl_sky_rayleigh_phase(cos_vs);
          for (int d = 0; d < 5; ++d) {
            double L[SL_SKY_SPECTRAL_COUNT], T[SL_SKY_SPECTRAL_COUNT];
            sl_sky_view_segment(&view, dir, 0.0, distances[d], L, T);
            for (int i = 0; i < atm.count; ++i) {
              ++evaluations;
              int ok = isfinite(L[i]) && L[i] >= 0.0 && T[i] >= 0.0 && T[i] <= 1.0 &&
                       L[i] <= phase * ((1.0 - T[i]) * (1.0 + 1e-12) + 4e-16); /* T rounds to 1 ulp */
              if (view.night && L[i] != 0.0) ok = 0;
              if (!ok) {
                if (bad < 10)
                  fprintf(stderr, "model %d eye %g sun %g view %g K %g nm %g: L %g T %g bound %g\n", model,
                          eyes[e], suns[s], el, distances[d], wl[i], L[i], T[i], phase * (1.0 - T[i]));
                ++bad;
              }
            }
          }
        }
      }
  }
  printf("stability sweep: %ld evaluations, %ld outside the bounds\n", evaluations, bad);
  CHECK(bad == 0);
  CHECK(night_ok);
  return sl_test_finish("test_sky_stability");
}
