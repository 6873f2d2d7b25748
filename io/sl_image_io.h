/* Image files: OpenEXR (through OpenEXR's C API) for linear HDR, PNG for tone-mapped sRGB. */
#ifndef SL_IMAGE_IO_H
#define SL_IMAGE_IO_H

#include "sl_image.h"
#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sl_exr_precision { SL_EXR_HALF = 0, SL_EXR_FLOAT = 1 } sl_exr_precision;

/* Writes R, G, B, A in the given precision and Z (float) when img->depth is set. */
int sl_write_exr(const char *path, const sl_image *img, sl_exr_precision precision, sl_error *err);
/* Reads R, G, B and, where present, A and Z; missing A reads as 1, missing Z as +inf. */
int sl_read_exr(const char *path, sl_image *img, sl_error *err);

/* Tone mapping happens only here: 1 - exp(-exposure * L) per channel, then the sRGB curve. */
float sl_tonemap(float radiance, float exposure);
/* Writes an 8-bit sRGB PNG of the RGB channels. */
int sl_write_png(const char *path, const sl_image *img, float exposure, sl_error *err);
/* Writes an 8-bit sRGB PNG from 8-bit RGB rows (top first), used for plots and difference maps. */
int sl_write_png_rgb8(const char *path, int width, int height, const unsigned char *rgb, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
