/* A linear HDR image: premultiplied RGBA in float (radiance relative to a top-of-atmosphere
 * sun of irradiance 1 per channel) plus a depth channel, rows from the top. */
#ifndef SL_IMAGE_H
#define SL_IMAGE_H

#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sl_image {
  int width, height;
  float *rgba;   /* 4 floats per pixel, row-major, row 0 at the top */
  float *depth;  /* distance along the view axis to the opacity-weighted depth of what the pixel
                    shows (the volume's; a background's: its ground); +inf where only sky */
  float *transparency; /* exp(-tau) toward the eye, kept apart from alpha = 1 - transparency, which
                          cannot hold a transparency below float's epsilon (tau > ~16) */
} sl_image;

int sl_image_alloc(sl_image *img, int width, int height, sl_error *err);
void sl_image_free(sl_image *img);
/* out = layer + layer.transparency * background for premultiplied RGBA ("over"); out's alpha is
 * the layer's coverage and its depth and transparency the layer's. out may alias layer. */
void sl_image_over(const sl_image *layer, const sl_image *background, sl_image *out);

/* out's depth = the opacity-weighted depth of the layer in front of an opaque background: the
 * layer's depth weighted by its coverage 1 - T plus the background's depth weighted by T, where the
 * background's depth is finite (ground, terrain); the layer's depth where it is not (sky). out may
 * alias either. */
void sl_image_depth_over(const sl_image *layer, const sl_image *background, sl_image *out);

typedef struct sl_image_metrics {
  double relative_rmse;  /* sqrt(sum (a-b)^2 / sum b^2) over R, G, B */
  double max_abs_diff;   /* largest |a-b| over R, G, B */
  double psnr_db;        /* 10 log10(peak^2 / MSE), peak = the reference's largest RGB value */
  long nonfinite;        /* pixels where either image is NaN or Inf */
} sl_image_metrics;

/* Compares image a with reference b on linear HDR RGB. Sizes must match. */
int sl_image_compare(const sl_image *a, const sl_image *b, sl_image_metrics *m, sl_error *err);
/* False-colour map of |a-b| (RGB mean), 8-bit RGB rows top first, black -> red -> yellow -> white
 * with white at `scale` (<= 0 picks the largest difference). */
int sl_image_diff_rgb8(const sl_image *a, const sl_image *b, double scale, unsigned char *rgb_out);

#ifdef __cplusplus
}
#endif
#endif
