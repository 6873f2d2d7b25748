#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "sl_volume.h"

int sl_volume_init(sl_volume *v, int nx, int ny, int nz, const double origin[3], const double spacing[3],
                   sl_error *err)
{
  *v = (sl_volume){0};
  if (nx < 1 || ny < 1 || nz < 1)
    return sl_fail(err, SL_ERR_ARG, "volume size %dx%dx%d: every dimension must be at least 1", nx, ny, nz);
  /* 2^31 cells of float per field is already 8 GiB: anything larger is a wrong shape, not a storm. */
  if ((double)nx * ny * nz > 2147483647.0)
    return sl_fail(err, SL_ERR_ARG, "volume size %dx%dx%d is absurdly large", nx, ny, nz);
  for (int a = 0; a < 3; ++a) {
    if (!(spacing[a] > 0.0) || !isfinite(spacing[a]) || !isfinite(origin[a]))
      return sl_fail(err, SL_ERR_ARG, "volume spacing/origin along axis %d is not a positive finite number", a);
    v->origin[a] = origin[a];
    v->spacing[a] = spacing[a];
  }
  v->nx = nx;
  v->ny = ny;
  v->nz = nz;
  return SL_OK;
}

int sl_volume_content_samples(const sl_volume *v, int lo[3], int hi[3])
{
  const int n[3] = {v->nx, v->ny, v->nz};
  int any = 1;
  for (int a = 0; a < 3; ++a) {
    lo[a] = v->content_known && v->content_lo[a] > 0 ? v->content_lo[a] : 0;
    hi[a] = v->content_known && v->content_hi[a] < n[a] - 1 ? v->content_hi[a] : n[a] - 1;
    any &= lo[a] <= hi[a];
  }
  return any;
}

int sl_volume_add_field(sl_volume *v, sl_particle p, sl_error *err)
{
  if ((int)p < 0 || p >= SL_PARTICLE_COUNT) return sl_fail(err, SL_ERR_ARG, "unknown particle field %d", (int)p);
  if (v->eta[p]) return SL_OK;
  v->eta[p] = calloc(sl_volume_count(v), sizeof(float));
  if (!v->eta[p]) return sl_fail(err, SL_ERR_NOMEM, "out of memory for a %dx%dx%d field", v->nx, v->ny, v->nz);
  v->effective_radius_m[p] = 0.0;
  return SL_OK;
}

int sl_volume_add_sized_field(sl_volume *v, sl_particle p, double r_eff_m, int *slot, sl_error *err)
{
  if ((int)p < 0 || p >= SL_PARTICLE_COUNT) return sl_fail(err, SL_ERR_ARG, "unknown particle field %d", (int)p);
  if (!(r_eff_m >= 0.0) || !isfinite(r_eff_m))
    return sl_fail(err, SL_ERR_ARG, "effective radius %g m of a %s field", r_eff_m, sl_particle_name(p));
  int k = p;
  if (v->eta[k])
    for (k = SL_PARTICLE_COUNT; k < SL_VOLUME_SLOTS && v->eta[k]; ++k) {
    }
  if (k == SL_VOLUME_SLOTS || sl_volume_field_count(v) >= SL_VOLUME_MAX_FIELDS)
    return sl_fail(err, SL_ERR_ARG, "no free field for another %s size (%d fields at most)", sl_particle_name(p),
                   SL_VOLUME_MAX_FIELDS);
  v->eta[k] = calloc(sl_volume_count(v), sizeof(float));
  if (!v->eta[k]) return sl_fail(err, SL_ERR_NOMEM, "out of memory for a %dx%dx%d field", v->nx, v->ny, v->nz);
  if (k >= SL_PARTICLE_COUNT) v->extra_type[k - SL_PARTICLE_COUNT] = p;
  v->effective_radius_m[k] = r_eff_m;
  *slot = k;
  return SL_OK;
}

int sl_volume_field_count(const sl_volume *v)
{
  int n = 0;
  for (int k = 0; k < SL_VOLUME_SLOTS; ++k) n += v->eta[k] != NULL;
  return n;
}

void sl_volume_drop_field(sl_volume *v, int slot)
{
  if (slot < 0 || slot >= SL_VOLUME_SLOTS) return;
  free(v->eta[slot]);
  v->eta[slot] = NULL;
  v->effective_radius_m[slot] = 0.0;
}

void sl_volume_free(sl_volume *v)
{
  for (int k = 0; k < SL_VOLUME_SLOTS; ++k) free(v->eta[k]);
  *v = (sl_volume){0};
}

size_t sl_volume_count(const sl_volume *v) { return (size_t)v->nx * (size_t)v->ny * (size_t)v->nz; }

void sl_volume_bounds(const sl_volume *v, double lo[3], double hi[3])
{
  const int n[3] = {v->nx, v->ny, v->nz};
  for (int a = 0; a < 3; ++a) {
    lo[a] = v->origin[a] - 0.5 * v->spacing[a];
    hi[a] = v->origin[a] + (n[a] - 0.5) * v->spacing[a];
  }
}

void sl_grid_view_init(sl_grid_view *g, const float *data, const sl_volume *shape)
{
  g->data = data;
  g->n[0] = shape->nx;
  g->n[1] = shape->ny;
  g->n[2] = shape->nz;
  for (int a = 0; a < 3; ++a) {
    g->origin[a] = shape->origin[a];
    g->inv_spacing[a] = 1.0 / shape->spacing[a];
  }
  sl_volume_bounds(shape, g->lo, g->hi);
}

double sl_grid_sample(const sl_grid_view *g, const double p[3])
{
  int i0[3];
  double f[3];
  for (int a = 0; a < 3; ++a) {
    if (!(p[a] >= g->lo[a] && p[a] <= g->hi[a])) return 0.0;
    double u = (p[a] - g->origin[a]) * g->inv_spacing[a];
    const double umax = (double)(g->n[a] - 1);
    if (u < 0.0) u = 0.0;
    if (u > umax) u = umax;
    int i = (int)u;
    if (i > g->n[a] - 2) i = g->n[a] - 2;
    if (i < 0) i = 0;
    i0[a] = i;
    f[a] = g->n[a] > 1 ? u - i : 0.0;
  }
  const int sx = g->n[0] > 1 ? 1 : 0;
  const size_t sy = g->n[1] > 1 ? (size_t)g->n[0] : 0;
  const size_t sz = g->n[2] > 1 ? (size_t)g->n[0] * g->n[1] : 0;
  const float *c = g->data + ((size_t)i0[2] * g->n[1] + i0[1]) * g->n[0] + i0[0];
  const double c00 = c[0] + f[0] * (c[sx] - c[0]);
  const double c10 = c[sy] + f[0] * (c[sy + sx] - c[sy]);
  const double c01 = c[sz] + f[0] * (c[sz + sx] - c[sz]);
  const double c11 = c[sz + sy] + f[0] * (c[sz + sy + sx] - c[sz + sy]);
  const double c0 = c00 + f[1] * (c10 - c00);
  const double c1 = c01 + f[1] * (c11 - c01);
  return c0 + f[2] * (c1 - c0);
}

int sl_ray_box(const double lo[3], const double hi[3], const double o[3], const double d[3], double *t0,
                   double *t1)
{
  double a = -INFINITY, b = INFINITY;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (o[i] < lo[i] || o[i] > hi[i]) return 0;
      continue;
    }
    double ta = (lo[i] - o[i]) / d[i], tb = (hi[i] - o[i]) / d[i];
    if (ta > tb) {
      const double s = ta;
      ta = tb;
      tb = s;
    }
    if (ta > a) a = ta;
    if (tb < b) b = tb;
  }
  *t0 = a;
  *t1 = b;
  return b > a;
}
