/* Skylight mode (issue 7, item 2) by a conservation law: a non-absorbing cloud inside a sky of
 * uniform radiance, with no sun, is invisible. Every direction brings L_sky, scattering only
 * redistributes it, so the frame (volume layer over the sky) equals L_sky everywhere; the layer
 * itself is (1 - T_vol) L_sky. Checked pixel by pixel within 4 standard errors, on an open-sided
 * lumpy cloud with a forward-peaked phase function. */
#include <math.h>
#include <stdio.h>

#include "sl_reference.h"
#include "sl_testing.h"

int main(void)
{
  float rho[125];
  for (int i = 0; i < 125; ++i) rho[i] = (float)(1.0 + sin(0.9 * i));
  sl_ref_medium_desc d;
  sl_ref_medium_desc_defaults(&d);
  d.n[0] = d.n[1] = d.n[2] = 5;
  d.spacing[0] = d.spacing[1] = d.spacing[2] = 0.2;
  d.origin[0] = d.origin[1] = d.origin[2] = 0.1;
  d.component[0].density = rho;
  d.component[0].sigma[0] = 4.0;
  d.component[0].albedo[0] = 1.0;
  d.component[0].phase[0].kind = SL_REF_PHASE_HG;
  d.component[0].phase[0].g = 0.8;
  sl_error err = {0};
  sl_ref_medium *m = sl_ref_medium_create(&d, &err);
  CHECK_MSG(m != NULL, err.message);
  if (!m) return sl_test_finish("test_ref_skylight");
  sl_ref_scene sc;
  sl_ref_scene_defaults(&sc);
  sc.medium = m;
  sc.sun_irradiance[0] = 0.0;
  sc.sky_radiance[0] = 0.25;
  sc.skylight = 1;
  sc.seed = 5;
  const int W = 6, H = 5;
  sl_camera cam = {{0.5, -2.5, 1.2}, {0.5, 0.5, 0.5}, {0, 0, 1}, 30.0, W, H, NULL};
  sl_ref_accum acc;
  CHECK(sl_ref_accum_init(&acc, W, H, 1, &err) == SL_OK);
  sl_ref_budget b = {4000, 0.0, NULL, NULL};
  CHECK(sl_ref_render(&sc, &cam, &b, &acc, &err) == SL_OK);
  sl_image layer, background, frame;
  float se[3 * 30];
  CHECK(sl_image_alloc(&layer, W, H, &err) == SL_OK && sl_image_alloc(&background, W, H, &err) == SL_OK &&
        sl_image_alloc(&frame, W, H, &err) == SL_OK);
  CHECK(sl_ref_accum_image(&acc, m, &layer, se, &err) == SL_OK);
  CHECK(sl_ref_background(&sc, &cam, &background, &err) == SL_OK);
  sl_image_over(&layer, &background, &frame);
  int covered = 0;
  double worst = 0.0;
  for (int q = 0; q < W * H; ++q) {
    /* The transparency's own noise enters the frame through T L_sky: bound it with the layer's. */
    const double got = frame.rgba[4 * q], tol = 4.0 * (se[3 * q] + 0.25 * 0.02) + 1e-6;
    char what[128];
    snprintf(what, sizeof what, "pixel %d: frame %.5f (layer %.5f, T %.3f), sky 0.25", q, got, layer.rgba[4 * q],
             layer.transparency[q]);
    CHECK_MSG(fabs(got - 0.25) <= tol, what);
    if (fabs(got - 0.25) > worst) worst = fabs(got - 0.25);
    covered += layer.transparency[q] < 0.9f;
  }
  CHECK_MSG(covered >= 6, "the cloud covers part of the frame");
  printf("worst deviation from the sky %.2e of 0.25 over %d covered pixels\n", worst, covered);
  sl_image_free(&layer), sl_image_free(&background), sl_image_free(&frame);
  sl_ref_accum_free(&acc);
  sl_ref_medium_destroy(m);
  return sl_test_finish("test_ref_skylight");
}
