/* Shared between the optics sources; not part of the public API. */
#ifndef SL_OPTICS_INTERNAL_H
#define SL_OPTICS_INTERNAL_H

#include "sl_optics.h"

/* The uniform theta grid of a table. */
typedef struct optics_grid {
  int n_angles;    /* 180 / step + 1 */
  double step_rad;
  double *theta;   /* n_angles */
  double *mu;      /* cos theta */
  double *weight;  /* sphere weights: 2 pi * int of the linear hat function * sin theta */
  double *weight_forward; /* the same over theta <= 90 degrees only */
} optics_grid;

int optics_grid_init(optics_grid *g, double step_deg, sl_error *err);
void optics_grid_free(optics_grid *g);
/* 2 pi int P sin theta dtheta of the piecewise-linear-in-theta interpolant of v. */
double optics_grid_integral(const optics_grid *g, const double *v);

/* What a particle model hands to the table builder: P on the grid, normalised so that the
 * exact integral over the sphere is 1 (the forward peak narrower than the grid included; the
 * builder truncates it), plus the bulk optics. */
typedef struct optics_raw_phase {
  double *p;         /* n_angles, 1/sr */
  double sigma_ext;  /* m^2 per representative particle */
  double albedo;
  double asymmetry;  /* g of the untruncated P, when the model knows it; NAN otherwise */
} optics_raw_phase;

/* Lognormal size distribution of one particle type (mie_distribution.c). */
typedef struct optics_lognormal {
  double median_radius_m, sigma_ln;
  const char *source;
} optics_lognormal;

/* Particle models (one file each). */
/* Water spheres over the lognormal `dist`; sigma_ext per representative particle of type p. */
int optics_mie_distribution(sl_particle p, const optics_lognormal *dist, double wavelength_nm,
                            const optics_grid *g, int radius_samples, optics_raw_phase *out, sl_error *err);
int optics_ice_crystals(double wavelength_nm, const optics_grid *g, long rays, unsigned long long seed,
                        optics_raw_phase *out, sl_error *err);
int optics_snow(double wavelength_nm, const optics_grid *g, optics_raw_phase *out, sl_error *err);
int optics_rimed_ice(sl_particle p, double wavelength_nm, const optics_grid *g, int radius_samples,
                     optics_raw_phase *out, sl_error *err);

const optics_lognormal *optics_size_distribution(sl_particle p);
/* Type p's lognormal moved to the effective radius r_eff_m (same width: the shape the schemes'
 * sizes are interpolated over); r_eff_m = 0 gives p's own. Returns 0 when p has none. */
int optics_size_distribution_at(sl_particle p, double r_eff_m, optics_lognormal *out);
/* Effective radius <r^3> / <r^2> of a lognormal: r_g exp(2.5 s^2). */
double optics_lognormal_effective_radius(const optics_lognormal *d);

/* Exponential size distribution n(D) = N0 exp(-slope D) of graupel and hail (rimed_ice.c): spheres
 * of the bulk density, Mie up to size parameter SL_RIMED_X_MIE_MAX, a large-particle limit beyond
 * whose angular shape is the mean of SL_RIMED_BAND_SPHERES spheres spread below it. */
typedef struct optics_exponential {
  double slope_per_m, density_kg_m3;
  const char *source;
} optics_exponential;
const optics_exponential *optics_rimed_distribution(sl_particle p);
#define SL_RIMED_X_MIE_MAX 2.0e4
#define SL_RIMED_BAND_SPHERES 64

/* Turns a raw phase function into a finished table (phase_table.c). The table owns one
 * allocation, released with optics_table_release. */
typedef struct optics_table_params {
  double truncation_rad;
  int n_moments;
  int max_order;           /* 0: until isotropic within tol */
  double isotropy_tolerance;
} optics_table_params;
int optics_table_from_raw(const optics_grid *g, const optics_raw_phase *raw, const optics_table_params *params,
                          double wavelength_nm, sl_phase_table *out, sl_error *err);
void optics_table_release(sl_phase_table *t);
/* One allocation holding delta, forward, moments and ams; sets the table's pointers and sizes. */
void *optics_table_alloc(sl_phase_table *t, int max_order, int n_angles, int n_moments);

/* Cache (cache.c). */
int optics_cache_load(const char *path, const char *key, sl_phase_table *tables, int n_tables, sl_error *err);
int optics_cache_store(const char *path, const char *key, const sl_phase_table *tables, int n_tables,
                       sl_error *err);
unsigned long long optics_fnv1a(const void *data, size_t n, unsigned long long h);
/* An exclusive lock on the cache entry path (a file path.lock beside it), waited for: processes
 * that miss the same entry at once build it once, the others load it. Returns a descriptor to
 * pass to optics_cache_unlock, or -1 where the lock cannot be taken (a read-only cache, a file
 * system without locks): the caller then builds unlocked, as before. */
int optics_cache_lock(const char *path);
void optics_cache_unlock(int fd);

#endif
