/* Reading storm-simulation output (WRF wrfout files) into the renderer's uniform ENU grid.
 * Mixing ratios become number concentrations eta = rho_dry * q / m_particle (DESIGN.md). */
#ifndef SL_STORM_H
#define SL_STORM_H

#include "sl_georef.h"
#include "sl_particles.h"
#include "sl_status.h"
#include "sl_volume.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SL_MAX_TIMES 4096

typedef struct sl_field_stats {
  int present;           /* the file has a variable feeding this particle type */
  double q_min, q_max;   /* kg/kg, before clamping */
  double q_mean;         /* kg/kg, after clamping negatives to zero */
  long negative_count;   /* values below zero, clamped to zero (advection error, normal in WRF) */
} sl_field_stats;

typedef struct sl_storm_info {
  char path[1024];
  int format;                 /* netCDF format code (NC_FORMAT_*) */
  int nx, ny, nz;             /* mass points: west_east, south_north, bottom_top */
  int ntimes;
  double dx, dy;              /* grid spacing on the projection plane, m */
  int map_proj;               /* WRF MAP_PROJ: 1 Lambert, 2 polar stereographic, 3 Mercator, 6 lat-lon; 0 unknown */
  double truelat1, truelat2, stand_lon; /* degrees, NAN when absent */
  double pole_lat, pole_lon;  /* degrees, WRF's rotated-pole attributes (MAP_PROJ 6); 90, 0 when absent */
  int mp_physics;             /* WRF MP_PHYSICS, -1 when absent */
  char times[SL_MAX_TIMES][24]; /* "YYYY-MM-DD_hh:mm:ss", empty when the file has none */
  int has_times;
} sl_storm_info;

/* One time of a storm file resampled to a uniform grid. */
typedef struct sl_storm_frame {
  sl_volume volume;           /* eta per particle field on the ENU grid */
  sl_field_stats stats[SL_PARTICLE_COUNT]; /* raw mixing-ratio statistics on the model grid */
  double center_lat, center_lon; /* degrees, at the grid's centre column */
  sl_georef georef;           /* projection, its check against XLAT/XLONG, placement in the world frame */
  double terrain_min, terrain_max; /* m above sea level */
  double model_top;           /* highest interface height, m */
  int time_index;
} sl_storm_frame;

typedef struct sl_load_options {
  int time_index;             /* 0-based */
  double dz;                  /* output vertical spacing, m; <= 0 picks (top - ground) / (2 nz) */
  /* Placement (docs/GEOREFERENCING.md). The world frame is the local east-north-up frame of
   * (origin_lat, origin_lon) when has_origin is set, else of this time's grid centre; a series
   * keeps one origin so a moving nest moves across the frame. */
  int has_origin;
  double origin_lat, origin_lon;
  int earth_curvature;        /* 1: each column sinks by the sphere's depth below the tangent plane */
} sl_load_options;

/* Reads the file's shape, projection attributes and times. */
int sl_storm_read_info(const char *path, sl_storm_info *info, sl_error *err);
/* Reads one time into a uniform grid (frees nothing of *frame on failure: it stays zeroed). */
int sl_storm_load(const char *path, const sl_load_options *opt, sl_storm_frame *frame, sl_error *err);
void sl_storm_frame_free(sl_storm_frame *frame);

/* Dry-air density (kg/m3) from total pressure p (Pa), temperature (K) and vapour mixing ratio
 * qv (kg/kg): p = rho_d T (R_d + qv R_v), so rho_d = p / (R_d T (1 + qv / eps)). WRF's mixing
 * ratios are per kilogram of dry air, so rho_d * q is the hydrometeor mass per cubic metre. */
double sl_dry_air_density(double pressure, double temperature, double qv);
/* Temperature (K) from WRF's perturbation potential temperature T (theta - 300 K) and pressure. */
double sl_temperature_from_wrf(double theta_perturbation, double pressure);

#ifdef __cplusplus
}
#endif
#endif
