/* Particle optics for the renderer: plan once (sl_optics_build), look up many times.
 *
 * For every particle type in a scene and every wavelength the tables hold the extinction
 * cross-section, the single-scattering albedo, the Legendre moments of the phase function and
 * the multiple-scattering angular distributions Ams_n (Riley et al. 2004, eq. 20) for
 * n = 0..N, with the forward fractions F_n (eq. 23).
 *
 * Representation of an angular distribution (all normalised to 1 over the sphere):
 *     Ams_n(theta) = delta[n] * dirac(forward) + ams[n](theta)
 * The forward diffraction peak of large particles is far narrower than the table's grid. It
 * is truncated (docs/OPTICS.md): the part of P above its value at the truncation angle,
 * inside that angle, becomes a forward Dirac of weight f; Ams_n then carries f^n of it.
 * ams[n] is tabulated on a uniform grid of theta (0..180 degrees) and linearly interpolated in
 * theta; integrated that way it gives exactly 1 - delta[n]. The renderer treats delta[n] as
 * light that keeps its direction (it only ever matters when looking into the light).
 *   n = 0: the collimated beam itself: delta[0] = 1, ams[0] = 0.
 *   n = 1: the phase function P: delta[1] = f, ams[1] = P outside the truncation cone.
 *   n > N: sl_phase_table_ams clamps n to N, which is isotropic within the tolerance when
 *          max_order was left to the builder (see sl_optics_request.max_order). */
#ifndef SL_OPTICS_H
#define SL_OPTICS_H

#include <math.h>
#include <stddef.h>

#include "sl_guards.h"
#include "sl_particles.h"
#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SL_OPTICS_MAX_WAVELENGTHS 64
#define SL_OPTICS_MAX_SIZES 8
#define SL_OPTICS_MAX_ORDER 400
/* Bumped whenever a change alters table contents: cached tables of another version are rebuilt. */
#define SL_OPTICS_TABLE_VERSION 2 /* 2: Warren & Brandt ice index table */

/* The paper's three wavelengths (red, green, blue): 650, 515, 440 nm. */
extern const double SL_WAVELENGTHS_RGB[3];
/* 16 wavelengths from 380 to 720 nm, evenly spaced, for the spectral mode (sl_cie.h). */
extern const double SL_WAVELENGTHS_SPECTRAL16[16];

typedef void (*sl_optics_progress_fn)(void *user, double fraction);

/* Tables of a type at another size: its size distribution moved to this effective radius
 * (cloud and rain, whose lognormals render/optics/mie_distribution.c keeps). */
typedef struct sl_optics_size {
  sl_particle type;
  double effective_radius_m;
} sl_optics_size;

typedef struct sl_optics_request {
  unsigned particles;        /* bit mask of (1u << sl_particle): build only the fields present */
  int n_sizes;               /* further tables at other sizes, 0..SL_OPTICS_MAX_SIZES */
  sl_optics_size sizes[SL_OPTICS_MAX_SIZES];
  int n_wavelengths;
  double wavelengths_nm[SL_OPTICS_MAX_WAVELENGTHS];
  double angle_step_deg;     /* table grid step in theta; must divide 90; default 0.1 */
  int max_order;             /* N; 0 = per particle, the first n whose Ams_n is isotropic within
                                isotropy_tolerance (capped at SL_OPTICS_MAX_ORDER) */
  double isotropy_tolerance; /* max over theta of |4 pi Ams_n - 1|, default 1e-4 */
  int n_moments;             /* Legendre moments used for Ams_n; 0 = 2 * 180 / step */
  double truncation_deg;     /* forward-peak truncation cone (half angle), default 0.5 (the sun's
                                disk); 0 = one grid step */
  int radius_samples;        /* quadrature points across each size distribution, default 256 */
  long ice_rays;             /* geometric-optics rays per wavelength and habit, default 400000 */
  unsigned long long seed;   /* ice ray tracing; results do not depend on the thread count */
  const char *cache_dir;     /* NULL: $SL_CACHE_DIR, $XDG_CACHE_HOME/stormlight, ~/.cache/stormlight;
                                if none resolves, tables are built without a cache */
  int use_cache;             /* default 1; 0 never reads or writes the cache */
  sl_optics_progress_fn progress; /* optional, called from the building thread */
  void *progress_user;
} sl_optics_request;

/* Defaults: all particle types, the paper's three wavelengths, 0.1 degree. */
void sl_optics_request_defaults(sl_optics_request *req);
/* The tables the fields of v take: each slot's type, or its size (sl_volume.effective_radius_m). */
struct sl_volume;
void sl_optics_request_fields(sl_optics_request *req, const struct sl_volume *v);
/* Wavelength sets by name: "rgb" or "spectral16". Returns SL_ERR_ARG for other names. */
int sl_optics_request_wavelengths(sl_optics_request *req, const char *set_name, sl_error *err);

/* Everything about one particle type at one wavelength. Read-only for callers. */
typedef struct sl_phase_table {
  double wavelength_nm;
  double sigma_ext;         /* m^2 per representative particle of sl_particles.h (see OPTICS.md) */
  double albedo;            /* single-scattering albedo */
  double asymmetry;         /* g = chi_1 of the untruncated P */
  double truncated_fraction;/* f: weight of the forward Dirac in P */
  int n_angles;             /* grid theta_j = j * step_rad, j = 0..n_angles-1, last = pi */
  double step_rad, inv_step_rad;
  int max_order;            /* N */
  const float *ams;         /* (N+1) rows of n_angles: smooth part of Ams_n, 1/sr */
  const double *delta;      /* N+1 Dirac weights, delta[n] = f^n */
  const double *forward;    /* N+1 forward fractions F_n (eq. 23), Dirac included */
  int n_moments;
  const double *moments;    /* chi_l of P (Dirac included), l = 0..n_moments-1, chi_0 = 1 */
} sl_phase_table;

typedef struct sl_optics_tables sl_optics_tables;

/* Builds (or loads from the cache) the tables the request names. Returns NULL and fills err
 * on failure. */
sl_optics_tables *sl_optics_build(const sl_optics_request *req, sl_error *err);
void sl_optics_free(sl_optics_tables *tables);

int sl_optics_wavelength_count(const sl_optics_tables *tables);
double sl_optics_wavelength(const sl_optics_tables *tables, int wl_index);
/* NULL when the particle was not requested or wl_index is out of range. */
const sl_phase_table *sl_optics_table(const sl_optics_tables *tables, sl_particle p, int wl_index);
/* Type p's table at the effective radius of a requested size (0: the type's own). */
const sl_phase_table *sl_optics_table_sized(const sl_optics_tables *tables, sl_particle p, double r_eff_m,
                                            int wl_index);

typedef struct sl_optics_stats {
  int tables_built, tables_loaded, cache_rejected; /* per particle type */
  double build_seconds, load_seconds;
  char cache_dir[512];
} sl_optics_stats;
void sl_optics_get_stats(const sl_optics_tables *tables, sl_optics_stats *stats);

/* Smooth part of Ams_n at the scattering angle theta (radians, 0..pi), linear in theta
 * between grid points: for callers that already have the angle (no acos). */
static inline double sl_phase_table_ams_theta(const sl_phase_table *t, int n, double theta)
{
  if (n < 0) n = 0;
  if (n > t->max_order) n = t->max_order;
  const double u = (theta > 0.0 ? theta : 0.0) * t->inv_step_rad;
  int i = (int)u;
  if (i > t->n_angles - 2) i = t->n_angles - 2;
  const double w = u - i > 1.0 ? 1.0 : u - i;
  const float *row = t->ams + (size_t)n * (size_t)t->n_angles;
  return row[i] + w * (row[i + 1] - row[i]);
}

/* Smooth part of Ams_n at cos_theta, linear in theta between grid points. */
static inline double sl_phase_table_ams(const sl_phase_table *t, int n, double cos_theta)
{
  if (n < 0) n = 0;
  if (n > t->max_order) n = t->max_order;
  const double c = sl_clamp_cosine(cos_theta);
  const double u = acos(c) * t->inv_step_rad;
  int i = (int)u;
  if (i > t->n_angles - 2) i = t->n_angles - 2;
  const double w = u - i;
  const float *row = t->ams + (size_t)n * (size_t)t->n_angles;
  return row[i] + w * (row[i + 1] - row[i]);
}

/* The renderer's per-sample call: smooth part of Ams_n for particle p at wavelength index wl.
 * Returns 0 for a particle that was not built. */
static inline double sl_optics_ams(const sl_optics_tables *tables, sl_particle p, int wl, int n, double cos_theta)
{
  const sl_phase_table *t = sl_optics_table(tables, p, wl);
  return t ? sl_phase_table_ams(t, n, cos_theta) : 0.0;
}

/* Forward fraction F_n (eq. 23), clamped to n = 0..N. */
static inline double sl_phase_table_forward(const sl_phase_table *t, int n)
{
  return t->forward[n < 0 ? 0 : (n > t->max_order ? t->max_order : n)];
}

/* Smallest n whose Ams_n is isotropic within tol (max over the grid of |4 pi ams[n] - 1| below
 * tol and Dirac weight delta[n] below tol); -1 if no n <= N is. */
int sl_phase_table_isotropic_order(const sl_phase_table *t, double tol);

/* The cache directory the request resolves to (no directory is created). */
int sl_optics_cache_dir(const sl_optics_request *req, char *out, int out_size, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
