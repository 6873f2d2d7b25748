/* Georeferencing against outside values: grid latitude/longitude from io/geo.cpp and io/georef.c
 * against PROJ (proj-bin's `proj`, run here on WRF's sphere, +R=6370000) for all four WRF
 * projections on synthetic grids, against the real files' own XLAT/XLONG and MAPFAC_M, each
 * Katrina frame's volume centre against the ENU position of that time's XLAT/XLONG centre (an
 * independent spherical formula), and the curvature drop against the exact sphere. */
#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sl_georef.h"
#include "sl_storm.h"
#include "sl_testing.h"

#define R_WRF 6370000.0
#define DEG (M_PI / 180.0)

/* Runs `proj ARGS` (forward, or inverse with -I) on n coordinate pairs; 0 on success. */
static int run_proj(const char *args, int inverse, const double *a, const double *b, int n, double *out_a,
                    double *out_b)
{
  char in[] = "/tmp/sl_test_projXXXXXX";
  const int fd = mkstemp(in);
  if (fd < 0) return 1;
  FILE *f = fdopen(fd, "w");
  for (int k = 0; k < n; ++k) fprintf(f, "%.10f %.10f\n", a[k], b[k]);
  fclose(f);
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "proj %s -f %%.10f %s %s", inverse ? "-I" : "", args, in);
  FILE *p = popen(cmd, "r");
  int got = 0;
  if (p) {
    while (got < n && fscanf(p, "%lf %lf", &out_a[got], &out_b[got]) == 2) ++got;
    pclose(p);
  }
  unlink(in);
  return got == n ? 0 : 1;
}

/* Great-circle distance and initial bearing on the sphere (haversine, the test's own formulas). */
static double haversine(double la1, double lo1, double la2, double lo2)
{
  const double s = sin(0.5 * (la2 - la1) * DEG), t = sin(0.5 * (lo2 - lo1) * DEG);
  return 2.0 * R_WRF * asin(sqrt(s * s + cos(la1 * DEG) * cos(la2 * DEG) * t * t));
}
static double bearing(double la1, double lo1, double la2, double lo2)
{
  const double dl = (lo2 - lo1) * DEG;
  return atan2(sin(dl) * cos(la2 * DEG), cos(la1 * DEG) * sin(la2 * DEG) - sin(la1 * DEG) * cos(la2 * DEG) * cos(dl)) /
         DEG;
}
static double wrap180(double a) { return a - 360.0 * floor((a + 180.0) / 360.0); }

typedef struct grid_case {
  const char *name;
  int map_proj;
  double truelat1, truelat2, stand_lon, pole_lat, pole_lon;
  const char *proj; /* the same projection for PROJ */
  double center_lat, center_lon, dx;
  int nx, ny;
} grid_case;

static const grid_case CASES[] = {
    {"Lambert, two true latitudes", 1, 30, 60, -98, 90, 0, "+proj=lcc +lat_1=30 +lat_2=60 +lat_0=30 +lon_0=-98 +R=6370000",
     38, -90, 12000, 61, 50},
    {"Lambert, tangent", 1, 45, 45, 10, 90, 0, "+proj=lcc +lat_1=45 +lat_0=45 +lon_0=10 +R=6370000", 48, 16, 9000, 40,
     45},
    {"Lambert, southern", 1, -20, -40, 140, 90, 0, "+proj=lcc +lat_1=-20 +lat_2=-40 +lat_0=-30 +lon_0=140 +R=6370000",
     -31, 147, 15000, 50, 40},
    {"polar stereographic, north", 2, 60, 60, -150, 90, 0, "+proj=stere +lat_0=90 +lat_ts=60 +lon_0=-150 +R=6370000",
     72, -130, 20000, 60, 60},
    {"polar stereographic, south", 2, -71, -71, 0, 90, 0, "+proj=stere +lat_0=-90 +lat_ts=-71 +lon_0=0 +R=6370000",
     -75, 40, 15000, 50, 60},
    {"Mercator, true at 30", 3, 30, 0, -70, 90, 0, "+proj=merc +lat_ts=30 +lon_0=-70 +R=6370000", 20, -65, 10000, 60,
     50},
    {"Mercator across the dateline", 3, 0, 0, 180, 90, 0, "+proj=merc +lat_ts=0 +lon_0=180 +R=6370000", 10, 179.5,
     25000, 40, 30},
    {"latitude-longitude", 6, 0, 0, 0, 90, 0, "+proj=eqc +R=6370000", 10, 20, 50000, 40, 30},
    /* WPS's recipe for a rotated regional grid centred at (40 N, 100 W): pole_lat = 90 - 40,
     * pole_lon = 180, stand_lon = 100; PROJ's o_lat_p/o_lon_p are the same quantities. */
    {"rotated latitude-longitude", 6, 0, 0, 100, 50, 180,
     "+proj=ob_tran +o_proj=eqc +o_lat_p=50 +o_lon_p=180 +lon_0=-100 +R=6370000", 40, -100, 25000, 60, 50},
    {"rotated latitude-longitude, pole_lon 170", 6, 0, 0, -15, 35, 170,
     "+proj=ob_tran +o_proj=eqc +o_lat_p=35 +o_lon_p=170 +lon_0=15 +R=6370000", 52, 8, 20000, 50, 50},
};

/* Lat/lon of every grid point by PROJ: the centre projected forward, then plane points at
 * (i - ic) dx, (j - jc) dx from it projected back. Fractional positions allowed. */
static int proj_grid(const grid_case *g, const double *is, const double *js, int n, double *lat, double *lon)
{
  double X, Y;
  const double clon = g->center_lon, clat = g->center_lat;
  if (run_proj(g->proj, 0, &clon, &clat, 1, &X, &Y)) return 1;
  double *x = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));
  const double ic = 0.5 * (g->nx - 1), jc = 0.5 * (g->ny - 1);
  for (int k = 0; k < n; ++k) x[k] = X + (is[k] - ic) * g->dx, y[k] = Y + (js[k] - jc) * g->dx;
  const int rc = run_proj(g->proj, 1, x, y, n, lon, lat);
  free(x);
  free(y);
  return rc;
}

static void check_case(const grid_case *g)
{
  const int nx = g->nx, ny = g->ny, n = nx * ny;
  double *is = malloc((n + 5) * sizeof(double)), *js = malloc((n + 5) * sizeof(double));
  double *lat = malloc((n + 5) * sizeof(double)), *lon = malloc((n + 5) * sizeof(double));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) is[j * nx + i] = i, js[j * nx + i] = j;
  /* and the centre's half-cell neighbours, for spacing and grid north */
  const double ic = 0.5 * (nx - 1), jc = 0.5 * (ny - 1);
  const double extra[5][2] = {{ic, jc}, {ic - 0.5, jc}, {ic + 0.5, jc}, {ic, jc - 0.5}, {ic, jc + 0.5}};
  for (int k = 0; k < 5; ++k) is[n + k] = extra[k][0], js[n + k] = extra[k][1];
  if (!CHECK_MSG(proj_grid(g, is, js, n + 5, lat, lon) == 0, g->name)) goto out;

  sl_georef geo;
  sl_error err = {0};
  if (!CHECK_MSG(sl_georef_build(&geo, g->map_proj, g->truelat1, g->truelat2, g->stand_lon, g->pole_lat, g->pole_lon,
                                 nx, ny, g->dx, g->dx, lat, lon, g->name, &err) == SL_OK,
                 err.message))
    goto out;
  /* Our grid (its offset fitted to PROJ's XLAT/XLONG) against PROJ at every point. */
  double worst = 0.0;
  for (int c = 0; c < n; ++c) {
    double la, lo;
    sl_georef_grid_latlon(&geo, is[c], js[c], &la, &lo);
    worst = fmax(worst, fmax(fabs(la - lat[c]), fabs(wrap180(lo - lon[c]))));
  }
  char what[256];
  snprintf(what, sizeof what, "%s: grid lat/lon within 1e-7 deg of PROJ (worst %.2g deg)", g->name, worst);
  CHECK_MSG(worst < 1e-7, what);
  CHECK_MSG(geo.max_error_deg < 1e-7 && !geo.from_xlat, g->name);
  CHECK_CLOSE(geo.center_lat, lat[n], 0.0, 1e-7);
  CHECK_CLOSE(wrap180(geo.center_lon - lon[n]), 0.0, 0.0, 1e-7);
  /* Ground spacing and grid north at the centre from PROJ's points, by the test's own
   * spherical formulas. */
  CHECK_CLOSE(geo.ground_dx, haversine(lat[n + 1], lon[n + 1], lat[n + 2], lon[n + 2]), 1e-7, 0.0);
  CHECK_CLOSE(geo.ground_dy, haversine(lat[n + 3], lon[n + 3], lat[n + 4], lon[n + 4]), 1e-7, 0.0);
  CHECK_CLOSE(wrap180(geo.grid_north_deg - bearing(lat[n + 3], lon[n + 3], lat[n + 4], lon[n + 4])), 0.0, 0.0, 1e-6);
  for (int k = 0; k < 4; ++k) {
    const int c = k == 0 ? 0 : k == 1 ? nx - 1 : k == 2 ? n - 1 : n - nx;
    CHECK_CLOSE(geo.corner_lat[k], lat[c], 0.0, 1e-7);
    CHECK_CLOSE(wrap180(geo.corner_lon[k] - lon[c]), 0.0, 0.0, 1e-7);
  }

  /* Wrong attributes (STAND_LON off by 3 degrees, or DX off by 2 %) miss XLAT/XLONG by more
   * than a tenth of a cell: the placement then comes from XLAT/XLONG, with a note. */
  sl_georef bad;
  const double off_lon = g->map_proj == 6 && !(g->pole_lat == 90 && g->pole_lon == 0) ? 3.0 : 0.0;
  const double dx_bad = off_lon > 0.0 ? g->dx : 1.02 * g->dx;
  if (CHECK(sl_georef_build(&bad, g->map_proj, g->truelat1, g->truelat2, g->stand_lon + off_lon, g->pole_lat + off_lon,
                            g->pole_lon, nx, ny, dx_bad, dx_bad, lat, lon, g->name, &err) == SL_OK)) {
    snprintf(what, sizeof what, "%s: wrong attributes are noticed (%.3g m) and XLAT/XLONG trusted", g->name,
             bad.max_error_m);
    CHECK_MSG(bad.from_xlat && bad.note[0] && bad.max_error_m > 0.1 * g->dx, what);
    /* XLAT/XLONG interpolated bilinearly to the centre: within a hundredth of a cell. */
    snprintf(what, sizeof what, "%s: centre from XLAT/XLONG within 0.01 cell of PROJ's (%.3g m)", g->name,
             haversine(bad.center_lat, bad.center_lon, lat[n], lon[n]));
    CHECK_MSG(haversine(bad.center_lat, bad.center_lon, lat[n], lon[n]) < 0.01 * g->dx, what);
    CHECK_CLOSE(bad.ground_dx, geo.ground_dx, 1e-4, 0.0);
    CHECK_CLOSE(wrap180(bad.grid_north_deg - geo.grid_north_deg), 0.0, 0.0, 1e-3);
  }
out:
  free(is);
  free(js);
  free(lat);
  free(lon);
}

static double *read_2d(const char *path, const char *name, int t, int *nx, int *ny)
{
  int id, v, nd, dims[4];
  if (nc_open(path, NC_NOWRITE, &id) != NC_NOERR) return NULL;
  double *out = NULL;
  if (nc_inq_varid(id, name, &v) == NC_NOERR && nc_inq_varndims(id, v, &nd) == NC_NOERR && nd >= 2) {
    nc_inq_vardimid(id, v, dims);
    size_t a, b;
    nc_inq_dimlen(id, dims[nd - 2], &a);
    nc_inq_dimlen(id, dims[nd - 1], &b);
    *ny = (int)a, *nx = (int)b;
    size_t start[3] = {(size_t)t, 0, 0}, count[3] = {1, a, b};
    out = malloc(a * b * sizeof(double));
    if (nc_get_vara_double(id, v, nd == 3 ? start : start + 1, nd == 3 ? count : count + 1, out) != NC_NOERR) {
      free(out);
      out = NULL;
    }
  }
  nc_close(id);
  return out;
}

/* East and north (m) of (lat, lon) in the tangent frame at (lat0, lon0) on the sphere. */
static void enu_sphere(double lat0, double lon0, double lat, double lon, double *e, double *n)
{
  const double p0 = lat0 * DEG, p = lat * DEG, dl = (lon - lon0) * DEG;
  *e = R_WRF * cos(p) * sin(dl);
  *n = R_WRF * (cos(p0) * sin(p) - sin(p0) * cos(p) * cos(dl));
}

/* The grid centre by the file's XLAT/XLONG: the mean of the middle one, two or four points. */
static void xlat_center(const double *la, const double *lo, int nx, int ny, double *lat, double *lon)
{
  const int i0 = (nx - 1) / 2, i1 = nx / 2, j0 = (ny - 1) / 2, j1 = ny / 2;
  *lat = 0.25 * (la[j0 * nx + i0] + la[j0 * nx + i1] + la[j1 * nx + i0] + la[j1 * nx + i1]);
  *lon = 0.25 * (lo[j0 * nx + i0] + lo[j0 * nx + i1] + lo[j1 * nx + i0] + lo[j1 * nx + i1]);
}

static void check_real_file(const char *path, int ntimes, int moving)
{
  double origin_lat = NAN, origin_lon = NAN, first_e = 0.0, first_n = 0.0, moved = 0.0;
  for (int t = 0; t < ntimes; ++t) {
    int nx, ny;
    double *la = read_2d(path, "XLAT", t, &nx, &ny), *lo = read_2d(path, "XLONG", t, &nx, &ny);
    double *mf = read_2d(path, "MAPFAC_M", t, &nx, &ny);
    if (!CHECK_MSG(la && lo && mf, path)) return;
    double clat, clon;
    xlat_center(la, lo, nx, ny, &clat, &clon);
    if (t == 0) origin_lat = clat, origin_lon = clon;
    sl_load_options opt = {.time_index = t, .has_origin = 1, .origin_lat = origin_lat, .origin_lon = origin_lon};
    sl_storm_frame f;
    sl_error err = {0};
    if (!CHECK_MSG(sl_storm_load(path, &opt, &f, &err) == SL_OK, err.message)) return;
    /* Every grid point by the projection against the file's XLAT/XLONG: within 0.001 deg. */
    double worst = 0.0;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        double a, b;
        sl_georef_grid_latlon(&f.georef, i, j, &a, &b);
        worst = fmax(worst, fmax(fabs(a - la[j * nx + i]), fabs(wrap180(b - lo[j * nx + i]))));
      }
    char what[512];
    snprintf(what, sizeof what, "%s t=%d: projection within 0.001 deg of XLAT/XLONG (worst %.2g deg)", path, t, worst);
    CHECK_MSG(worst < 1e-3 && !f.georef.from_xlat, what);
    /* The volume's centre at the ENU position of this time's XLAT/XLONG centre. */
    const sl_volume *v = &f.volume;
    const double ce = v->origin[0] + 0.5 * (v->nx - 1) * v->spacing[0];
    const double cn = v->origin[1] + 0.5 * (v->ny - 1) * v->spacing[1];
    double e, n;
    enu_sphere(origin_lat, origin_lon, clat, clon, &e, &n);
    snprintf(what, sizeof what, "%s t=%d: volume centre (%.0f, %.0f) m within half a cell of XLAT/XLONG's (%.0f, %.0f)",
             path, t, ce, cn, e, n);
    CHECK_MSG(fabs(ce - e) < 0.5 * v->spacing[0] && fabs(cn - n) < 0.5 * v->spacing[1], what);
    if (t == 0) first_e = e, first_n = n;
    moved = fmax(moved, hypot(e - first_e, n - first_n));
    /* Spacing: DX over the file's own map factor at the centre (MAPFAC_M), within 0.1 %. */
    const double m = 0.25 * (mf[((ny - 1) / 2) * nx + (nx - 1) / 2] + mf[((ny - 1) / 2) * nx + nx / 2] +
                             mf[(ny / 2) * nx + (nx - 1) / 2] + mf[(ny / 2) * nx + nx / 2]);
    CHECK_CLOSE(v->spacing[0], f.georef.dx / m, 1e-3, 0.0);
    CHECK_CLOSE(v->spacing[1], f.georef.dy / m, 1e-3, 0.0);
    sl_storm_frame_free(&f);
    free(la);
    free(lo);
    free(mf);
  }
  /* A moving nest moves across the fixed frame (more than two cells over its times). */
  if (moving) CHECK_MSG(moved > 20000.0, "the Katrina nest moves across the frame");
}

static void check_curvature(void)
{
  /* Horizontal distance R sin(theta) on the tangent plane lies R (1 - cos theta) above the sphere. */
  const double s_km[] = {1.0, 100.0, 500.0, 707.0, 1000.0, 3000.0};
  for (size_t k = 0; k < sizeof s_km / sizeof s_km[0]; ++k) {
    const double theta = s_km[k] * 1000.0 / R_WRF, r = R_WRF * sin(theta);
    const double exact = 2.0 * R_WRF * sin(0.5 * theta) * sin(0.5 * theta); /* R (1 - cos theta) */
    CHECK_CLOSE(sl_curvature_drop(r), exact, 1e-12, 0.0);
    /* The sagitta r^2 / 2R is the first term of R (1 - sqrt(1 - u)), u = r^2 / R^2; the rest lies
     * between R u^2 / 8 and R u^2 / 8 / (1 - u). */
    const double u = r * r / (R_WRF * R_WRF), rest = sl_curvature_drop(r) - r * r / (2.0 * R_WRF);
    CHECK(rest >= R_WRF * u * u / 8.0 * (1.0 - 1e-9) - 1e-9 && rest <= R_WRF * u * u / 8.0 / (1.0 - u) * (1.0 + 1e-9) + 1e-9);
  }
  /* A 1000 km domain's edge (500 km from the centre) lies 19.6 km below the tangent plane. */
  CHECK_CLOSE(sl_curvature_drop(500e3), 19654.0, 0.0, 1.0);
}

/* An unsupported MAP_PROJ is an error naming the file; a supported one without its parameters
 * is placed by XLAT/XLONG with a note. */
static void check_attributes(void)
{
  const double la[4] = {35, 35, 35.01, 35.01}, lo[4] = {-97, -96.99, -97, -96.99};
  sl_georef g;
  sl_error err = {0};
  CHECK(sl_georef_build(&g, 4, 30, 60, -97, 90, 0, 2, 2, 1000, 1000, la, lo, "gauss.nc", &err) == SL_ERR_FORMAT);
  CHECK(strstr(err.message, "gauss.nc") && strstr(err.message, "MAP_PROJ 4"));
  CHECK(sl_georef_build(&g, 1, NAN, NAN, NAN, 90, 0, 2, 2, 1000, 1000, la, lo, "bare.nc", &err) == SL_OK);
  CHECK(g.from_xlat && strstr(g.note, "bare.nc") && isnan(g.max_error_deg));
  CHECK_CLOSE(g.center_lat, 35.005, 0.0, 1e-9);
  CHECK_CLOSE(g.center_lon, -96.995, 0.0, 1e-9);
  CHECK_CLOSE(g.ground_dx, haversine(35.005, -97, 35.005, -96.99), 1e-6, 0.0);
}

int main(void)
{
  check_attributes();
  for (size_t c = 0; c < sizeof CASES / sizeof CASES[0]; ++c) check_case(&CASES[c]);
  const char *shared = getenv("SL_SHARED_DIR");
  char katrina[4096], tibet[4096];
  snprintf(katrina, sizeof katrina, "%s/data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc", shared ? shared : "../shared");
  snprintf(tibet, sizeof tibet, "%s/data/wrf/wrf_tibet2005_d01_lambert_thompson_4t_tiny.nc", shared ? shared : "../shared");
  check_real_file(katrina, 4, 1);
  check_real_file(tibet, 4, 0);
  check_curvature();
  return sl_test_finish("projection");
}
