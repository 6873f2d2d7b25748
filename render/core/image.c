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
  if (!img->rgba || !img->depth) {
    sl_image_free(img);
    return sl_fail(err, SL_ERR_NOMEM, "out of memory for a %dx%d image", width, height);
  }
  img->width = width;
  img->height = height;
  return SL_OK;
}

void sl_image_free(sl_image *img)
{
  free(img->rgba);
  free(img->depth);
  *img = (sl_image){0};
}

void sl_image_over(const sl_image *layer, const sl_image *background, sl_image *out)
{
  const size_t n = (size_t)layer->width * layer->height;
  for (size_t i = 0; i < n; ++i) {
    const float keep = 1.0f - layer->rgba[4 * i + 3];
    for (int c = 0; c < 3; ++c) out->rgba[4 * i + c] = layer->rgba[4 * i + c] + keep * background->rgba[4 * i + c];
    out->rgba[4 * i + 3] = layer->rgba[4 * i + 3];
    out->depth[i] = layer->depth[i];
  }
}
