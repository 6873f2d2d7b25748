/* Results do not depend on the number of threads (DESIGN.md): the same seed gives bitwise the
 * same fluxes and images with one thread and with three. And a different seed gives a different
 * estimate (the seed is used). */
#include <math.h>
#include <omp.h>
#include <string.h>

#include "sl_reference.h"
#include "sl_testing.h"

static void run(const sl_ref_medium *m, int threads, unsigned long long seed, sl_ref_fluxes_result *f, double *img)
{
  omp_set_num_threads(threads);
  sl_error err = {0};
  sl_ref_flux_options o;
  sl_ref_flux_options_defaults(&o);
  o.sun_zenith_deg = 30.0, o.photons = 5000, o.seed = seed;
  CHECK(sl_ref_fluxes(m, &o, f, &err) == SL_OK);
  sl_ref_scene sc;
  sl_ref_scene_defaults(&sc);
  sc.medium = m;
  sc.sun_direction[0] = 0.5, sc.sun_direction[2] = 0.8;
  sc.sky_radiance[0] = 0.1, sc.skylight = 1, sc.seed = seed;
  sl_camera cam = {{0.5, -3.0, 2.0}, {0.5, 0.5, 0.5}, {0, 0, 1}, 40.0, 8, 6, NULL};
  sl_ref_accum acc;
  CHECK(sl_ref_accum_init(&acc, 8, 6, 1, &err) == SL_OK);
  sl_ref_budget b = {16, 0.0, NULL, NULL};
  CHECK(sl_ref_render(&sc, &cam, &b, &acc, &err) == SL_OK);
  memcpy(img, acc.sum, 48 * sizeof(double));
  sl_ref_accum_free(&acc);
}

int main(void)
{
  /* A lumpy 4x4x4 cloud, open sides. */
  float rho[64];
  for (int i = 0; i < 64; ++i) rho[i] = (float)(1.0 + sin(1.7 * i));
  sl_ref_medium_desc d;
  sl_ref_medium_desc_defaults(&d);
  d.n[0] = d.n[1] = d.n[2] = 4;
  d.spacing[0] = d.spacing[1] = d.spacing[2] = 0.25;
  d.origin[0] = d.origin[1] = d.origin[2] = 0.125;
  d.component[0].density = rho;
  d.component[0].sigma[0] = 3.0;
  d.component[0].albedo[0] = 0.95;
  d.component[0].phase[0].kind = SL_REF_PHASE_HG;
  d.component[0].phase[0].g = 0.7;
  d.majorant_block = 2;
  sl_error err = {0};
  sl_ref_medium *m = sl_ref_medium_create(&d, &err);
  CHECK_MSG(m != NULL, err.message);
  if (!m) return sl_test_finish("test_ref_threads");
  sl_ref_fluxes_result f1, f3, f_other;
  double i1[48], i3[48], i_other[48];
  run(m, 1, 5, &f1, i1);
  run(m, 3, 5, &f3, i3);
  run(m, 2, 6, &f_other, i_other);
  CHECK(f1.reflectance == f3.reflectance && f1.transmittance == f3.transmittance && f1.side == f3.side &&
        f1.absorptance == f3.absorptance && f1.se_reflectance == f3.se_reflectance);
  CHECK(memcmp(i1, i3, sizeof i1) == 0);
  CHECK(f1.reflectance != f_other.reflectance);
  CHECK(memcmp(i1, i_other, sizeof i1) != 0);
  /* Open sides: energy leaves through them too, and still sums to 1 within the noise. */
  const double se = f1.se_reflectance + f1.se_transmittance + f1.se_absorptance + f1.se_side;
  CHECK(f1.side > 0.0);
  CHECK(fabs(f1.reflectance + f1.transmittance + f1.absorptance + f1.side - 1.0) <= 4.0 * se);
  sl_ref_medium_destroy(m);
  return sl_test_finish("test_ref_threads");
}
