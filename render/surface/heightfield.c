/* The terrain as triangles over the storm's columns: lattice points, normals, and the first hit
 * of a ray (what stops the renderer's eye rays). */
#include <math.h>

#include "sl_terrain.h"

void sl_heightfield_point(const sl_heightfield *hf, int i, int j, double p[3])
{
  p[0] = hf->origin[0] + i * hf->spacing[0];
  p[1] = hf->origin[1] + j * hf->spacing[1];
  p[2] = hf->height[(size_t)j * hf->nx + i];
}

double sl_heightfield_height_at(const sl_heightfield *hf, double fi, double fj)
{
  if (!hf->height || hf->nx < 2 || hf->ny < 2) return hf->height ? hf->height[0] : 0.0;
  int i = (int)floor(fi), j = (int)floor(fj);
  i = i < 0 ? 0 : i > hf->nx - 2 ? hf->nx - 2 : i;
  j = j < 0 ? 0 : j > hf->ny - 2 ? hf->ny - 2 : j;
  double u = fi - i, v = fj - j;
  u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
  v = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
  const float *h = hf->height + (size_t)j * hf->nx + i;
  const double h00 = h[0], h10 = h[1], h01 = h[hf->nx], h11 = h[hf->nx + 1];
  /* The cell's triangles (00, 10, 11) for u >= v and (00, 11, 01) otherwise, as the ray hits. */
  if (u >= v) return (1 - u) * h00 + (u - v) * h10 + v * h11;
  return (1 - v) * h00 + u * h11 + (v - u) * h01;
}

void sl_heightfield_normal(const sl_heightfield *hf, int i, int j, double n[3])
{
  const int i0 = i > 0 ? i - 1 : i, i1 = i < hf->nx - 1 ? i + 1 : i;
  const int j0 = j > 0 ? j - 1 : j, j1 = j < hf->ny - 1 ? j + 1 : j;
  const float *h = hf->height;
  const double dzdx = (h[(size_t)j * hf->nx + i1] - h[(size_t)j * hf->nx + i0]) / ((i1 - i0) * hf->spacing[0]);
  const double dzdy = (h[(size_t)j1 * hf->nx + i] - h[(size_t)j0 * hf->nx + i]) / ((j1 - j0) * hf->spacing[1]);
  const double len = sqrt(dzdx * dzdx + dzdy * dzdy + 1.0);
  n[0] = -dzdx / len;
  n[1] = -dzdy / len;
  n[2] = 1.0 / len;
}

/* Moller-Trumbore, front faces only; edges count as inside (a small tolerance), so a ray through the shared
 * diagonal or a cell edge cannot slip between two triangles. */
static int ray_triangle(const double o[3], const double d[3], const double a[3], const double b[3], const double c[3],
                        double *t)
{
  const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
  const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
  /* One-sided: a ray meets the ground from above (det = -d . n > 0 for the upward normal). From
   * below, it has already gone through the earth (behind the round earth's horizon). */
  if (!(det > 1e-300)) return 0;
  const double inv = 1.0 / det;
  const double s[3] = {o[0] - a[0], o[1] - a[1], o[2] - a[2]};
  const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
  const double tol = 1e-9;
  if (u < -tol || u > 1.0 + tol) return 0;
  const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
  const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
  if (v < -tol || u + v > 1.0 + tol) return 0;
  *t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
  return 1;
}

static int cell_hit(const sl_heightfield *hf, int i, int j, const double o[3], const double d[3], double t_lo,
                    double t_hi, double *t_best)
{
  double p00[3], p10[3], p11[3], p01[3], t;
  sl_heightfield_point(hf, i, j, p00);
  sl_heightfield_point(hf, i + 1, j, p10);
  sl_heightfield_point(hf, i + 1, j + 1, p11);
  sl_heightfield_point(hf, i, j + 1, p01);
  int hit = 0;
  if (ray_triangle(o, d, p00, p10, p11, &t) && t > t_lo && t <= t_hi) *t_best = t, t_hi = t, hit = 1;
  if (ray_triangle(o, d, p00, p11, p01, &t) && t > t_lo && t <= t_hi) *t_best = t, hit = 1;
  return hit;
}

int sl_heightfield_ray(const sl_heightfield *hf, const double o[3], const double d[3], double t_max, double *t_hit)
{
  if (hf->nx < 2 || hf->ny < 2) return 0;
  float zmin = INFINITY, zmax = -INFINITY;
  if (hf->zmax >= hf->zmin) zmin = (float)hf->zmin, zmax = (float)hf->zmax;
  else
    for (size_t c = 0; c < (size_t)hf->nx * hf->ny; ++c) {
      if (hf->height[c] < zmin) zmin = hf->height[c];
      if (hf->height[c] > zmax) zmax = hf->height[c];
    }
  /* Only the slab of heights the terrain spans can hold a hit: rays from above skip the rest. */
  const double lo[3] = {hf->origin[0], hf->origin[1], zmin - 1.0};
  const double hi[3] = {hf->origin[0] + (hf->nx - 1) * hf->spacing[0], hf->origin[1] + (hf->ny - 1) * hf->spacing[1],
                        zmax + 1.0};
  double ta, tb;
  if (!sl_ray_box(lo, hi, o, d, &ta, &tb)) return 0;
  const double t_floor = 1e-9 * (1.0 + fabs(hf->spacing[0]));
  if (ta < 0.0) ta = 0.0;
  if (tb > t_max) tb = t_max;
  if (tb < ta) return 0;
  /* 2-D DDA over the cells, from where the ray enters the slab. */
  const double x = o[0] + ta * d[0] - hf->origin[0], y = o[1] + ta * d[1] - hf->origin[1];
  int i = (int)floor(x / hf->spacing[0]), j = (int)floor(y / hf->spacing[1]);
  i = i < 0 ? 0 : i > hf->nx - 2 ? hf->nx - 2 : i;
  j = j < 0 ? 0 : j > hf->ny - 2 ? hf->ny - 2 : j;
  const int step_i = d[0] > 0.0 ? 1 : -1, step_j = d[1] > 0.0 ? 1 : -1;
  double next_i = INFINITY, next_j = INFINITY, delta_i = INFINITY, delta_j = INFINITY;
  if (d[0] != 0.0) {
    next_i = (hf->origin[0] + (i + (step_i > 0)) * hf->spacing[0] - o[0]) / d[0];
    delta_i = hf->spacing[0] / fabs(d[0]);
  }
  if (d[1] != 0.0) {
    next_j = (hf->origin[1] + (j + (step_j > 0)) * hf->spacing[1] - o[1]) / d[1];
    delta_j = hf->spacing[1] / fabs(d[1]);
  }
  for (;;) {
    double t;
    if (cell_hit(hf, i, j, o, d, t_floor, tb, &t)) {
      *t_hit = t;
      return 1;
    }
    const double t_exit = next_i < next_j ? next_i : next_j;
    if (!(t_exit <= tb)) return 0;
    if (next_i < next_j) {
      i += step_i;
      next_i += delta_i;
    } else {
      j += step_j;
      next_j += delta_j;
    }
    if (i < 0 || j < 0 || i > hf->nx - 2 || j > hf->ny - 2) return 0;
  }
}

void sl_heightfield_init(sl_heightfield *hf, int nx, int ny, const double origin[2], const double spacing[2],
                         const float *height)
{
  hf->nx = nx, hf->ny = ny;
  hf->origin[0] = origin[0], hf->origin[1] = origin[1];
  hf->spacing[0] = spacing[0], hf->spacing[1] = spacing[1];
  hf->height = height;
  hf->zmin = INFINITY, hf->zmax = -INFINITY;
  for (size_t c = 0; c < (size_t)nx * ny; ++c) {
    if (height[c] < hf->zmin) hf->zmin = height[c];
    if (height[c] > hf->zmax) hf->zmax = height[c];
  }
}
