/* Everything between a storm file and a renderer, once, for every front end (render, view,
 * validate, reference, series, the Python module): the storm loaded and placed at its time, the
 * sun (given angles, a date, or the file's own time over the grid's centre), the air, the particle
 * tables of the fields present, the renderer's scene and the CPU renderer; and the camera as
 * render frames it. Plan once (sl_scene_build), render many (sl_renderer_render). */
#ifndef SL_SCENE_BUILD_H
#define SL_SCENE_BUILD_H

#include "sl_camera.h"
#include "sl_optics.h"
#include "sl_renderer.h"
#include "sl_settings.h"
#include "sl_sky.h"
#include "sl_storm.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sl_built_scene {
  sl_storm_frame frame;  /* the storm at its time, placed (docs/GEOREFERENCING.md) */
  int have_frame;
  sl_atmosphere atmosphere; /* unused with no_atmosphere */
  sl_optics_tables *optics; /* NULL for the low-albedo model, which reads none */
  sl_scene scene;           /* the renderer's: volume, air, tables, sun, slicing, lighting */
  sl_renderer *renderer;    /* the CPU renderer (sl_scene_build), or NULL */
  double sun_elevation_deg, sun_azimuth_deg; /* compass azimuth, degrees */
  int sun_from_time;        /* the sun is the solar position at sun_time (not given angles) */
  sl_utc sun_time;
  double load_seconds;      /* reading and resampling the storm */
} sl_built_scene;

typedef struct sl_build_options {
  int for_gpu;              /* the GPU pass carries at most SL_GPU_MAX_FIELDS fields */
  int no_renderer;          /* stop after the scene (air, tables): the caller creates renderers */
  sl_optics_progress_fn tables_progress;   /* optional: the tables' build */
  void *tables_progress_user;
  void (*render_progress)(void *user, double fraction); /* optional: sl_scene.progress */
  void *render_progress_user;
} sl_build_options;

/* The load options the settings give (time, dz, fields, sizes, region, levels, stride, memory,
 * placement); for_gpu caps the fields. The field names point into s. */
void sl_settings_load_options(const sl_settings *s, int for_gpu, sl_load_options *out);

/* Loads the storm and places the sun (b zeroed first). Errors name the file; SL_ERR_ARG where the
 * settings cannot place the sun (no times in the file, no latitude): the caller's usage error. */
int sl_scene_load(const sl_settings *s, int for_gpu, sl_built_scene *b, sl_error *err);
/* The air of the scene at rgb or spectral wavelengths: the flat or round earth's air mass, and
 * with curvature drop the round ground the storm stands on (the horizon). */
int sl_scene_air(const sl_settings *s, int spectral, sl_atmosphere *atm, sl_error *err);
/* The particle tables of volume v's fields at rgb or spectral wavelengths; max_order 0: each
 * type's own (cached on disk). NULL with err on failure. */
sl_optics_tables *sl_scene_tables(const sl_volume *v, int spectral, int max_order, sl_optics_progress_fn progress,
                                  void *progress_user, sl_error *err);
/* The flat ground's albedo (sl_scene.ground_albedo, without --terrain): ground-albedo where given,
 * else the domain's mean of the file's ALBEDO, else of its land mask (land SL_LAND_ALBEDO, water
 * SL_WATER_ALBEDO), else the setting's default (land). */
double sl_scene_ground_albedo(const sl_settings *s, const sl_storm_frame *f);
/* The renderer's scene from the settings, over b's volume, air (NULL: none) and tables. */
void sl_scene_fill(const sl_settings *s, const sl_built_scene *b, const sl_atmosphere *air,
                   const sl_optics_tables *optics, sl_scene *out);
/* All of it: load, sun, air, tables, scene and (unless opt->no_renderer) the CPU renderer. On
 * failure b holds nothing to free. */
int sl_scene_build(const sl_settings *s, const sl_build_options *opt, sl_built_scene *b, sl_error *err);
void sl_built_scene_free(sl_built_scene *b);

/* The camera as render frames it. With none of view-azimuth, view-elevation, camera-position and
 * camera-target given: a storm chaser's view (sl_camera_chaser) of v's condensate (the columns of
 * vertical optical depth SL_CHASER_TAU or more, sl_volume_condensate_boxes) from SL_CHASER_EYE_M
 * above the grid's ground (or sea level), from the compass direction of the sun (unit vector sun,
 * the volume's axes) turned SL_CHASER_SUN_OFFSET_DEG; at night, without such columns, or for a
 * storm too wide to frame from the ground (a deck, a hurricane), the orbit below. Otherwise: the content bounds lo..hi (sl_renderer_content_bounds, or the reference
 * medium's, which are defined alike) seen from view-azimuth and view-elevation at fov, with
 * camera-position and camera-target where given. */
#define SL_CHASER_TAU 1.0
#define SL_CHASER_CORE_TAU 100.0
#define SL_CHASER_BETA 1e-4
#define SL_CHASER_EYE_M 2.0
#define SL_CHASER_SUN_OFFSET_DEG 30.0
void sl_scene_camera(const sl_settings *s, const sl_volume *v, const double lo[3], const double hi[3],
                     const double sun[3], sl_camera *cam);
/* Where each of cam's pixel rays meets the round ground of the scene's air (its ground_radius, set
 * with curvature drop), lowering opaque (width x height, distances along the rays; the terrain's or
 * INFINITY) to it, so that the volume draws nothing behind the horizon; returns 0 and leaves
 * opaque untouched without air or on flat ground. */
int sl_scene_ground_opaque(const sl_atmosphere *air, const sl_camera *cam, float *opaque);

#ifdef __cplusplus
}
#endif
#endif
