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

typedef struct sl_volume {
  int nx, ny, nz;            /* samples along east, north, up */
  double origin[3];          /* world position of sample (0,0,0), metres */
  double spacing[3];         /* dx, dy, dz in metres, all > 0 */
  float *eta[SL_PARTICLE_COUNT]; /* number concentration, x fastest; NULL when the field is absent */
} sl_volume;

/* Allocates an empty volume (no fields). */
int sl_volume_init(sl_volume *v, int nx, int ny, int nz, const double origin[3], const double spacing[3],
                   sl_error *err);
/* Allocates one field filled with zeros. */
int sl_volume_add_field(sl_volume *v, sl_particle p, sl_error *err);
/* Frees one field (NULL again: the type is absent). */
void sl_volume_drop_field(sl_volume *v, sl_particle p);
void sl_volume_free(sl_volume *v);
size_t sl_volume_count(const sl_volume *v);
static inline size_t sl_volume_index(const sl_volume *v, int i, int j, int k)
{
  return ((size_t)k * (size_t)v->ny + (size_t)j) * (size_t)v->nx + (size_t)i;
}
/* Axis-aligned box covered by the cells: samples sit at cell centres. */
void sl_volume_bounds(const sl_volume *v, double lo[3], double hi[3]);

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
