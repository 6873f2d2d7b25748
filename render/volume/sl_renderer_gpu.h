/* What a GPU pass needs from a prepared CPU renderer to draw the same model: the lattice and
 * the per-field extinction, the light model (tables), the content box, the sunlight table for a
 * camera, and the CPU's own resolve of an eye accumulator (aerial perspective in front of the
 * volume, spectral-to-RGB). The GPU draws with the light volume's method (light_volume.c):
 * a sweep of the light state along the sun's dominant grid axis, then a ray-marched eye pass. */
#ifndef SL_RENDERER_GPU_H
#define SL_RENDERER_GPU_H

#include "sl_renderer.h"
#include "sl_sweep_geometry.h"

#ifdef __cplusplus
extern "C" {
#endif
#include "lighting.h" /* a C header without C++ guards */

#define SL_SUNLIGHT_TABLE_SIZE 257

typedef struct sl_renderer_gpu_inputs {
  const sl_light_model *model;
  int n[3];
  double origin[3], spacing[3];    /* the lattice: sample (i,j,k) sits at origin + (i,j,k) spacing */
  const float *fields;             /* extinction per present field, model->nf per sample, x fastest, m^-1 */
  double content_lo[3], content_hi[3], content_center[3];
  double sun_direction[3];        /* unit, toward the sun */
  sl_sweep_geometry sweep;        /* the light volume's sweep, as the CPU's */
  double termination_transparency;
  int march_samples;              /* eye samples per grid cell along a ray */
  int any_extinction;
  int skylight;                   /* the scene asks for the skylight term (render/volume/sky_light.h) */
  /* Its lattice, once sl_renderer_prepare_sky built it (sky_ready; sky NULL at night): per
   * sample beta M per wavelength then beta (four floats at three wavelengths), x fastest. */
  int sky_ready;
  const float *sky;
  int sky_n[3];
  double sky_origin[3], sky_spacing[3];
} sl_renderer_gpu_inputs;

void sl_renderer_gpu_inputs_get(const sl_renderer *r, sl_renderer_gpu_inputs *out);

/* Sunlight reaching altitudes z0 + i dz (i < SL_SUNLIGHT_TABLE_SIZE) through the air for this
 * camera's view of the sky (eq. 12), rows of model->nwl values; *night set when the sun is down.
 * Altitudes are sl_sky_altitude's: world z, or with *ground_radius R > 0 the height above the
 * sphere of radius R centred at (0, 0, -R). */
int sl_renderer_sunlight_table(const sl_renderer *r, const sl_camera *cam, double *rows, double *z0, double *dz,
                               double *ground_radius, int *night, sl_error *err);

/* The eye accumulator of a frame (rows from the top, `stride` floats per pixel: radiance per
 * wavelength, transparency toward the eye, opacity-weighted depth numerator) resolved into the
 * volume layer exactly as the CPU's light-volume pass resolves its own. */
int sl_renderer_resolve_accumulator(const sl_renderer *r, const sl_camera *cam, const float *acc, int stride,
                                    sl_image *img, sl_error *err);

/* What a resolve on the GPU needs per frame to compute, per pixel, what
 * sl_renderer_resolve_accumulator and sl_renderer_background compute on the CPU: the sky as seen
 * from this camera (sl_sky_view_init: the eye's height and vertical, the sun's air mass, the unit
 * sun), the air's constants per wavelength, the spectral-to-RGB rows, the constant background
 * without air, and the distance along the view axis from the eye to the content's midplane (the
 * light-volume pass's split between the front aerial perspective and the volume). */
typedef struct sl_renderer_gpu_sky {
  int has_atmosphere;              /* 0: no air, the background is sky_radiance, no aerial perspective */
  int nwl;
  double altitude, up[3];          /* the eye's height above the ground and its local vertical */
  double airmass;                  /* the sun's air mass at the eye; infinite at night */
  double sun[3];                   /* unit, toward the sun */
  double beta_sea_level[SL_MAX_WAVELENGTHS], sun_irradiance[SL_MAX_WAVELENGTHS];
  double inv_scale_height, ground_radius;
  double to_rgb[3 * SL_MAX_WAVELENGTHS]; /* row c: the weights of linear sRGB channel c */
  double sky_radiance[3];
  double mid_distance;             /* dot(forward, content centre - eye) */
  /* The lit ground (sl_scene.ground_albedo; after sl_renderer_prepare_sky): its radiance is
   * ground_sun * shadow + ground_sky, the shadow map's cell (i, j) centred at
   * shadow_origin + (i, j) shadow_spacing (world x, y), 1 off the map. */
  int ground_on;
  double ground_sun[SL_MAX_WAVELENGTHS], ground_sky[SL_MAX_WAVELENGTHS];
  const float *shadow;
  int shadow_n[2];
  double shadow_origin[2], shadow_spacing[2];
} sl_renderer_gpu_sky;

int sl_renderer_gpu_sky_get(const sl_renderer *r, const sl_camera *cam, sl_renderer_gpu_sky *out, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
