/* The model grid's columns by latitude and longitude (sl_georef.h, sl_column_map): the file's own
 * XLAT/XLONG (or the placement's) interpolated bilinearly within each cell, and its inversion by
 * Newton's method from the nearest column, for map layers draped on the grid. */
#include <math.h>
#include <stddef.h>

#include "sl_georef.h"

void sl_column_map_init(sl_column_map *m, int nx, int ny, const double *lat, const double *lon, const double origin[2],
                        const double spacing[2])
{
  m->nx = nx, m->ny = ny, m->lat = lat, m->lon = lon;
  for (int a = 0; a < 2; ++a) m->origin[a] = origin[a], m->spacing[a] = spacing[a];
}

static int clamp_int(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

void sl_column_map_lonlat(const sl_column_map *m, double fi, double fj, double *lon, double *lat)
{
  /* Bilinear in the cell, extrapolated linearly past the edges (for Newton's steps). */
  const int i = clamp_int((int)floor(fi), 0, m->nx - 2), j = clamp_int((int)floor(fj), 0, m->ny - 2);
  const double u = fi - i, v = fj - j;
  const size_t c00 = (size_t)j * m->nx + i, c10 = c00 + 1, c01 = c00 + m->nx, c11 = c01 + 1;
  const double w00 = (1 - u) * (1 - v), w10 = u * (1 - v), w01 = (1 - u) * v, w11 = u * v;
  *lon = w00 * m->lon[c00] + w10 * m->lon[c10] + w01 * m->lon[c01] + w11 * m->lon[c11];
  *lat = w00 * m->lat[c00] + w10 * m->lat[c10] + w01 * m->lat[c01] + w11 * m->lat[c11];
}

int sl_column_map_to_grid(const sl_column_map *m, double lat, double lon, double *fi, double *fj)
{
  if (!m->lat || !m->lon || m->nx < 2 || m->ny < 2) return 0;
  size_t best = 0;
  double best_d = INFINITY;
  for (size_t c = 0; c < (size_t)m->nx * m->ny; ++c) {
    const double dl = (m->lon[c] - lon) * cos(lat * M_PI / 180.0), dp = m->lat[c] - lat;
    const double d = dl * dl + dp * dp;
    if (d < best_d) best_d = d, best = c;
  }
  double x = (double)(best % m->nx), y = (double)(best / m->nx);
  for (int it = 0; it < 20; ++it) {
    /* The Jacobian by forward differences of the bilinear map. */
    double lo0, la0, lo1, la1, lo2, la2;
    const double h = 1e-3;
    sl_column_map_lonlat(m, x, y, &lo0, &la0);
    sl_column_map_lonlat(m, x + h, y, &lo1, &la1);
    sl_column_map_lonlat(m, x, y + h, &lo2, &la2);
    const double a = (lo1 - lo0) / h, b = (lo2 - lo0) / h, c = (la1 - la0) / h, d = (la2 - la0) / h;
    const double det = a * d - b * c;
    if (det == 0.0) return 0;
    const double r0 = lon - lo0, r1 = lat - la0;
    const double dx = (d * r0 - b * r1) / det, dy = (-c * r0 + a * r1) / det;
    x += dx, y += dy;
    if (fabs(dx) + fabs(dy) < 1e-9) break;
  }
  *fi = x, *fj = y;
  return x >= 0.0 && y >= 0.0 && x <= m->nx - 1 && y <= m->ny - 1;
}

void sl_column_map_world(const sl_column_map *m, double fi, double fj, double *x, double *y)
{
  *x = m->origin[0] + fi * m->spacing[0];
  *y = m->origin[1] + fj * m->spacing[1];
}

void sl_column_map_range(const sl_column_map *m, double *lon0, double *lon1, double *lat0, double *lat1)
{
  *lon0 = *lat0 = INFINITY, *lon1 = *lat1 = -INFINITY;
  for (size_t c = 0; c < (size_t)m->nx * m->ny; ++c) {
    *lon0 = fmin(*lon0, m->lon[c]), *lon1 = fmax(*lon1, m->lon[c]);
    *lat0 = fmin(*lat0, m->lat[c]), *lat1 = fmax(*lat1, m->lat[c]);
  }
}
