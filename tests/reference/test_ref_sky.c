/* The single-scattering limit against the sky's closed form: an exponential Rayleigh atmosphere
 * given to the path tracer as a medium (1000 levels of 100 m, periodic sides 200 km apart), rendered with at
 * most one scattering, must give render/sky's corrected eqs. 14-15 (sl_sky_inscatter, flat
 * earth, which docs/SKY.md checks against quadrature to 1e-12) within the Monte Carlo noise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "sl_reference.h"
#include "sl_testing.h"

int main(int argc, char **argv)
{
  const long scale = argc > 1 && atol(argv[1]) > 0 ? atol(argv[1]) : 1;
  const double H = 8000.0, wl[3] = {650.0, 515.0, 440.0};
  const int nz = 1000;
  float *density = malloc(nz * sizeof(float));
  for (int k = 0; k < nz; ++k) density[k] = (float)exp(-(50.0 + 100.0 * k) / H);
  sl_ref_medium_desc d;
  sl_ref_medium_desc_defaults(&d);
  d.n[2] = nz;
  d.spacing[0] = d.spacing[1] = 200000.0; /* wide: few crossings of the periodic sides */
  d.spacing[2] = 100.0;
  d.origin[2] = 50.0; /* the box spans 0..100 km */
  d.n_wavelengths = 3;
  d.lateral = SL_REF_PERIODIC;
  d.component[0].density = density;
  double beta[3];
  for (int w = 0; w < 3; ++w) {
    d.wavelength_nm[w] = wl[w];
    beta[w] = sl_rayleigh_beta_standard_air(wl[w]);
    d.component[0].sigma[w] = beta[w];
    d.component[0].albedo[w] = 1.0;
    d.component[0].phase[w].kind = SL_REF_PHASE_RAYLEIGH;
  }
  sl_error err = {0};
  sl_ref_medium *m = sl_ref_medium_create(&d, &err);
  CHECK_MSG(m != NULL, err.message);
  if (!m) return sl_test_finish("test_ref_sky");

  sl_ref_scene sc;
  sl_ref_scene_defaults(&sc);
  sc.medium = m;
  sc.max_scatter = 1;
  const double sun_elev = 30.0 * M_PI / 180.0;
  sc.sun_direction[0] = 0.0, sc.sun_direction[1] = cos(sun_elev), sc.sun_direction[2] = sin(sun_elev);
  sc.seed = 3;
  /* Three pixels from 6 to 26 degrees of elevation, looking east (90 degrees from the sun). */
  sl_camera cam = {{0.0, 0.0, 1.0}, {cos(0.28), 0.0, 1.0 + sin(0.28)}, {0.0, 0.0, 1.0}, 20.0, 1, 3, NULL};
  sl_ref_accum acc;
  CHECK(sl_ref_accum_init(&acc, 1, 3, 3, &err) == SL_OK);
  sl_ref_budget b = {20000 * scale, 0.0, NULL, NULL};
  CHECK(sl_ref_render(&sc, &cam, &b, &acc, &err) == SL_OK);
  for (int py = 0; py < 3; ++py) {
    double dir[3];
    sl_camera_ray(&cam, 0, py, dir);
    const double cos_sun = dir[0] * sc.sun_direction[0] + dir[1] * sc.sun_direction[1] + dir[2] * sc.sun_direction[2];
    for (int w = 0; w < 3; ++w) {
      const double want = sl_sky_inscatter(beta[w], 1.0 / H, 1.0, dir[2], INFINITY, 1.0 / sin(sun_elev), cos_sun);
      const double n = (double)acc.samples, mean = acc.sum[py * 3 + w] / n;
      const double se = sqrt(fmax(0.0, acc.sum2[py * 3 + w] / n - mean * mean) / (n - 1.0));
      char what[160];
      snprintf(what, sizeof what, "view mu %.3f, %g nm: %.6e +- %.1e, closed form %.6e", dir[2], wl[w], mean, se, want);
      printf("%s\n", what);
      CHECK_MSG(fabs(mean - want) <= 4.0 * se + 1e-4 * want, what);
    }
  }
  sl_ref_accum_free(&acc);
  sl_ref_medium_destroy(m);
  free(density);
  return sl_test_finish("test_ref_sky");
}
