/* Georeferencing a WRF grid (sl_georef.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sl_georef.h"

static double wrap180(double a) { return a - 360.0 * floor((a + 180.0) / 360.0); }

void sl_georef_grid_latlon(const sl_georef *g, double i, double j, double *lat, double *lon)
{
  sl_projection_reverse(&g->projection, g->x0 + i * g->dx, g->y0 + j * g->dy, lat, lon);
}

/* Samples every s-th index and always the last, so the edges and corners are checked. */
static int sample_stride(int n) { return n > 200 ? n / 200 : 1; }
static int next_index(int k, int s, int n) { return k == n - 1 ? n : (k + s < n - 1 ? k + s : n - 1); }

/* Latitude/longitude at fractional grid position by bilinear interpolation of the file's
 * arrays, longitude unwrapped around the first corner. */
static void xlat_at(const double *xlat, const double *xlon, int nx, int ny, double i, double j, double *lat,
                    double *lon)
{
  int i0 = (int)floor(i), j0 = (int)floor(j);
  if (i0 > nx - 2) i0 = nx - 2;
  if (j0 > ny - 2) j0 = ny - 2;
  if (i0 < 0) i0 = 0;
  if (j0 < 0) j0 = 0;
  const double fi = nx > 1 ? i - i0 : 0.0, fj = ny > 1 ? j - j0 : 0.0;
  const int i1 = nx > 1 ? i0 + 1 : i0, j1 = ny > 1 ? j0 + 1 : j0;
  const size_t c[4] = {(size_t)j0 * nx + i0, (size_t)j0 * nx + i1, (size_t)j1 * nx + i0, (size_t)j1 * nx + i1};
  const double w[4] = {(1 - fi) * (1 - fj), fi * (1 - fj), (1 - fi) * fj, fi * fj};
  double la = 0.0, lo = 0.0;
  for (int k = 0; k < 4; ++k) {
    la += w[k] * xlat[c[k]];
    lo += w[k] * (xlon[c[0]] + wrap180(xlon[c[k]] - xlon[c[0]]));
  }
  *lat = la;
  *lon = wrap180(lo);
}

/* The grid's local frame at position (i, j): ground spacing along both axes and the azimuth of
 * +y, from positions half a cell either side (the projection's or the file's). */
static void local_frame(const sl_georef *g, const double *xlat, const double *xlon, double i, double j, double *gdx,
                        double *gdy, double *north)
{
  double la[4], lo[4];
  const double at[4][2] = {{i - 0.5, j}, {i + 0.5, j}, {i, j - 0.5}, {i, j + 0.5}};
  for (int k = 0; k < 4; ++k) {
    if (g->from_xlat) xlat_at(xlat, xlon, g->nx, g->ny, at[k][0], at[k][1], &la[k], &lo[k]);
    else sl_georef_grid_latlon(g, at[k][0], at[k][1], &la[k], &lo[k]);
  }
  double azi;
  sl_sphere_inverse(la[0], lo[0], la[1], lo[1], gdx, &azi);
  sl_sphere_inverse(la[2], lo[2], la[3], lo[3], gdy, north);
}

static void place_from_xlat(sl_georef *g, const double *xlat, const double *xlon);

int sl_georef_build(sl_georef *g, int map_proj, double truelat1, double truelat2, double stand_lon,
                    double pole_lat, double pole_lon, int nx, int ny, double dx, double dy, const double *xlat,
                    const double *xlon, const char *path, sl_error *err)
{
  memset(g, 0, sizeof *g);
  char why[200] = "";
  const int known = map_proj == SL_MAP_LAMBERT || map_proj == SL_MAP_POLAR || map_proj == SL_MAP_MERCATOR ||
                    map_proj == SL_MAP_LATLON;
  const int usable = !sl_projection_init(&g->projection, map_proj, truelat1, truelat2, stand_lon, pole_lat,
                                         pole_lon, why, sizeof why);
  if (!known) return sl_fail(err, SL_ERR_FORMAT, "%s: MAP_PROJ %d: %s", path, map_proj, why);
  if (nx < 2 || ny < 2) return sl_fail(err, SL_ERR_FORMAT, "%s: a %dx%d grid is too small to place", path, nx, ny);
  g->nx = nx, g->ny = ny, g->dx = dx, g->dy = dy;
  const size_t n2 = (size_t)nx * ny;
  for (size_t c = 0; c < n2; ++c)
    if (!(fabs(xlat[c]) <= 90.0) || !(fabs(xlon[c]) <= 540.0))
      return sl_fail(err, SL_ERR_DATA, "%s: XLAT/XLONG out of range (%g, %g)", path, xlat[c], xlon[c]);
  g->placed = 1;
  if (!usable) {
    /* A known projection whose attributes are missing or invalid: XLAT/XLONG still place it. */
    g->max_error_deg = g->max_error_m = NAN;
    g->from_xlat = 1;
    snprintf(g->note, sizeof g->note, "%s: MAP_PROJ %d: %s; placing the grid by XLAT/XLONG", path, map_proj, why);
    place_from_xlat(g, xlat, xlon);
    return SL_OK;
  }

  /* The grid is uniform on the plane: plane(i, j) = (x0 + i dx, y0 + j dy). The offset is the
   * mean of plane - (i dx, j dy) over the sampled points (least squares for a pure shift), so a
   * crop or a moving nest needs no CEN_LAT/CEN_LON; longitudes wrap with x_period. */
  const int si = sample_stride(nx), sj = sample_stride(ny);
  const double period = g->projection.x_period;
  double sx = 0.0, sy = 0.0, first = NAN;
  long count = 0;
  for (int j = 0; j < ny; j = next_index(j, sj, ny))
    for (int i = 0; i < nx; i = next_index(i, si, nx)) {
      double x, y;
      sl_projection_forward(&g->projection, xlat[(size_t)j * nx + i], xlon[(size_t)j * nx + i], &x, &y);
      if (!isfinite(x) || !isfinite(y))
        return sl_fail(err, SL_ERR_DATA, "%s: XLAT/XLONG (%g, %g) has no place on MAP_PROJ %d", path,
                       xlat[(size_t)j * nx + i], xlon[(size_t)j * nx + i], map_proj);
      x -= i * dx;
      y -= j * dy;
      if (isnan(first)) first = x;
      if (period > 0.0) x += period * round((first - x) / period);
      sx += x, sy += y, ++count;
    }
  g->x0 = sx / count, g->y0 = sy / count;

  for (int j = 0; j < ny; j = next_index(j, sj, ny))
    for (int i = 0; i < nx; i = next_index(i, si, nx)) {
      const size_t c = (size_t)j * nx + i;
      double la, lo, s, azi;
      sl_georef_grid_latlon(g, i, j, &la, &lo);
      const double e = fmax(fabs(la - xlat[c]), fabs(wrap180(lo - xlon[c])));
      if (e > g->max_error_deg) g->max_error_deg = e;
      sl_sphere_inverse(la, lo, xlat[c], xlon[c], &s, &azi);
      if (s > g->max_error_m) g->max_error_m = s;
    }
  const double cell = dx < dy ? dx : dy;
  g->from_xlat = !(g->max_error_m <= SL_GEOREF_TRUST_CELLS * cell);
  if (g->from_xlat)
    snprintf(g->note, sizeof g->note,
             "%s: MAP_PROJ %d from the attributes misses XLAT/XLONG by up to %.0f m (%.2f cells, %.4f deg); placing "
             "the grid by XLAT/XLONG",
             path, map_proj, g->max_error_m, g->max_error_m / cell, g->max_error_deg);

  place_from_xlat(g, xlat, xlon);
  return SL_OK;
}

/* Centre, corners, spacing, grid north and map factors, by the projection or by XLAT/XLONG. */
static void place_from_xlat(sl_georef *g, const double *xlat, const double *xlon)
{
  const int nx = g->nx, ny = g->ny;
  const double dx = g->dx, dy = g->dy;
  const double ic = 0.5 * (nx - 1), jc = 0.5 * (ny - 1);
  const double corner[4][2] = {{0, 0}, {nx - 1, 0}, {nx - 1, ny - 1}, {0, ny - 1}};
  if (g->from_xlat) {
    xlat_at(xlat, xlon, nx, ny, ic, jc, &g->center_lat, &g->center_lon);
    for (int k = 0; k < 4; ++k) {
      const size_t c = (size_t)corner[k][1] * nx + (size_t)corner[k][0];
      g->corner_lat[k] = xlat[c], g->corner_lon[k] = wrap180(xlon[c]);
    }
  } else {
    sl_georef_grid_latlon(g, ic, jc, &g->center_lat, &g->center_lon);
    for (int k = 0; k < 4; ++k) sl_georef_grid_latlon(g, corner[k][0], corner[k][1], &g->corner_lat[k], &g->corner_lon[k]);
  }
  local_frame(g, xlat, xlon, ic, jc, &g->ground_dx, &g->ground_dy, &g->grid_north_deg);
  /* Map factors at the centre, edge midpoints and corners (half a cell inside): how far the
   * uniform spacing used for the volume is from the ground distance anywhere in the grid. */
  g->map_factor_min = INFINITY, g->map_factor_max = 0.0;
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a) {
      const double i = a == 0 ? 0.5 : a == 1 ? ic : nx - 1.5, j = b == 0 ? 0.5 : b == 1 ? jc : ny - 1.5;
      double gdx, gdy, north;
      local_frame(g, xlat, xlon, i, j, &gdx, &gdy, &north);
      const double m[2] = {dx / gdx, dy / gdy};
      for (int k = 0; k < 2; ++k) {
        if (m[k] < g->map_factor_min) g->map_factor_min = m[k];
        if (m[k] > g->map_factor_max) g->map_factor_max = m[k];
      }
    }
  sl_georef_place(g, NAN, NAN);
}

void sl_georef_place(sl_georef *g, double origin_lat, double origin_lon)
{
  const int own = !(isfinite(origin_lat) && isfinite(origin_lon));
  g->origin_lat = own ? g->center_lat : origin_lat;
  g->origin_lon = own ? g->center_lon : origin_lon;
  sl_enu_forward(g->origin_lat, g->origin_lon, g->center_lat, g->center_lon, 0.0, g->center_enu);
  /* True north at the centre seen in the world frame: toward a point 1 km north of it. */
  double north[3];
  const double step = 1000.0 / (SL_WRF_EARTH_RADIUS * M_PI / 180.0);
  const double lat_n = g->center_lat + (g->center_lat < 89.0 ? step : -step);
  sl_enu_forward(g->origin_lat, g->origin_lon, lat_n, g->center_lon, 0.0, north);
  double de = north[0] - g->center_enu[0], dn = north[1] - g->center_enu[1];
  if (g->center_lat >= 89.0) de = -de, dn = -dn;
  g->frame_rotation_deg = atan2(de, dn) * 180.0 / M_PI;
}

void sl_georef_flat(sl_georef *g, int nx, int ny, double dx, double dy)
{
  memset(g, 0, sizeof *g);
  g->nx = nx, g->ny = ny, g->dx = g->ground_dx = dx, g->dy = g->ground_dy = dy;
  g->map_factor_min = g->map_factor_max = 1.0;
  g->max_error_deg = g->max_error_m = NAN;
  g->center_lat = g->center_lon = g->origin_lat = g->origin_lon = NAN;
  for (int k = 0; k < 4; ++k) g->corner_lat[k] = g->corner_lon[k] = NAN;
  snprintf(g->note, sizeof g->note, "MAP_PROJ 0 (an idealized run): a flat grid with no place on the earth");
}

double sl_georef_grid_azimuth(const sl_georef *g, double compass_azimuth_deg)
{
  const double a = fmod(compass_azimuth_deg - g->grid_north_deg, 360.0);
  return a < 0.0 ? a + 360.0 : a;
}

double sl_curvature_drop(double r)
{
  const double R = SL_WRF_EARTH_RADIUS;
  if (!(r < R)) return R;
  /* R - sqrt(R^2 - r^2) = r^2 / (R + sqrt(R^2 - r^2)) */
  return r * r / (R + sqrt((R - r) * (R + r)));
}
