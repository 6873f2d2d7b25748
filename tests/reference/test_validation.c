/* The validation statistics (render/reference/validation.c) against values known without them:
 * a uniform 10 % excess, Gaussian noise of known sigma (mean |noise| = sqrt(2/pi) sigma, by the law
 * of large numbers), block means of a known image and the quadrature of standard errors, a Pareto
 * front by hand, the 1/spp law of equal error, the error map's end colours. */
#include <math.h>
#include <stdlib.h>

#include "sl_testing.h"
#include "sl_validation.h"

static double gauss(unsigned long long *state)
{
  /* Box-Muller over a 64-bit LCG (Knuth's MMIX constants): enough for a mean of 10^6 draws. */
  double u[2];
  for (int k = 0; k < 2; ++k) {
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    u[k] = ((*state >> 11) + 0.5) / 9007199254740992.0;
  }
  return sqrt(-2.0 * log(u[0])) * cos(2.0 * M_PI * u[1]);
}

int main(void)
{
  /* 10 % too bright everywhere, the reference's noise 5 % of each value. */
  sl_error_sums e = {0};
  for (int i = 1; i <= 100; ++i) sl_error_sums_add(&e, 1.1 * i, i, 0.05 * i);
  CHECK_CLOSE(sl_error_relative_rmse(&e), 0.1, 1e-12, 0);
  CHECK_CLOSE(sl_error_mean_relative(&e), 0.1, 1e-12, 0);
  CHECK_CLOSE(sl_error_bias(&e), 0.1, 1e-12, 0);
  CHECK_CLOSE(sl_error_noise_rmse(&e), 0.05, 1e-12, 0);
  CHECK_CLOSE(sl_error_model_rmse(&e), sqrt(0.01 - 0.0025), 1e-12, 0);
  sl_error_sums darker = {0};
  sl_error_sums_add(&darker, 0.8, 1.0, 0.0);
  CHECK_CLOSE(sl_error_bias(&darker), -0.2, 1e-12, 0);
  const sl_error_sums none = {0};
  CHECK(sl_error_relative_rmse(&none) == 0.0 && sl_error_model_rmse(&none) == 0.0);

  /* A perfect model against a noisy reference: what the error measures is the noise, as
   * noise_rmse and noise_mean predict. */
  sl_error_sums g = {0};
  unsigned long long state = 12345;
  const double sigma = 0.03;
  for (int i = 0; i < 1000000; ++i) sl_error_sums_add(&g, 1.0, 1.0 + sigma * gauss(&state), sigma);
  CHECK_CLOSE(sl_error_mean_relative(&g), sl_error_noise_mean(&g), 3e-3, 0);
  CHECK_CLOSE(sl_error_relative_rmse(&g), sl_error_noise_rmse(&g), 5e-3, 0);
  CHECK(sl_error_model_rmse(&g) < 0.1 * sigma);

  /* Block means of a 5 x 4 image in 2 x 2 blocks: 2 x 2 blocks, the fifth column dropped. */
  sl_image img;
  sl_error err = {0};
  CHECK(sl_image_alloc(&img, 5, 4, &err) == SL_OK);
  float se[3 * 20];
  for (int q = 0; q < 20; ++q) {
    for (int c = 0; c < 3; ++c) img.rgba[4 * q + c] = (float)(q + c), se[3 * q + c] = 0.4f;
    img.transparency[q] = q % 2 ? 1.0f : 0.0f;
  }
  sl_blocks b;
  CHECK(sl_block_means(&img, se, 2, &b, &err) == SL_OK);
  CHECK(b.width == 2 && b.height == 2);
  /* Block (1, 1): pixels (2,2), (3,2), (2,3), (3,3) = q 12, 13, 17, 18; channel 1 adds 1. */
  CHECK_CLOSE(b.rgb[3 * 3 + 1], (12 + 13 + 17 + 18) / 4.0 + 1.0, 1e-12, 0);
  CHECK_CLOSE(b.transparency[3], 0.5, 1e-12, 0);
  CHECK_CLOSE(b.se[3 * 3 + 2], 0.4 / 2.0, 1e-6, 0); /* sqrt(4 s^2) / 4 */
  sl_blocks_free(&b);
  CHECK(sl_block_means(&img, se, 6, &b, &err) == SL_ERR_ARG);
  sl_image_free(&img);

  /* Speed against error. */
  const double seconds[] = {1.0, 2.0, 1.5, 3.0, 0.5, 1.0};
  const double error[] = {0.5, 0.3, 0.6, 0.3, 0.9, 0.5};
  unsigned char front[6];
  sl_pareto_front(6, seconds, error, front);
  const unsigned char want[] = {1, 1, 0, 0, 1, 1}; /* (1, 0.5) twice: neither beats the other */
  for (int i = 0; i < 6; ++i) CHECK(front[i] == want[i]);
  CHECK_CLOSE(sl_equal_error_seconds(100.0, 0.01, 0.1), 1.0, 1e-12, 0);
  CHECK(isinf(sl_equal_error_seconds(100.0, 0.01, 0.0)));

  /* The error map: equal is white, +range red, -range blue, no volume grey. */
  double ra[12] = {1, 1, 1, 1.5, 1.5, 1.5, 0.5, 0.5, 0.5, 9, 9, 9}, rb[12] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  sl_blocks a = {4, 1, ra, NULL, NULL}, r = {4, 1, rb, NULL, NULL};
  const unsigned char cls[4] = {1, 1, 1, 0};
  unsigned char rgb[12];
  sl_error_map(&a, &r, cls, 0.01, 0.5, rgb);
  CHECK(rgb[0] == 255 && rgb[1] == 255 && rgb[2] == 255);
  CHECK(rgb[3] == 255 && rgb[4] == 0 && rgb[5] == 0);
  CHECK(rgb[6] == 0 && rgb[7] == 0 && rgb[8] == 255);
  CHECK(rgb[9] == 40 && rgb[10] == 40 && rgb[11] == 40);
  return sl_test_finish("test_validation");
}
