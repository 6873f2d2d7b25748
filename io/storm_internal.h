/* Shared by the storm readers (wrf_read.c, cf_read.c): NetCDF helpers, the species mapping and
 * the remap that turns a block of levels at a time into the uniform grid. Not installed. */
#ifndef SL_STORM_INTERNAL_H
#define SL_STORM_INTERNAL_H

#include <stddef.h>

#include "sl_storm.h"

#define SL_FREEZING_K 273.15

/* The cells a thread takes at a time in the loaders' loops between reads: dynamically, so that a
 * thread another process keeps off its core leaves its share to the other (docs/PERFORMANCE.md, "A
 * busy machine"), in pieces long enough that taking one costs nothing beside its work. */
#define SL_IO_CHUNK 16384

typedef struct sl_nc {
  int id;
  const char *path;
} sl_nc;

/* The columns and levels a load reads: x = i0 + stride * i for i < nx, the same in y, model levels
 * k0 .. k0 + nz - 1 (interfaces k0 .. k0 + nz). */
typedef struct sl_subset {
  int i0, j0, stride, nx, ny;
  int k0, nz;
} sl_subset;

/* A variable opened for slab reads: unpacking and fill values resolved once. */
typedef struct sl_nc_var {
  int varid, ndims, has_time;
  double scale, offset, fill, missing;
  char name[64];
} sl_nc_var;

int sl_nc_open(const char *path, const void *data, size_t size, sl_nc *f, sl_error *err);
double sl_nc_attr_double(const sl_nc *f, int varid, const char *name, double fallback);
int sl_nc_attr_text(const sl_nc *f, int varid, const char *name, char *out, size_t cap);
int sl_nc_has_var(const sl_nc *f, const char *name);
/* 1 when variable varid is numeric and one-dimensional with at least min_len values (its length
 * in *len): the shape a coordinate or time variable must have before a 1-D start/count or a
 * whole-variable read into a buffer of min_len values may touch it. */
int sl_nc_var_is_1d(const sl_nc *f, int varid, size_t min_len, size_t *len);

/* The calendars of CF section 4.4.1 (calendar.c): "standard" (alias "gregorian": Julian before
 * 1582-10-15), "proleptic_gregorian", "julian", "noleap" (alias "365_day"), "all_leap" ("366_day")
 * and "360_day". Dates are int[6]: year, month, day, hour, minute, second. */
typedef enum sl_calendar {
  SL_CAL_STANDARD,
  SL_CAL_PROLEPTIC_GREGORIAN,
  SL_CAL_JULIAN,
  SL_CAL_NOLEAP,
  SL_CAL_ALL_LEAP,
  SL_CAL_360_DAY,
  SL_CAL_UNKNOWN
} sl_calendar;
/* The calendar a `calendar` attribute names ("" is the standard one); SL_CAL_UNKNOWN otherwise. */
sl_calendar sl_calendar_named(const char *name);
/* 1 when date exists in the calendar (years 1..9999, clock fields in their ranges): checked before
 * any arithmetic on a date parsed from a file. */
int sl_calendar_valid(sl_calendar cal, const int date[6]);
/* The date `seconds` after base in the calendar; 0 when base is not a date of it or the result
 * leaves years 1..9999 (an absurd offset). */
int sl_calendar_add_seconds(sl_calendar cal, const int base[6], double seconds, int out[6]);
/* The Gregorian date at which the sun stands as at `date` in the calendar: the same day for the
 * Gregorian and Julian calendars; for the model calendars (noleap, all_leap, 360_day) the same
 * clock time on the day at the same fraction of the year. */
void sl_calendar_sun_date(sl_calendar cal, const int date[6], int out[6]);
/* "YYYY-MM-DD_hh:mm:ss", as sl_storm_info's times. */
void sl_calendar_format(const int date[6], char out[24]);
/* Opens `name` and checks that its trailing `ndims` dimensions have the given lengths (names too
 * when dim_names is not NULL); a leading time dimension is optional (static fields). */
int sl_nc_var_open(const sl_nc *f, const char *name, int ndims, const char *const *dim_names, const size_t *lens,
                   sl_nc_var *v, sl_error *err);
/* Reads the horizontal slab at time t and level k (k < 0 for a 2-D variable) over the subset's
 * columns into out[ny][nx], unpacked; fill/missing values become NaN. */
int sl_nc_read_slab(const sl_nc *f, const sl_nc_var *v, int t, int k, const sl_subset *s, double *out,
                    sl_error *err);
/* The variables a reader has opened, by name (each opened and checked once per load). */
typedef struct sl_var_cache {
  sl_nc_var vars[16];
  int count;
} sl_var_cache;
/* The opened variable `name` of 3-D shape (dims, lens), opening it on first use. */
int sl_var_cache_get(sl_var_cache *cache, const sl_nc *f, const char *name, const char *const dims[3],
                     const size_t lens[3], const sl_nc_var **out, sl_error *err);
/* Levels k0 .. k0 + nk - 1 of a variable at time t over the subset's columns, as floats
 * ([level][y][x]), unpacked, failing on NaN/Inf/fill naming the variable. A chunk the block
 * covers only in part is inflated again by the next block that reads it (netCDF's chunk cache
 * holds a few): sl_nc_chunk_levels says where blocks should end. */
int sl_nc_read_block(const sl_nc *f, const sl_nc_var *v, int t, int k0, int nk, const sl_subset *s, float *out,
                     sl_error *err);
/* The same without the check: missing values read as NaN (pressure levels below the ground). */
int sl_nc_read_block_raw(const sl_nc *f, const sl_nc_var *v, int t, int k0, int nk, const sl_subset *s, float *out,
                         sl_error *err);
/* The levels one compressed chunk of 3-D variable v spans (1 when v is contiguous or 2-D). */
int sl_nc_chunk_levels(const sl_nc *f, const sl_nc_var *v);
/* Raises *levels to the largest chunk layer of the species' variables and numbers (3-D, of shape
 * dims, lens), each opened through the cache. */
int sl_species_chunk_levels(sl_var_cache *cache, const sl_nc *f, const char *const dims[3], const size_t lens[3],
                            const sl_species *species, int nspecies, int *levels, sl_error *err);
/* The error for a NaN, infinite or missing value in variable `name`. */
int sl_nc_fail_missing(const sl_nc *f, const char *name, int t, sl_error *err);
/* Fails on NaN/Inf naming the variable. */
int sl_all_finite(const sl_nc *f, const char *name, int t, const double *v, size_t n, sl_error *err);

/* What a format reader supplies to the remap, a block of levels per call: levels are counted from
 * the subset's first, arrays are [k][y][x] over the subset's columns. */
typedef struct sl_level_reader {
  void *ctx;
  /* Heights (m above sea level) of interfaces k0 .. k0 + nk - 1 (0 .. nz of the subset). */
  int (*interfaces)(void *ctx, int k0, int nk, double *z, sl_error *err);
  /* Dry-air density (kg/m3), moist-air density (NULL when not wanted) and whether each cell is
   * below 0 C, for levels k0 .. k0 + nk - 1. */
  int (*air)(void *ctx, int k0, int nk, float *rho_dry, float *rho_moist, unsigned char *frozen, sl_error *err);
  /* Values of a hydrometeor variable on levels k0 .. k0 + nk - 1 (unpacked, checked finite). */
  int (*field)(void *ctx, const char *name, int k0, int nk, float *out, sl_error *err);
  /* The files' compressed chunks along the levels: level k starts a layer of chunks where
   * (k + chunk_phase) is a multiple of chunk_levels (1: any level does; a contiguous variable). */
  int chunk_levels, chunk_phase;
  /* > 0: levels read per block whatever the memory and the chunks (sl_load_options.block_levels). */
  int block_levels;
} sl_level_reader;

/* Fills frame->volume from the mapped species with the conservative vertical remap, a block of
 * levels at a time (each variable's chunks inflated once where the blocks follow them); ground and
 * top are the output grid's bottom and top (m); spacing_h the output's horizontal spacing; corner
 * the first column's x, y (NULL: the grid centred on 0, 0); drop, per output column, how far the
 * column sinks for the earth's curvature (NULL: none); max_fields the fields the renderer will
 * carry (0: SL_VOLUME_MAX_FIELDS), which the size tables share. */
int sl_remap_levels(const char *path, const sl_level_reader *r, const sl_subset *s, const sl_species *species,
                    int nspecies, double ground, double top, double dz, const double spacing_h[2],
                    const double corner[2], const double *drop, int max_fields, sl_storm_frame *frame,
                    sl_error *err);

/* Number of distinct particle types the species feed. */
int sl_species_type_count(const sl_species *species, int n);
/* Default species of a WRF file from the variables it has and its MP_PHYSICS. */
void sl_species_wrf(const sl_nc *f, int mp_physics, sl_storm_info *info);
int sl_map_species_nc(const sl_nc *f, const sl_storm_info *info, const sl_load_options *opt,
                      sl_species out[SL_MAX_SPECIES], int *count, sl_error *err);
/* CM1's scheme from its ptype attribute: info->scheme in words, sizes and number variables of the
 * species sl_species_cf_match found. */
void sl_species_cm1_scheme(const sl_nc *f, sl_storm_info *info);
/* A CM1 name (cm1 != 0) or CF standard_name of a hydrometeor: fills *sp and returns 1. */
int sl_species_cf_match(const char *var_name, const char *standard_name, int cm1, sl_species *sp);
/* The species' number mixing ratio (per kg of air) is variable number_variable: its sizes follow
 * from (q, N) through its scheme's distribution, or Stormlight's default for the type. */
void sl_species_set_number(sl_species *sp, const char *number_variable);
/* Extinction-equivalent number concentration (m^-3) of `target` particles for one cell: the
 * species' mass concentration rho_air * q and, for double-moment schemes, its number
 * concentration rho_dry * qn (qn < 0: none). */
double sl_species_eta(const sl_species *sp, int target, double rho_air, double q, double rho_dry, double qn,
                      double *r_eff);
/* Splits each sized type's field (cloud, rain) between tables of effective radii across its range:
 * lnr_eta[t] holds the sum of eta ln(r_eff) per cell beside v->eta[t] (NULL: not sized). */
int sl_size_bins_split(sl_volume *v, float *const lnr_eta[SL_PARTICLE_COUNT], int max_fields, sl_size_bins *out,
                       sl_error *err);

/* Work bytes per cell of a block of levels (remap.c): interface heights (a double), dry and moist
 * density (floats), the freezing flag, one species and its number (floats), and the reader's
 * buffers while it derives the air (up to three floats). */
#define SL_REMAP_BYTES_PER_CELL 40
/* The most levels one of the remap's blocks holds, for nz levels of n2 columns: as many as 64 MB
 * of work arrays hold, rounded to the reader's chunk layers (r NULL: before they are known). */
int sl_remap_block_levels(const sl_level_reader *r, int nz, size_t n2);
/* Estimated bytes of a load of nx x ny columns, nz_block levels at a time, into `types` fields of
 * nz_out levels. */
double sl_load_bytes(size_t nx, size_t ny, size_t nz_block, size_t nz_out, int types);

int sl_cf_read_info(const sl_nc *f, sl_storm_info *info, sl_error *err);
int sl_cf_load(const sl_nc *f, const sl_storm_info *info, const sl_load_options *opt, const sl_species *species,
               int nspecies, sl_storm_frame *frame, sl_error *err);
/* Limits a load to the machine's memory or --max-memory. */
int sl_check_memory(const char *path, double need, const sl_load_options *opt, sl_error *err);

#endif
