/* The reference and render/volume agree where their physics is the same: with single scattering,
 * an isotropic phase function and Table 2's cross-section (the fast renderer's low-albedo model,
 * Riley et al. 2004 Fig. 13), the two volume layers must match to the Monte Carlo noise plus the
 * slicer's discretisation (docs/DESIGN-NOTES.md: 0.1-0.2% on resolved grids). This checks that the
 * reference draws the same rays, splits the aerial perspective at the same plane and lights each
 * point with the same sunlight: the tiny end-to-end validation of issue 7 that runs in seconds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "sl_reference.h"
#include "sl_renderer.h"
#include "sl_testing.h"

int main(void)
{
  sl_error err = {0};
  sl_volume v;
  const int n = 16;
  const double origin[3] = {-500.0 + 31.25, -500.0 + 31.25, 2000.0 + 31.25}, spacing[3] = {62.5, 62.5, 62.5};
  CHECK(sl_volume_init(&v, n, n, n, origin, spacing, &err) == SL_OK);
  CHECK(sl_volume_add_field(&v, SL_CLOUD, &err) == SL_OK);
  const double sigma = sl_particle_properties(SL_CLOUD)->sigma_ext_m2;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = (i - 7.5) / 5.0, y = (j - 7.5) / 5.0, z = (k - 7.5) / 4.0;
        /* A blob of peak extinction 6e-3 m^-1: optical depth about 3 through the middle. */
        v.eta[SL_CLOUD][sl_volume_index(&v, i, j, k)] = (float)(6e-3 / sigma * exp(-(x * x + y * y + z * z)));
      }
  sl_atmosphere atm;
  CHECK(sl_atmosphere_init(&atm, sl_sky_rgb_wavelengths_nm, 3, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, &err) == SL_OK);
  double sun[3];
  sl_sun_direction(35.0, 120.0, sun);

  const int W = 24, H = 16;
  double lo[3], hi[3];
  sl_volume_bounds(&v, lo, hi);
  sl_camera cam;
  sl_camera_frame(lo, hi, 200.0, 15.0, 40.0, W, H, &cam);

  /* The fast renderer. */
  sl_scene fs = {0};
  fs.volume = &v;
  for (int a = 0; a < 3; ++a) fs.sun_direction[a] = sun[a];
  fs.atmosphere = &atm;
  fs.lighting = SL_LIGHTING_LOW_ALBEDO;
  sl_renderer *r = sl_renderer_create(&fs, &err);
  CHECK_MSG(r != NULL, err.message);
  sl_image fast, ref;
  CHECK(sl_image_alloc(&fast, W, H, &err) == SL_OK);
  CHECK(sl_image_alloc(&ref, W, H, &err) == SL_OK);
  if (r) CHECK(sl_renderer_render(r, &cam, &fast, NULL, &err) == SL_OK);

  /* The reference with the same physics. */
  sl_ref_medium_desc d;
  sl_ref_medium_desc_defaults(&d);
  d.n[0] = d.n[1] = d.n[2] = n;
  for (int a = 0; a < 3; ++a) d.origin[a] = origin[a], d.spacing[a] = spacing[a];
  d.n_wavelengths = 3;
  d.component[0].density = v.eta[SL_CLOUD];
  for (int w = 0; w < 3; ++w) {
    d.wavelength_nm[w] = sl_sky_rgb_wavelengths_nm[w];
    d.component[0].sigma[w] = sigma;
    d.component[0].albedo[w] = 1.0;
    d.component[0].phase[w].kind = SL_REF_PHASE_ISOTROPIC;
  }
  sl_ref_medium *m = sl_ref_medium_create(&d, &err);
  CHECK_MSG(m != NULL, err.message);
  sl_ref_scene sc;
  sl_ref_scene_defaults(&sc);
  sc.medium = m;
  for (int a = 0; a < 3; ++a) sc.sun_direction[a] = sun[a];
  sc.atmosphere = &atm;
  sc.max_scatter = 1;
  sc.seed = 9;
  sl_ref_accum acc;
  CHECK(sl_ref_accum_init(&acc, W, H, 3, &err) == SL_OK);
  sl_ref_budget b = {4096, 0.0, NULL, NULL};
  float *se = malloc((size_t)W * H * 3 * sizeof(float));
  if (m && sl_ref_render(&sc, &cam, &b, &acc, &err) == SL_OK) CHECK(sl_ref_accum_image(&acc, m, &ref, se, &err) == SL_OK);

  /* Relative RMSE of the layers against what the reference's own noise explains. */
  double diff2 = 0.0, ref2 = 0.0, noise2 = 0.0, tdiff = 0.0;
  for (int q = 0; q < W * H; ++q) {
    for (int c = 0; c < 3; ++c) {
      const double a = fast.rgba[4 * q + c], bref = ref.rgba[4 * q + c];
      diff2 += (a - bref) * (a - bref);
      ref2 += bref * bref;
      noise2 += (double)se[3 * q + c] * se[3 * q + c];
    }
    tdiff = fmax(tdiff, fabs(fast.transparency[q] - ref.transparency[q]));
  }
  const double rel = sqrt(diff2 / ref2), noise = sqrt(noise2 / ref2);
  char what[160];
  snprintf(what, sizeof what, "layer relative RMSE %.4f, reference noise %.4f, worst transparency difference %.4f",
           rel, noise, tdiff);
  printf("%s\n", what);
  CHECK_MSG(ref2 > 0.0, "the reference sees the cloud");
  /* With the fast renderer exact, rel equals the noise on average; a bias b adds in quadrature. */
  CHECK_MSG(rel <= 1.3 * noise + 0.005, what);
  CHECK_MSG(tdiff <= 0.05, what);

  free(se);
  sl_ref_accum_free(&acc);
  sl_ref_medium_destroy(m);
  sl_image_free(&fast);
  sl_image_free(&ref);
  sl_renderer_destroy(r);
  sl_volume_free(&v);
  return sl_test_finish("test_ref_vs_volume");
}
