/* Every option of a rendered scene, typed, with its default: what `stormlight render` flags and a
 * scene file's keys (docs/SCENES.md) set, and what sl_scene_build reads. One table
 * (sl_settings_options) names each option with its type, range, default and help: the CLI's
 * --help, the scene schema and this parser all come from it. */
#ifndef SL_SETTINGS_H
#define SL_SETTINGS_H

#include <stddef.h>

#include "sl_particles.h"
#include "sl_sky.h"
#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SL_SETTINGS_PATH 4096
#define SL_SETTINGS_VARIABLE 256

typedef struct sl_settings {
  char data[SL_SETTINGS_PATH]; /* the storm file */
  char out[SL_SETTINGS_PATH];  /* output image(s), comma-separated */
  int time_index;
  int width, height;
  int slices, light_resolution;      /* 0: automatic */
  double sun_azimuth_deg, sun_elevation_deg; /* compass; given together (sl_settings_given) */
  sl_utc date;                       /* with "date" given */
  int flat_earth;                    /* earth flat (the paper's air mass) or round */
  int curvature_drop;                /* columns sunk by the sphere's depth below the tangent plane */
  double origin[2];                  /* tangent point, lat, lon, degrees (given: "origin") */
  int lighting;                      /* sl_lighting */
  double xi;
  int spectral;                      /* 16 wavelengths through CIE instead of rgb */
  double fog_visibility_km;
  int fog_haze;                      /* haze (rural aerosol) instead of fog droplets */
  double fog_depth_km;
  int light_volume;
  int skylight;                      /* the sky dome lights the volume (sl_scene.skylight) */
  int diffuse_sunlight;              /* sunlight diffused through the cloud (sl_scene.diffuse_sunlight) */
  double ground_albedo;              /* the flat ground under the storm (sl_scene.ground_albedo) */
  int march_samples;
  double march_thin_depth;           /* sl_scene.march_thin_depth */
  double march_refine_tolerance;     /* sl_scene.march_refine_tolerance */
  int no_atmosphere;
  double camera_position[3], camera_target[3]; /* given: "camera-position", "camera-target" */
  double view_azimuth_deg, view_elevation_deg, fov_deg;
  int threads;
  double exposure;
  double sky[3];
  double dz;
  int float_exr;
  char field_variable[SL_PARTICLE_COUNT][SL_SETTINGS_VARIABLE]; /* "" keeps the scheme's mapping */
  int representative_particles;
  int max_fields;
  double droplet_number_cm3;         /* given: "droplet-number" */
  double region[4];                  /* given: "region" */
  int level_first, level_count;      /* given: "levels" */
  int stride;
  double max_memory;                 /* bytes; given: "max-memory" */
  int terrain;
  double terrain_albedo;             /* given: "terrain-albedo" */
  int coastlines, borders, graticule, domain_outline, scale_bar;
  double graticule_step;
  double night_sky_luminance;
  int lights_count[2];               /* given: "lights-count" */
  double lights_center[2], lights_spacing, lights_height, lights_jitter, lights_intensity_cd, lights_color[3];
  unsigned char given[96];           /* per option of sl_settings_options, 1 when set */
} sl_settings;

typedef enum sl_option_type {
  SL_OPTION_FLAG,    /* no value; true when given */
  SL_OPTION_INT,     /* an integer in [min, max] */
  SL_OPTION_NUMBER,  /* a finite number in [min, max] */
  SL_OPTION_CHOICE,  /* one of choices ("a|b|c"): its index */
  SL_OPTION_LIST,    /* count comma-separated finite numbers (min: the count) */
  SL_OPTION_TEXT,    /* text (paths) */
  SL_OPTION_SPECIAL  /* its own syntax (fields, levels, bytes, a date) */
} sl_option_type;

typedef struct sl_option sl_option;
struct sl_option {
  const char *name;     /* the flag without "--", the scene key */
  const char *metavar;  /* the value's name in --help; NULL for a flag */
  const char *help;
  const char *fallback; /* the default as text, as --help shows it; NULL: none (not set) */
  sl_option_type type;
  double min, max;      /* INT, NUMBER: range; LIST: min is the count */
  const char *choices;  /* CHOICE: "a|b|c" */
  const int *values;    /* CHOICE: the value stored for each choice (NULL: its index) */
  size_t offset;        /* where in sl_settings the value goes (int, double, double[], char[]) */
  int (*parse)(sl_settings *s, const char *value, sl_error *err); /* SPECIAL */
};

/* The table, in --help order, and its length. */
extern const sl_option sl_settings_options[];
extern const int sl_settings_option_count;
/* The option called name, or NULL. */
const sl_option *sl_settings_option(const char *name);

/* Every option at its default (data and out empty, nothing given). */
void sl_settings_defaults(sl_settings *s);
/* Sets option `name` from its text (NULL or "" for a flag); a one-line error naming the option
 * and the value when it does not parse or lies outside its range. */
int sl_settings_set(sl_settings *s, const char *name, const char *value, sl_error *err);
/* Whether option `name` was set (a flag: given). */
int sl_settings_given(const sl_settings *s, const char *name);
/* Command-line arguments: "--name value", "--flag", and one positional, the storm file. */
int sl_settings_parse_args(sl_settings *s, int argc, char **argv, sl_error *err);
/* The checks between options (both sun angles or neither, a date or the angles, spectral needs
 * the air); a one-line error. */
int sl_settings_check(const sl_settings *s, sl_error *err);

/* A scene file's JSON object (docs/SCENES.md) as command-line arguments: "data" first (a
 * positional), then "--key value" per key; paths ("data", "out") relative to the file's folder
 * `dir`. Keys not in the table are refused, naming `path`. The caller frees with
 * sl_scene_args_free. */
typedef struct sl_scene_args {
  int argc;
  char **argv;
} sl_scene_args;
int sl_scene_json_args(const char *text, const char *path, sl_scene_args *out, sl_error *err);
/* The same from the file at path. */
int sl_scene_file_args(const char *path, sl_scene_args *out, sl_error *err);
void sl_scene_args_free(sl_scene_args *a);
/* Settings from a scene file (read, then sl_scene_json_args and sl_settings_parse_args). */
int sl_settings_from_scene_file(sl_settings *s, const char *path, sl_error *err);
/* A scene as a front end reads it: the defaults, the file's settings, then argc arguments that
 * override them (render's flags, such as "--width 64"; NULL for none), checked
 * (sl_settings_check) and naming a storm file; a one-line error naming the scene file. */
int sl_settings_from_scene(sl_settings *s, const char *path, int argc, char **argv, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
