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
  float *depth;  /* distance along the view axis to the volume's opacity-weighted depth; +inf where empty */
} sl_image;

int sl_image_alloc(sl_image *img, int width, int height, sl_error *err);
void sl_image_free(sl_image *img);
/* out = layer + (1 - layer.alpha) * background for premultiplied RGBA ("over"); out's alpha is
 * the layer's coverage and its depth the layer's depth. out may alias layer. */
void sl_image_over(const sl_image *layer, const sl_image *background, sl_image *out);

#ifdef __cplusplus
}
#endif
#endif
