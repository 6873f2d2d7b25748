/* Statistics of the fast model against the Monte Carlo reference (sl_validation.h). */
#include "sl_validation.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sl_error_sums_add(sl_error_sums *e, double a, double b, double se)
{
  e->d2 += (a - b) * (a - b), e->b2 += b * b, e->d1 += fabs(a - b), e->b1 += fabs(b), e->d += a - b;
  e->se2 += se * se, e->se1 += se;
}

double sl_error_relative_rmse(const sl_error_sums *e) { return e->b2 > 0 ? sqrt(e->d2 / e->b2) : 0.0; }
double sl_error_mean_relative(const sl_error_sums *e) { return e->b1 > 0 ? e->d1 / e->b1 : 0.0; }
double sl_error_bias(const sl_error_sums *e) { return e->b1 > 0 ? e->d / e->b1 : 0.0; }
double sl_error_noise_rmse(const sl_error_sums *e) { return e->b2 > 0 ? sqrt(e->se2 / e->b2) : 0.0; }
double sl_error_noise_mean(const sl_error_sums *e) { return e->b1 > 0 ? sqrt(2.0 / M_PI) * e->se1 / e->b1 : 0.0; }

double sl_error_model_rmse(const sl_error_sums *e)
{
  return e->b2 > 0 ? sqrt(fmax(0.0, e->d2 - e->se2) / e->b2) : 0.0;
}

int sl_block_means(const sl_image *img, const float *se, int b, sl_blocks *out, sl_error *err)
{
  memset(out, 0, sizeof *out);
  if (b < 1 || img->width < b || img->height < b)
    return sl_fail(err, SL_ERR_ARG, "blocks of %d pixels do not fit a %dx%d image", b, img->width, img->height);
  out->width = img->width / b, out->height = img->height / b;
  const size_t n = (size_t)out->width * out->height;
  out->rgb = calloc(3 * n, sizeof(double));
  out->se = calloc(3 * n, sizeof(double));
  out->transparency = calloc(n, sizeof(double));
  if (!out->rgb || !out->se || !out->transparency) {
    sl_blocks_free(out);
    return sl_fail(err, SL_ERR_NOMEM, "out of memory for %zu blocks", n);
  }
  const double inv = 1.0 / ((double)b * b);
  for (int by = 0; by < out->height; ++by)
    for (int bx = 0; bx < out->width; ++bx) {
      const size_t k = (size_t)by * out->width + bx;
      for (int y = by * b; y < (by + 1) * b; ++y)
        for (int x = bx * b; x < (bx + 1) * b; ++x) {
          const size_t q = (size_t)y * img->width + x;
          for (int c = 0; c < 3; ++c) {
            out->rgb[3 * k + c] += inv * img->rgba[4 * q + c];
            if (se) out->se[3 * k + c] += inv * inv * (double)se[3 * q + c] * se[3 * q + c];
          }
          out->transparency[k] += inv * img->transparency[q];
        }
      for (int c = 0; c < 3; ++c) out->se[3 * k + c] = sqrt(out->se[3 * k + c]);
    }
  return SL_OK;
}

void sl_blocks_free(sl_blocks *blocks)
{
  free(blocks->rgb), free(blocks->se), free(blocks->transparency);
  memset(blocks, 0, sizeof *blocks);
}

double sl_equal_error_seconds(double ref_seconds, double noise, double error)
{
  return error > 0 ? ref_seconds * (noise / error) * (noise / error) : INFINITY;
}

void sl_pareto_front(int n, const double *seconds, const double *error, unsigned char *on_front)
{
  for (int i = 0; i < n; ++i) {
    on_front[i] = 1;
    for (int j = 0; j < n && on_front[i]; ++j)
      if ((seconds[j] <= seconds[i] && error[j] < error[i]) || (seconds[j] < seconds[i] && error[j] <= error[i]))
        on_front[i] = 0;
  }
}

void sl_error_map(const sl_blocks *a, const sl_blocks *b, const unsigned char *cls, double floor, double range,
                  unsigned char *rgb)
{
  const size_t n = (size_t)a->width * a->height;
  memset(rgb, 40, 3 * n);
  for (size_t q = 0; q < n; ++q) {
    if (!cls[q]) continue;
    double sa = 0, sb = 0;
    for (int c = 0; c < 3; ++c) sa += a->rgb[3 * q + c], sb += b->rgb[3 * q + c];
    const double e = fmax(-1.0, fmin(1.0, (sa - sb) / fmax(sb, floor) / range));
    const double w = 1.0 - fabs(e);
    unsigned char *p = rgb + 3 * q;
    p[0] = (unsigned char)lround(255 * (e > 0 ? 1.0 : w));
    p[1] = (unsigned char)lround(255 * w);
    p[2] = (unsigned char)lround(255 * (e < 0 ? 1.0 : w));
  }
}
