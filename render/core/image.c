#include <math.h>
#include <stdlib.h>

#include "sl_image.h"

int sl_image_alloc(sl_image *img, int width, int height, sl_error *err)
{
  *img = (sl_image){0};
  if (width < 1 || height < 1 || width > 32768 || height > 32768)
    return sl_fail(err, SL_ERR_ARG, "image size %dx%d is out of range (1..32768)", width, height);
  const size_t n = (size_t)width * (size_t)height;
  img->rgba = calloc(4 * n, sizeof(float));
  img->depth = calloc(n, sizeof(float));
  img->transparency = malloc(n * sizeof(float));
  if (!img->rgba || !img->depth || !img->transparency) {
    sl_image_free(img);
    return sl_fail(err, SL_ERR_NOMEM, "out of memory for a %dx%d image", width, height);
  }
  for (size_t i = 0; i < n; ++i) img->transparency[i] = 1.0f;
  img->width = width;
  img->height = height;
  return SL_OK;
}

void sl_image_free(sl_image *img)
{
  free(img->rgba);
  free(img->depth);
  free(img->transparency);
  *img = (sl_image){0};
}

void sl_image_over(const sl_image *layer, const sl_image *background, sl_image *out)
{
  const size_t n = (size_t)layer->width * layer->height;
  for (size_t i = 0; i < n; ++i) {
    const float keep = layer->transparency[i];
    for (int c = 0; c < 3; ++c) out->rgba[4 * i + c] = layer->rgba[4 * i + c] + keep * background->rgba[4 * i + c];
    out->rgba[4 * i + 3] = layer->rgba[4 * i + 3];
    out->depth[i] = layer->depth[i];
    out->transparency[i] = layer->transparency[i];
  }
}

void sl_image_depth_over(const sl_image *layer, const sl_image *background, sl_image *out)
{
  const size_t n = (size_t)layer->width * layer->height;
  for (size_t i = 0; i < n; ++i) {
    const float behind = background->depth[i], front = layer->depth[i];
    if (!isfinite(behind)) {
      out->depth[i] = front;
      continue;
    }
    /* The layer's own depth is weighted by the opacity each sample took from the ray; what it
     * let through (its transparency) stops at the background. */
    const float coverage = 1.0f - layer->transparency[i];
    out->depth[i] = isfinite(front) && coverage > 0.0f ? coverage * front + (1.0f - coverage) * behind : behind;
  }
}

int sl_image_compare(const sl_image *a, const sl_image *b, sl_image_metrics *m, sl_error *err)
{
  *m = (sl_image_metrics){0};
  if (a->width != b->width || a->height != b->height)
    return sl_fail(err, SL_ERR_ARG, "images differ in size: %dx%d and %dx%d", a->width, a->height, b->width,
                   b->height);
  const size_t n = (size_t)a->width * a->height;
  double se = 0.0, ref = 0.0, peak = 0.0;
  for (size_t i = 0; i < n; ++i) {
    int bad = 0;
    for (int c = 0; c < 3; ++c) bad |= !isfinite(a->rgba[4 * i + c]) || !isfinite(b->rgba[4 * i + c]);
    if (bad) {
      m->nonfinite++;
      continue;
    }
    for (int c = 0; c < 3; ++c) {
      const double d = (double)a->rgba[4 * i + c] - b->rgba[4 * i + c];
      se += d * d;
      ref += (double)b->rgba[4 * i + c] * b->rgba[4 * i + c];
      if (fabs(d) > m->max_abs_diff) m->max_abs_diff = fabs(d);
      if (b->rgba[4 * i + c] > peak) peak = b->rgba[4 * i + c];
    }
  }
  m->relative_rmse = ref > 0.0 ? sqrt(se / ref) : (se > 0.0 ? INFINITY : 0.0);
  const double mse = se / (3.0 * (double)n);
  m->psnr_db = mse > 0.0 ? 10.0 * log10(peak * peak / mse) : INFINITY;
  return SL_OK;
}

int sl_image_diff_rgb8(const sl_image *a, const sl_image *b, double scale, unsigned char *rgb)
{
  const size_t n = (size_t)a->width * a->height;
  if (!(scale > 0.0)) {
    scale = 0.0;
    for (size_t i = 0; i < n; ++i) {
      double d = 0.0;
      for (int c = 0; c < 3; ++c) d += fabs((double)a->rgba[4 * i + c] - b->rgba[4 * i + c]) / 3.0;
      if (isfinite(d) && d > scale) scale = d;
    }
    if (!(scale > 0.0)) scale = 1.0;
  }
  for (size_t i = 0; i < n; ++i) {
    double d = 0.0;
    for (int c = 0; c < 3; ++c) d += fabs((double)a->rgba[4 * i + c] - b->rgba[4 * i + c]) / 3.0;
    double x = isfinite(d) ? d / scale : 1.0;
    x = x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x;
    /* Three ramps: red rises first, then green, then blue. */
    const double r = fmin(1.0, 3.0 * x), g = fmin(1.0, fmax(0.0, 3.0 * x - 1.0)), bl = fmax(0.0, 3.0 * x - 2.0);
    rgb[3 * i + 0] = (unsigned char)lrint(255.0 * r);
    rgb[3 * i + 1] = (unsigned char)lrint(255.0 * g);
    rgb[3 * i + 2] = (unsigned char)lrint(255.0 * bl);
  }
  return SL_OK;
}
