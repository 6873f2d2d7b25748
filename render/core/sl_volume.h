/* The uniform east-north-up voxel grid every renderer reads: number concentration (m^-3) per
 * particle field, cell-centred samples. World frame: local ENU metres around the grid's centre,
 * z up (height above mean sea level). */
#ifndef SL_VOLUME_H
#define SL_VOLUME_H

#include <stddef.h>

#include "sl_particles.h"
#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fields: slot p < SL_PARTICLE_COUNT holds particle type p; the slots above hold further sizes of
 * a type (io/size_bins.c). At most SL_VOLUME_MAX_FIELDS are held at once: the renderer's eight
 * per-sample lanes. */
#define SL_VOLUME_SLOTS (2 * SL_PARTICLE_COUNT)
#define SL_VOLUME_MAX_FIELDS 8

typedef struct sl_volume {
  int nx, ny, nz;            /* samples along east, north, up */
  double origin[3];          /* world position of sample (0,0,0), metres */
  double spacing[3];         /* dx, dy, dz in metres, all > 0 */
  float *eta[SL_VOLUME_SLOTS]; /* number concentration, x fastest; NULL when the field is absent */
  sl_particle extra_type[SL_VOLUME_SLOTS - SL_PARTICLE_COUNT]; /* type of slot SL_PARTICLE_COUNT + i */
  /* Effective radius of the size distribution whose optics tables the slot's particles take
   * (sl_optics_request.sizes); 0: the type's own tables. eta counts the type's representative
   * particles (sl_particles.h) either way. */
  double effective_radius_m[SL_VOLUME_SLOTS];
  /* Where the fields may be non-zero, when the one who filled them knows (the loader: where the
   * remap deposited): samples content_lo .. content_hi (inclusive, empty where lo > hi), every
   * field zero outside. Zero-initialised (content_known 0): anywhere. Passes over the fields read
   * only this box: a storm's clear air is most of a large grid, and never written it takes no
   * memory until read (some kernels give even a read its own page). */
  int content_known;
  int content_lo[3], content_hi[3];
} sl_volume;

static inline sl_particle sl_volume_field_type(const sl_volume *v, int slot)
{
  return slot < SL_PARTICLE_COUNT ? (sl_particle)slot : v->extra_type[slot - SL_PARTICLE_COUNT];
}

/* Allocates an empty volume (no fields). */
int sl_volume_init(sl_volume *v, int nx, int ny, int nz, const double origin[3], const double spacing[3],
                   sl_error *err);
/* Allocates type p's own field (slot p) filled with zeros. */
int sl_volume_add_field(sl_volume *v, sl_particle p, sl_error *err);
/* Allocates a zero field of type p whose particles take the tables of effective radius r_eff_m:
 * slot p when it is free, else the first free slot above the types. *slot receives it. */
int sl_volume_add_sized_field(sl_volume *v, sl_particle p, double r_eff_m, int *slot, sl_error *err);
/* Number of slots that hold a field. */
int sl_volume_field_count(const sl_volume *v);
/* Frees one slot's field (NULL again: absent). */
void sl_volume_drop_field(sl_volume *v, int slot);
void sl_volume_free(sl_volume *v);
size_t sl_volume_count(const sl_volume *v);
static inline size_t sl_volume_index(const sl_volume *v, int i, int j, int k)
{
  return ((size_t)k * (size_t)v->ny + (size_t)j) * (size_t)v->nx + (size_t)i;
}
/* The samples that may hold medium (content_lo .. content_hi where content_known, else the whole
 * grid) into lo, hi (inclusive); 0 when there are none. */
int sl_volume_content_samples(const sl_volume *v, int lo[3], int hi[3]);
/* The rows along x of the box lo .. hi (from sl_volume_content_samples), in the grid's order: how
 * many, and the index of row r's first sample (each row holds hi[0] - lo[0] + 1). */
static inline long sl_volume_box_rows(const int lo[3], const int hi[3])
{
  return (long)(hi[1] - lo[1] + 1) * (long)(hi[2] - lo[2] + 1);
}
static inline size_t sl_volume_box_row(const sl_volume *v, const int lo[3], const int hi[3], long r)
{
  const long ny = hi[1] - lo[1] + 1;
  return sl_volume_index(v, lo[0], lo[1] + (int)(r % ny), lo[2] + (int)(r / ny));
}
/* Axis-aligned box covered by the cells: samples sit at cell centres. */
void sl_volume_bounds(const sl_volume *v, double lo[3], double hi[3]);
/* The boxes around the storm's condensate, one per threshold tau_min[b], from one pass over the
 * fields (it reads every sample of every field: seconds at 10^8 samples): the columns whose
 * vertical optical depth (Table 2's cross-sections) reaches tau_min[b], and within them the
 * samples whose extinction reaches beta_min (m^-1); box b in lo[b], hi[b] where found[b] (no column
 * reaches it: 0, its box untouched). Returns whether any was found (0 also when the column sums
 * find no memory). */
int sl_volume_condensate_boxes(const sl_volume *v, int n, const double *tau_min, double beta_min, double (*lo)[3],
                               double (*hi)[3], int *found);

/* A scalar field on the same lattice, sampled trilinearly between cell centres and clamped to
 * the outer cell centres inside the box; zero outside the box. */
typedef struct sl_grid_view {
  const float *data;
  int n[3];
  double origin[3];
  double inv_spacing[3];
  double lo[3], hi[3];
} sl_grid_view;

/* Parametric interval [t0, t1] where the ray o + t d lies in the box [lo, hi] (slab method;
 * d need not be unit; a zero component requires o inside that slab). Returns 0 when it misses. */
int sl_ray_box(const double lo[3], const double hi[3], const double o[3], const double d[3], double *t0, double *t1);

void sl_grid_view_init(sl_grid_view *g, const float *data, const sl_volume *shape);
double sl_grid_sample(const sl_grid_view *g, const double p[3]);

#ifdef __cplusplus
}
#endif
#endif
