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

/* How a frame was made, written as OpenEXR header attributes: the standard worldToCamera and
 * worldToNDC (4x4, row vectors: p' = p M, camera looking down -z with +y up, NDC x and y in
 * [-1, 1] after the divide by w), and Stormlight's sunDirection (v3f, world ENU, toward the
 * sun) and stormlightScene (string). */
typedef struct sl_exr_metadata {
  int has_camera;
  float world_to_camera[16], world_to_ndc[16];
  int has_sun;
  float sun_direction[3];
  const char *scene;  /* may be NULL */
} sl_exr_metadata;

int sl_write_exr_meta(const char *path, const sl_image *img, sl_exr_precision precision,
                      const sl_exr_metadata *meta, sl_error *err);
/* Fills the matrices for a pinhole camera (position, target, up, vertical fov, aspect, near and
 * far clipping distances). */
void sl_exr_camera_matrices(const double position[3], const double target[3], const double up[3], double fov_deg,
                            double aspect, double near_m, double far_m, sl_exr_metadata *meta);
/* Reads R, G, B and, where present, A and Z; missing A reads as 1, missing Z as +inf. */
int sl_read_exr(const char *path, sl_image *img, sl_error *err);

/* Tone mapping happens only here: 1 - exp(-exposure * L) per channel, then the sRGB curve. */
float sl_tonemap(float radiance, float exposure);
/* Writes an 8-bit sRGB PNG of the RGB channels. */
int sl_write_png(const char *path, const sl_image *img, float exposure, sl_error *err);
/* The tone-mapped 8-bit sRGB that sl_write_png writes: 3 bytes per pixel, rows from the top. */
void sl_image_to_srgb8(const sl_image *img, float exposure, unsigned char *rgb);
/* Writes an 8-bit sRGB PNG from 8-bit RGB rows (top first), used for plots and difference maps. */
int sl_write_png_rgb8(const char *path, int width, int height, const unsigned char *rgb, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
