/* The fast model measured against the Monte Carlo reference: error sums over a class of pixels
 * (relative RMSE, mean relative error, bias, and what the reference's own noise contributes),
 * images averaged over pixel blocks, the time Monte Carlo needs for the same error, and the
 * Pareto front of speed against error. `stormlight validate` reports these (docs/ACCURACY.md). */
#ifndef SL_VALIDATION_H
#define SL_VALIDATION_H

#include "sl_image.h"
#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Sums over a class's pixels and channels of the model a against the reference b with the
 * reference's standard error se. */
typedef struct sl_error_sums {
  long pixels;
  double d2, b2, d1, b1, d, se2, se1; /* (a-b)^2, b^2, |a-b|, |b|, a-b, se^2, se */
} sl_error_sums;

void sl_error_sums_add(sl_error_sums *e, double a, double b, double se);
/* sqrt(sum (a-b)^2 / sum b^2) */
double sl_error_relative_rmse(const sl_error_sums *e);
/* Radiance-weighted mean relative error, sum |a-b| / sum |b|. */
double sl_error_mean_relative(const sl_error_sums *e);
/* sum (a-b) / sum |b|: the sign says brighter or darker. */
double sl_error_bias(const sl_error_sums *e);
/* What a perfect model would show against this reference: the reference's relative RMS standard
 * error, and its expected share of the mean absolute error (sqrt(2/pi) se for Gaussian noise). */
double sl_error_noise_rmse(const sl_error_sums *e);
double sl_error_noise_mean(const sl_error_sums *e);
/* The model's own relative RMSE with the reference's noise taken out (squares subtract). */
double sl_error_model_rmse(const sl_error_sums *e);

/* An image averaged over b x b pixel blocks (a last partial row or column of blocks dropped):
 * radiance and transparency are means; per-pixel standard errors (3 per pixel, or NULL) combine in
 * quadrature into the mean's. Blocks lower the reference's noise by b where the model's errors are
 * smoother than a pixel. */
typedef struct sl_blocks {
  int width, height;
  double *rgb, *se, *transparency; /* 3, 3 and 1 per block */
} sl_blocks;
int sl_block_means(const sl_image *img, const float *se, int b, sl_blocks *out, sl_error *err);
void sl_blocks_free(sl_blocks *blocks);

/* The seconds Monte Carlo needs to reach relative error `error` when ref_seconds gave relative
 * noise `noise`: its variance falls as 1/spp, so ref_seconds (noise / error)^2; INFINITY at 0. */
double sl_equal_error_seconds(double ref_seconds, double noise, double error);

/* on_front[i] = 1 where no other point is at least as fast and as accurate and better in one of
 * the two (seconds, error): the Pareto front of speed against error. */
void sl_pareto_front(int n, const double *seconds, const double *error, unsigned char *on_front);

/* The signed relative error of each block's R+G+B (model a against reference b, below floor
 * taken as floor) as a colour: blue (too dark) through white to red (too bright), saturating at
 * +-range; blocks whose class is 0 (no volume) dark grey. rgb: 3 bytes per block. */
void sl_error_map(const sl_blocks *a, const sl_blocks *b, const unsigned char *cls, double floor, double range,
                  unsigned char *rgb);

#ifdef __cplusplus
}
#endif
#endif
