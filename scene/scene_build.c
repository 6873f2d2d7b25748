/* sl_scene_build: the storm, its sun, the air, the tables and the renderer, from one settings
 * struct, the same for every front end. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sl_geo.h"
#include "sl_georef.h"
#include "sl_scene_build.h"
#include "sl_terrain.h"

static double seconds_now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

void sl_settings_load_options(const sl_settings *s, int for_gpu, sl_load_options *out)
{
  memset(out, 0, sizeof *out);
  out->time_index = s->time_index;
  out->dz = s->dz;
  out->stride = s->stride;
  out->level_first = s->level_first, out->level_count = s->level_count;
  out->has_region = sl_settings_given(s, "region");
  memcpy(out->region, s->region, sizeof out->region);
  out->max_memory = s->max_memory;
  for (int t = 0; t < SL_PARTICLE_COUNT; ++t) out->field_variable[t] = s->field_variable[t][0] ? s->field_variable[t] : NULL;
  out->representative_particles = s->representative_particles;
  out->droplet_number_m3 = s->droplet_number_cm3 * 1e6;
  out->max_fields = s->max_fields;
  if (for_gpu && out->max_fields > SL_GPU_MAX_FIELDS) out->max_fields = SL_GPU_MAX_FIELDS;
  out->earth_curvature = s->curvature_drop;
  out->has_origin = sl_settings_given(s, "origin");
  out->origin_lat = s->origin[0], out->origin_lon = s->origin[1];
}

/* The UTC time the sun is placed at: the date given (a run that counts seconds from its start, as
 * CM1's, starts there and each time adds its seconds), else the file's own time at time_index. */
static int sun_time(const sl_settings *s, sl_utc *when, sl_error *err)
{
  sl_storm_info *info = malloc(sizeof *info);
  if (!info) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", s->data);
  sl_error info_err = {0};
  const int have_info = sl_storm_read_info(s->data, info, &info_err) == SL_OK;
  int rc = SL_OK;
  const int t = s->time_index;
  if (sl_settings_given(s, "date")) {
    *when = s->date;
    if (have_info && !info->has_times && info->has_elapsed && t >= 0 && t < info->ntimes && info->elapsed_s[t] != 0.0)
      rc = sl_utc_add_seconds(when, info->elapsed_s[t], err);
  } else if (!have_info || !info->has_times) {
    const char *cal = have_info ? info->calendar : "";
    if (!cal[0] || !strcmp(cal, "standard"))
      rc = sl_fail(err, SL_ERR_ARG, "%s: the file has no times: give a date or the sun's azimuth and elevation", s->data);
    else
      rc = sl_fail(err, SL_ERR_ARG,
                   "%s: the file has no times in a calendar this reader knows (calendar '%s'): give a date or the "
                   "sun's azimuth and elevation",
                   s->data, cal);
  } else {
    char text[40];
    snprintf(text, sizeof text, "%sZ", info->sun_times[t]);
    for (char *c = text; *c; ++c)
      if (*c == '_') *c = 'T';
    sl_error e = {0};
    if (sl_utc_parse_iso8601(text, when, &e))
      rc = sl_fail(err, SL_ERR_FORMAT, "%s: time '%s' is not a date-time: %s", s->data, info->times[t], e.message);
  }
  free(info);
  return rc;
}

int sl_scene_load(const sl_settings *s, int for_gpu, sl_built_scene *b, sl_error *err)
{
  memset(b, 0, sizeof *b);
  if (!s->data[0]) return sl_fail(err, SL_ERR_ARG, "no storm file");
  sl_load_options load;
  sl_settings_load_options(s, for_gpu, &load);
  const double t0 = seconds_now();
  if (sl_storm_load(s->data, &load, &b->frame, err)) return err->code;
  b->have_frame = 1;
  b->load_seconds = seconds_now() - t0;
  if (sl_settings_given(s, "sun-azimuth")) {
    b->sun_elevation_deg = s->sun_elevation_deg, b->sun_azimuth_deg = s->sun_azimuth_deg;
    return SL_OK;
  }
  int rc = sun_time(s, &b->sun_time, err);
  if (!rc && !(isfinite(b->frame.center_lat) && isfinite(b->frame.center_lon)))
    rc = sl_fail(err, SL_ERR_ARG,
                 "%s: the grid has no latitude and longitude (CM1, a WRF idealized run with MAP_PROJ 0 and no --origin, "
                 "or a projected CF grid without 2-D lat/lon or a projection origin): give the sun's azimuth and "
                 "elevation",
                 s->data);
  sl_solar_position pos;
  if (!rc) rc = sl_solar_position_compute(&b->sun_time, b->frame.center_lat, b->frame.center_lon, NULL, &pos, err);
  if (rc) {
    sl_built_scene_free(b);
    return rc;
  }
  b->sun_elevation_deg = pos.elevation_deg, b->sun_azimuth_deg = pos.azimuth_deg;
  b->sun_from_time = 1;
  return SL_OK;
}

int sl_scene_air(const sl_settings *s, int spectral, sl_atmosphere *atm, sl_error *err)
{
  double nm[SL_SKY_SPECTRAL_COUNT];
  sl_sky_spectral_wavelengths(nm);
  const int rc = sl_atmosphere_init(atm, spectral ? nm : sl_sky_rgb_wavelengths_nm,
                                    spectral ? SL_SKY_SPECTRAL_COUNT : SL_SKY_RGB_COUNT,
                                    s->flat_earth ? SL_EARTH_FLAT : SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, err);
  /* The round earth the storm was placed on is also the ground the eye rays meet (the horizon). */
  if (!rc && s->curvature_drop) atm->ground_radius = SL_WRF_EARTH_RADIUS;
  return rc;
}

sl_optics_tables *sl_scene_tables(const sl_volume *v, int spectral, int max_order, sl_optics_progress_fn progress,
                                  void *progress_user, sl_error *err)
{
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  sl_optics_request_fields(&req, v);
  if (sl_optics_request_wavelengths(&req, spectral ? "spectral16" : "rgb", err)) return NULL;
  req.max_order = max_order;
  req.progress = progress, req.progress_user = progress_user;
  return sl_optics_build(&req, err);
}

double sl_scene_ground_albedo(const sl_settings *s, const sl_storm_frame *f)
{
  if (sl_settings_given(s, "ground-albedo")) return s->ground_albedo;
  /* The domain's mean: the file's own albedo, else land and water from its land mask. */
  const size_t n = (size_t)f->volume.nx * f->volume.ny;
  double sum = 0.0;
  size_t count = 0;
  const float *values = f->surface_albedo ? f->surface_albedo : f->land_mask;
  for (size_t c = 0; values && c < n; ++c)
    if (values[c] >= 0.0f && values[c] <= 1.0f) sum += values[c], count++;
  if (!count) return s->ground_albedo;
  const double mean = sum / count;
  return f->surface_albedo ? mean : SL_LAND_ALBEDO * mean + SL_WATER_ALBEDO * (1.0 - mean);
}

void sl_scene_fill(const sl_settings *s, const sl_built_scene *b, const sl_atmosphere *air,
                   const sl_optics_tables *optics, sl_scene *out)
{
  memset(out, 0, sizeof *out);
  out->volume = &b->frame.volume;
  out->atmosphere = air;
  out->optics = optics;
  out->lighting = (sl_lighting)s->lighting;
  out->xi = s->xi;
  out->light_volume = s->light_volume;
  out->skylight = s->skylight;
  out->diffuse_sunlight = s->diffuse_sunlight;
  /* The terrain draws its own ground (app/terrain_scene); the flat one is the sky's otherwise. */
  out->ground_albedo = s->terrain ? 0.0 : sl_scene_ground_albedo(s, &b->frame);
  /* Compass azimuth into the volume's axes, which are the grid's (docs/GEOREFERENCING.md). */
  sl_sun_direction(b->sun_elevation_deg, sl_georef_grid_azimuth(&b->frame.georef, b->sun_azimuth_deg),
                   out->sun_direction);
  for (int c = 0; c < SL_CHANNELS; ++c) {
    out->sun_irradiance[c] = 1.0;
    out->sky_radiance[c] = s->sky[c];
  }
  out->termination_transparency = 1e-6;
  out->slices = s->slices;
  out->light_resolution = s->light_resolution;
  out->march_samples = s->march_samples;
  out->march_thin_depth = s->march_thin_depth;
  out->march_refine_tolerance = s->march_refine_tolerance;
}

int sl_scene_build(const sl_settings *s, const sl_build_options *opt, sl_built_scene *b, sl_error *err)
{
  const sl_build_options none = {0};
  if (!opt) opt = &none;
  int rc = sl_settings_check(s, err);
  if (rc) return rc;
  if ((rc = sl_scene_load(s, opt->for_gpu, b, err))) return rc;
  const int with_air = !s->no_atmosphere;
  if (with_air && (rc = sl_scene_air(s, s->spectral, &b->atmosphere, err))) goto fail;
  /* Particle tables only for the fields this storm has, at the scene's wavelengths (cached). */
  if (s->lighting != SL_LIGHTING_LOW_ALBEDO) {
    b->optics = sl_scene_tables(&b->frame.volume, s->spectral, 0, opt->tables_progress, opt->tables_progress_user, err);
    if (!b->optics) {
      char message[sizeof err->message];
      snprintf(message, sizeof message, "%s", err->message);
      err->code = 0;
      rc = sl_fail(err, SL_ERR_DATA, "particle tables: %s", message);
      goto fail;
    }
  }
  sl_scene_fill(s, b, with_air ? &b->atmosphere : NULL, b->optics, &b->scene);
  b->scene.progress = opt->render_progress, b->scene.progress_user = opt->render_progress_user;
  if (!opt->no_renderer) {
    b->renderer = sl_renderer_create(&b->scene, err);
    if (!b->renderer) {
      char message[sizeof err->message];
      snprintf(message, sizeof message, "%s", err->message);
      err->code = 0;
      rc = sl_fail(err, SL_ERR_DATA, "%s: %s", s->data, message);
      goto fail;
    }
  }
  return SL_OK;
fail:
  sl_built_scene_free(b);
  return rc;
}

void sl_built_scene_free(sl_built_scene *b)
{
  sl_renderer_destroy(b->renderer);
  sl_optics_free(b->optics);
  if (b->have_frame) sl_storm_frame_free(&b->frame); /* last: the renderer's scene pointed into it */
  memset(b, 0, sizeof *b);
}

void sl_scene_camera(const sl_settings *s, const sl_volume *v, const double lo[3], const double hi[3],
                     const double sun[3], sl_camera *cam)
{
  const int given = sl_settings_given(s, "view-azimuth") || sl_settings_given(s, "view-elevation") ||
                    sl_settings_given(s, "camera-position") || sl_settings_given(s, "camera-target");
  /* The storm's box (columns of optical depth SL_CHASER_TAU) and its core's, from one pass. */
  const double taus[2] = {SL_CHASER_TAU, SL_CHASER_CORE_TAU};
  double box_lo[2][3], box_hi[2][3];
  int found[2];
  if (!given && v && sl_volume_condensate_boxes(v, 2, taus, SL_CHASER_BETA, box_lo, box_hi, found) && found[0]) {
    double clo[3], chi[3];
    for (int a = 0; a < 3; ++a) clo[a] = box_lo[0][a], chi[a] = box_hi[0][a];
    /* The width framed is the core's (a thin anvil may run off the sides), the height the whole
     * storm's. */
    if (found[1])
      for (int a = 0; a < 2; ++a) clo[a] = box_lo[1][a], chi[a] = box_hi[1][a];
    /* A storm chaser: on the ground, the sun over the left shoulder (30 degrees round from behind,
     * so that the faces it lights show relief), looking back at the storm and a little up. */
    const double sun_azimuth = sun[2] > 0.0 ? atan2(sun[0], sun[1]) * 180.0 / M_PI : 170.0;
    const double ground = fmax(v->origin[2] - 0.5 * v->spacing[2], 0.0);
    if (sl_camera_chaser(clo, chi, sun_azimuth + SL_CHASER_SUN_OFFSET_DEG, ground + SL_CHASER_EYE_M, s->fov_deg,
                         s->width, s->height, cam))
      return;
  }
  sl_camera_frame(lo, hi, s->view_azimuth_deg, s->view_elevation_deg, s->fov_deg, s->width, s->height, cam);
  if (sl_settings_given(s, "camera-target")) memcpy(cam->target, s->camera_target, sizeof cam->target);
  if (sl_settings_given(s, "camera-position")) memcpy(cam->position, s->camera_position, sizeof cam->position);
}

int sl_scene_ground_opaque(const sl_atmosphere *air, const sl_camera *cam, float *opaque)
{
  if (!air || !(air->ground_radius > 0.0)) return 0;
  sl_camera_ground_distance(cam, air, opaque);
  return 1;
}
