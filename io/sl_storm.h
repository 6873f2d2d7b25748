/* Reading storm-simulation output (WRF wrfout files, CM1 and CF-NetCDF) into the renderer's
 * uniform ENU grid. Mixing ratios become number concentrations eta = rho_dry * q / m_particle
 * (DESIGN.md); docs/DATA.md tables the microphysics schemes and how each species is mapped. */
#ifndef SL_STORM_H
#define SL_STORM_H

#include "sl_georef.h"
#include "sl_particles.h"
#include "sl_size_distribution.h"
#include "sl_status.h"
#include "sl_volume.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SL_MAX_TIMES 4096
#define SL_MAX_SPECIES 8

/* Storm file formats sl_storm_read_info recognises by content. */
typedef enum sl_storm_format { SL_STORM_WRF = 0, SL_STORM_CM1 = 1, SL_STORM_CF = 2 } sl_storm_format;

/* One hydrometeor variable of the file and the particle type(s) it feeds. A species whose warm
 * and cold types differ is split per cell at 0 C (simple-ice and warm-rain schemes). A variable
 * drawn as another type (--field) is that type's particle (docs/DATA.md). */
typedef struct sl_species {
  char variable[64];          /* mixing ratio or mass fraction, kg/kg */
  char number_variable[64];   /* number per kg of dry air (double-moment schemes), "" when none */
  int warm, cold;             /* sl_particle above / below 0 C; equal when not split */
  const char *kind;           /* "cloud water", "graupel", ... (static) */
  int per_moist_air;          /* CF mass fraction: per kg of moist air, not dry air */
  /* The scheme's size distribution (docs/DATA.md, "Sizes"): with the number variable, or with the
   * scheme's fixed number, each cell's effective radius scales the extinction of the warm type's
   * tables. density 0: the representative particle (Riley's, --particles representative). */
  sl_gamma_distribution sizes;
} sl_species;

/* Whether the species' sizes follow from the microphysics: a distribution, and a number read,
 * fixed by the scheme or implied by its fixed intercept. Otherwise the representative particle. */
int sl_species_sized(const sl_species *sp);

typedef struct sl_field_stats {
  int present;           /* the file has a variable feeding this particle type */
  double q_min, q_max;   /* kg/kg, before clamping */
  double q_mean;         /* kg/kg, after clamping negatives to zero */
  long negative_count;   /* values below zero, clamped to zero (advection error, normal in WRF) */
  /* Sizes (species with a distribution): the effective radius over cells with q above 1e-6 kg/kg
   * (0 when none), and the cells whose number variable was negative (clamped to 0) or zero where
   * q > 0 (the scheme's single-moment assumption, or the representative particle, there). */
  double r_eff_min, r_eff_max;
  long number_negative, number_missing;
} sl_field_stats;

typedef struct sl_storm_info {
  char path[1024];
  int format;                 /* netCDF format code (NC_FORMAT_*) */
  sl_storm_format kind;       /* WRF, CM1 or generic CF */
  int nx, ny, nz;             /* mass points: west_east, south_north, bottom_top */
  int ntimes;
  double dx, dy;              /* grid spacing on the projection plane, m */
  int map_proj;               /* WRF MAP_PROJ: 1 Lambert, 2 polar stereographic, 3 Mercator, 6 lat-lon; 0 unknown */
  double truelat1, truelat2, stand_lon; /* degrees, NAN when absent */
  double pole_lat, pole_lon;  /* degrees, WRF's rotated-pole attributes (MAP_PROJ 6); 90, 0 when absent */
  int mp_physics;             /* WRF MP_PHYSICS, -1 when absent */
  int cm1_ptype;              /* CM1's microphysics option (global attribute ptype), -1 when absent */
  char scheme[96];            /* microphysics scheme in words */
  char vertical[256];         /* the vertical coordinate and where heights come from, in words */
  int nspecies;               /* hydrometeor variables found and how they map (before --field) */
  sl_species species[SL_MAX_SPECIES];
  char times[SL_MAX_TIMES][24]; /* "YYYY-MM-DD_hh:mm:ss" in the file's calendar, empty when the file has none */
  int has_times;
  char calendar[24];          /* the time coordinate's CF calendar, "standard" when it names none (WRF) */
  /* The same instants as Gregorian dates where the sun stands as it does then (the sun's position
   * takes these): equal to times in the standard and proleptic Gregorian calendars, the same day
   * in the Julian one, the same fraction of the year in noleap, all_leap and 360_day. */
  char sun_times[SL_MAX_TIMES][24];
  /* A time coordinate that counts from the run's start with no date (CM1's "seconds"): each time
   * as seconds since the start. The run is placed in time by --date, its start. */
  int has_elapsed;
  double elapsed_s[SL_MAX_TIMES];
} sl_storm_info;

/* One time of a storm file resampled to a uniform grid. */
/* The optics tables of sized cloud and rain (io/size_bins.c): per type, the effective radii of its
 * fields in the volume, and the range of the cells' effective radius they span. */
typedef struct sl_size_bins {
  int count[SL_PARTICLE_COUNT];    /* tables of the type; 0: its own (not sized) */
  double radius_m[SL_PARTICLE_COUNT][SL_VOLUME_MAX_FIELDS];
  double range_lo_m[SL_PARTICLE_COUNT], range_hi_m[SL_PARTICLE_COUNT]; /* 1st and 99th percentiles,
                                                                         extinction-weighted */
  int limited[SL_PARTICLE_COUNT];  /* fewer tables than the range asks: the fields ran out */
} sl_size_bins;

typedef struct sl_storm_frame {
  sl_volume volume;           /* eta per particle field on the ENU grid */
  sl_size_bins sizes;         /* the tables sized cloud and rain take */
  sl_field_stats stats[SL_PARTICLE_COUNT]; /* raw statistics of the variable named after each type (QCLOUD, qc, ...) */
  double center_lat, center_lon; /* degrees, at the grid's centre column */
  sl_georef georef;           /* projection, its check against XLAT/XLONG, placement in the world frame */
  double terrain_min, terrain_max; /* m above sea level */
  double model_top;           /* highest interface height, m */
  int time_index;
  int nspecies;               /* the mapping used (after --field overrides) and per-variable stats */
  sl_species species[SL_MAX_SPECIES];
  sl_field_stats species_stats[SL_MAX_SPECIES];
  double memory_estimate;     /* bytes the load needed by its estimate (output grid + buffers) */
  /* The scene around the storm (terrain, coastlines, graticule): one value per column of the
   * volume's horizontal grid (nx * ny, x fastest, the same columns as volume's samples), owned,
   * freed by sl_storm_frame_free. NULL when the reader had none. */
  float *terrain_height;      /* HGT, m above sea level (world z: less the drop with earth_curvature) */
  double *column_lat, *column_lon; /* XLAT, XLONG, degrees north and east */
  float *surface_albedo;      /* the file's ALBEDO (land-surface model, broadband; CF surface_albedo), NULL when absent */
  float *land_mask;           /* 1 land, 0 water: LANDMASK, else XLAND (1 land, 2 water); CF land_binary_mask, else
                                 land_area_fraction (0..1); NULL when absent */
} sl_storm_frame;

/* Zero-initialised options read the whole domain at its full resolution. */
typedef struct sl_load_options {
  int time_index;             /* 0-based */
  double dz;                  /* output vertical spacing, m; <= 0 picks (top - ground) / (2 nz) */
  int stride;                 /* read every stride-th column in x and y (0 or 1: all) */
  int level_first, level_count; /* model levels [first, first + count); count 0: to the top */
  int has_region;             /* read only the columns inside region (degrees) */
  double region[4];           /* lat0, lat1, lon0, lon1 */
  double max_memory;          /* bytes; 0: what the machine has available */
  /* Per particle type: the variable that feeds it instead of the default mapping ("none": no
   * variable); NULL keeps the default. */
  const char *field_variable[SL_PARTICLE_COUNT];
  /* 1: every species as its type's representative particle (Riley et al. 2004), ignoring number
   * concentrations and the schemes' size distributions (--particles representative). */
  int representative_particles;
  /* > 0: cloud droplets per m^3 where the file writes no droplet number, instead of the scheme's
   * fixed number (CM1's namelist ndcnst, which its output does not record) (--droplet-number). */
  double droplet_number_m3;
  /* Fields the renderer will carry per sample, 0: SL_VOLUME_MAX_FIELDS (8), which the GPU pass
   * carries too (SL_GPU_MAX_FIELDS). The cloud and rain size tables share what the species leave. */
  int max_fields;
  /* Placement (docs/GEOREFERENCING.md). The world frame is the local east-north-up frame of
   * (origin_lat, origin_lon) when has_origin is set, else of this time's grid centre; a series
   * keeps one origin so a moving nest moves across the frame. */
  int has_origin;
  double origin_lat, origin_lon;
  int earth_curvature;        /* 1: each column sinks by the sphere's depth below the tangent plane */
  /* > 0: model levels the loader holds at a time; 0: as many as 64 MB of work arrays hold, rounded
   * to the layers of the file's compressed chunks. The frame is the same to float rounding. */
  int block_levels;
} sl_load_options;

/* A 3-D float variable (dimensions z, y, x) of a NetCDF file, read as it stands into *out (malloc;
 * the caller frees), its sizes into n (x, y, z); negative or non-finite values are an error naming
 * the element. For fields that are not storms (a reference medium's extinction). */
int sl_read_field3d(const char *path, const char *variable, int n[3], float **out, sl_error *err);

/* Reads the file's shape, projection attributes and times. */
int sl_storm_read_info(const char *path, sl_storm_info *info, sl_error *err);
/* Reads one time into a uniform grid (frees nothing of *frame on failure: it stays zeroed). */
int sl_storm_load(const char *path, const sl_load_options *opt, sl_storm_frame *frame, sl_error *err);
void sl_storm_frame_free(sl_storm_frame *frame);
/* The same from a file image in memory (nc_open_mem; netCDF-3 and, where the library allows it,
 * netCDF-4). `name` names the image in messages. */
int sl_storm_load_memory(const char *name, const void *data, size_t size, const sl_load_options *opt,
                         sl_storm_frame *frame, sl_error *err);

/* The species mapping a load would use: the file's default (info->species) with the options'
 * --field overrides applied. Fails naming an override variable the file lacks. */
int sl_storm_map_species(const sl_storm_info *info, const sl_load_options *opt, sl_species out[SL_MAX_SPECIES],
                         int *count, sl_error *err);
/* Bytes a load of one time would need (output grid, per-level buffers), from the dimensions only,
 * before anything is read. */
double sl_storm_memory_estimate(const sl_storm_info *info, const sl_load_options *opt);
/* Bytes this machine can give a load now (MemAvailable, else physical memory). */
double sl_machine_memory(void);

/* Dry-air density (kg/m3) from total pressure p (Pa), temperature (K) and vapour mixing ratio
 * qv (kg/kg): p = rho_d T (R_d + qv R_v), so rho_d = p / (R_d T (1 + qv / eps)). WRF's mixing
 * ratios are per kilogram of dry air, so rho_d * q is the hydrometeor mass per cubic metre. */
double sl_dry_air_density(double pressure, double temperature, double qv);
/* Temperature (K) from potential temperature (K) and pressure (Pa): theta (p / 1e5 Pa)^(R_d/c_p). */
double sl_temperature_from_theta(double theta, double pressure);
/* Temperature (K) from WRF's perturbation potential temperature T (theta - 300 K) and pressure. */
double sl_temperature_from_wrf(double theta_perturbation, double pressure);

#ifdef __cplusplus
}
#endif
#endif
