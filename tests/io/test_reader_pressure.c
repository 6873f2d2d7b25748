/* CF storms on pressure levels (ERA5's, CMIP's, post-processed WRF's), whose heights come from a
 * geopotential on the same grid. The air here is a polytropic atmosphere (constant lapse rate),
 * for which the geopotential height of a pressure and the hydrostatic mass between two heights
 * have closed forms; the reader instead takes density from the ideal gas law at each level and
 * thickness from the geopotential. So the loaded column's water path, sum of rho q dz, must equal
 * the hydrostatic mass, sum of q dp / g0, of the layers the levels stand for.
 * Files are written here through netCDF-C: one laid out as ERA5 writes it (levels in millibars
 * from the top down, latitudes north to south, geopotential in m2 s-2, ECMWF's short name clwc
 * without a standard name), one as CMIP writes it (plev in Pa, bottom up, zg in m, standard names). */
#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sl_storm.h"
#include "sl_testing.h"
#include "column_path.h"

enum { NX = 3, NY = 2, NP = 19 };
#define G0 9.80665
#define RD 287.05  /* J/(kg K), textbook (the reader uses WRF's 287) */
#define LAPSE 0.0065
#define P0 101325.0

static char dir[] = "/tmp/sl_test_pressure_XXXXXX";

/* The polytrope of column (i, j): surface temperature 300 K + 2 i - 3 j at P0. */
static double t_surface(int i, int j) { return 300.0 + 2.0 * i - 3.0 * j; }
static double kappa(void) { return RD * LAPSE / G0; }
static double temperature_at(int i, int j, double p) { return t_surface(i, j) * pow(p / P0, kappa()); }
/* Geopotential height of pressure p: dZ = -R T dp / (g0 p) integrated with T = T0 (p/P0)^kappa. */
static double height_at(int i, int j, double p) { return t_surface(i, j) / LAPSE * (1.0 - pow(p / P0, kappa())); }
static double pressure_at(int i, int j, double z) { return P0 * pow(1.0 - LAPSE * z / t_surface(i, j), 1.0 / kappa()); }

/* Levels 1000, 950, ..., 100 hPa, from the bottom. */
static double level_hpa(int k) { return 1000.0 - 50.0 * k; }

/* Cloud specific content at level k of column (i, j): a cloud from 900 to 400 hPa (900 hPa is
 * the first level above the ground of the column masked below it), its amount differing per
 * column so that a column read in the wrong place shows. */
static double cloud_at(int i, int j, int k)
{
  const double p = level_hpa(k);
  return p <= 900.0 && p >= 400.0 ? 1e-4 * (1.0 + i + 2.0 * j) * (1.0 + 0.1 * k) : 0.0;
}

typedef struct layout {
  int top_down, north_south, height_var, hpa, ecmwf_name, missing_geo, bad_column, one_level;
  int below;       /* 1: column (2, 1) masked at 1000 and 950 hPa (below its ground), as CMIP writes;
                      2: every column masked at 1000 hPa */
  int hole;        /* 1: the cloud, 2: the geopotential missing at 500 hPa in column (0, 0) */
} layout;

#define FILL 1e20f

static void put(int nc, const char *name, int ndims, const int *dims, const char *std, const char *units, int *id)
{
  nc_def_var(nc, name, NC_FLOAT, ndims, dims, id);
  if (std) nc_put_att_text(nc, *id, "standard_name", strlen(std), std);
  if (units) nc_put_att_text(nc, *id, "units", strlen(units), units);
}

/* Writes the storm as `lay` says; returns the path. */
static const char *write_storm(const char *name, layout lay)
{
  static char path[8][512];
  static int which;
  char *out = path[which++ % 8];
  snprintf(out, 512, "%s/%s.nc", dir, name);
  const int np = lay.one_level ? 1 : NP;
  int nc, d[4], v_t, v_p, v_y, v_x, v_cloud, v_geo, v_ta, v_q;
  nc_create(out, NC_NETCDF4, &nc);
  nc_def_dim(nc, "time", 1, &d[0]);
  nc_def_dim(nc, lay.ecmwf_name ? "level" : "plev", (size_t)np, &d[1]);
  nc_def_dim(nc, "lat", NY, &d[2]);
  nc_def_dim(nc, "lon", NX, &d[3]);
  put(nc, "time", 1, d, NULL, "hours since 2005-08-29 00:00:00", &v_t);
  put(nc, lay.ecmwf_name ? "level" : "plev", 1, d + 1, "air_pressure", lay.hpa ? "millibars" : "Pa", &v_p);
  nc_put_att_text(nc, v_p, "positive", 4, "down");
  put(nc, "lat", 1, d + 2, "latitude", "degrees_north", &v_y);
  put(nc, "lon", 1, d + 3, "longitude", "degrees_east", &v_x);
  put(nc, lay.ecmwf_name ? "clwc" : "clw", 4, d, lay.ecmwf_name ? NULL : "mass_fraction_of_cloud_liquid_water_in_air",
      "kg kg**-1", &v_cloud);
  if (!lay.missing_geo)
    put(nc, lay.height_var ? "zg" : "z", 4, d, lay.height_var ? "geopotential_height" : "geopotential",
        lay.height_var ? "m" : "m**2 s**-2", &v_geo);
  put(nc, "t", 4, d, "air_temperature", "K", &v_ta);
  put(nc, "q", 4, d, "specific_humidity", "kg kg**-1", &v_q);
  if (lay.below || lay.hole) {
    const float fill = FILL;
    nc_put_att_float(nc, v_cloud, "_FillValue", NC_FLOAT, 1, &fill);
    nc_put_att_float(nc, v_ta, "_FillValue", NC_FLOAT, 1, &fill);
    nc_put_att_float(nc, v_q, "_FillValue", NC_FLOAT, 1, &fill);
    if (!lay.missing_geo) nc_put_att_float(nc, v_geo, "_FillValue", NC_FLOAT, 1, &fill);
  }
  nc_enddef(nc);
  const float t0 = 12.0f;
  nc_put_var_float(nc, v_t, &t0);
  float p[NP], lat[NY], lon[NX];
  for (int k = 0; k < np; ++k) {
    const int kf = lay.top_down ? np - 1 - k : k; /* file level k holds model level kf */
    p[k] = (float)(lay.hpa ? level_hpa(kf) : 100.0 * level_hpa(kf));
  }
  for (int j = 0; j < NY; ++j) lat[j] = (float)(lay.north_south ? 25.5 - 0.25 * j : 25.25 + 0.25 * j);
  for (int i = 0; i < NX; ++i) lon[i] = (float)(-89.0 + 0.25 * i);
  nc_put_var_float(nc, v_p, p);
  nc_put_var_float(nc, v_y, lat);
  nc_put_var_float(nc, v_x, lon);
  static float cloud[NP][NY][NX], geo[NP][NY][NX], ta[NP][NY][NX], q[NP][NY][NX];
  for (int k = 0; k < np; ++k)
    for (int jf = 0; jf < NY; ++jf)
      for (int i = 0; i < NX; ++i) {
        const int kf = lay.top_down ? np - 1 - k : k;
        const int j = lay.north_south ? NY - 1 - jf : jf; /* column j counts from the south */
        const double pa = 100.0 * level_hpa(kf), z = height_at(i, j, pa);
        cloud[k][jf][i] = (float)cloud_at(i, j, kf);
        geo[k][jf][i] = (float)(lay.height_var ? z : G0 * z);
        ta[k][jf][i] = (float)temperature_at(i, j, pa);
        q[k][jf][i] = 0.0f;
        if ((lay.below == 1 && i == 2 && j == 1 && kf < 2) || (lay.below == 2 && kf == 0))
          cloud[k][jf][i] = geo[k][jf][i] = ta[k][jf][i] = q[k][jf][i] = FILL;
        if (lay.hole && i == 0 && j == 0 && level_hpa(kf) == 500.0) *(lay.hole == 1 ? &cloud[k][jf][i] : &geo[k][jf][i]) = FILL;
      }
  if (lay.bad_column) { /* column (1, 0): the 700 hPa level below the 750 hPa one */
    const int k = lay.top_down ? np - 1 - 6 : 6, jf = lay.north_south ? NY - 1 : 0;
    geo[k][jf][1] = geo[lay.top_down ? k + 1 : k - 1][jf][1] - 10.0f;
  }
  nc_put_var_float(nc, v_cloud, &cloud[0][0][0]);
  if (!lay.missing_geo) nc_put_var_float(nc, v_geo, &geo[0][0][0]);
  nc_put_var_float(nc, v_ta, &ta[0][0][0]);
  nc_put_var_float(nc, v_q, &q[0][0][0]);
  nc_close(nc);
  return out;
}

static int load(const char *path, const sl_load_options *opt, sl_storm_frame *f, sl_error *err)
{
  sl_load_options zero = {0};
  return sl_storm_load(path, opt ? opt : &zero, f, err);
}

/* The hydrostatic cloud mass (kg m-2) of column (i, j) over levels k0 .. k0 + nk - 1: each level's
 * content over the layer between the heights halfway to its neighbours (half a layer beyond the
 * outermost levels), through the polytrope's pressures there. */
static double hydrostatic_path(int i, int j, int k0, int nk)
{
  double m = 0.0;
  for (int k = k0; k < k0 + nk; ++k) {
    const double z = height_at(i, j, 100.0 * level_hpa(k));
    const double below = k > 0 ? height_at(i, j, 100.0 * level_hpa(k - 1)) : 2.0 * z - height_at(i, j, 100.0 * level_hpa(1));
    const double above = k < NP - 1 ? height_at(i, j, 100.0 * level_hpa(k + 1))
                                    : 2.0 * z - height_at(i, j, 100.0 * level_hpa(NP - 2));
    m += cloud_at(i, j, k) * (pressure_at(i, j, 0.5 * (below + z)) - pressure_at(i, j, 0.5 * (z + above))) / G0;
  }
  return m;
}

static void test_hydrostatic_mass(void)
{
  const layout era5 = {.top_down = 1, .north_south = 1, .hpa = 1, .ecmwf_name = 1};
  const layout cmip = {.height_var = 1};
  const char *paths[2] = {write_storm("era5", era5), write_storm("cmip", cmip)};
  sl_storm_frame f[2];
  int ok[2];
  for (int v = 0; v < 2; ++v) {
    sl_error err = {0};
    sl_storm_info info;
    ok[v] = CHECK(sl_storm_read_info(paths[v], &info, &err) == SL_OK);
    if (!ok[v]) {
      fprintf(stderr, "%s\n", err.message);
      continue;
    }
    CHECK(info.kind == SL_STORM_CF && info.nz == NP && info.nspecies == 1 && info.map_proj == 6);
    /* `info` says where the heights come from. */
    CHECK(strstr(info.vertical, "1000 to 100 hPa") &&
          strstr(info.vertical, v ? "geopotential_height 'zg'" : "geopotential 'z'"));
    ok[v] = CHECK(load(paths[v], NULL, &f[v], &err) == SL_OK);
    if (!ok[v]) {
      fprintf(stderr, "%s\n", err.message);
      continue;
    }
    double worst = 0.0;
    for (int j = 0; j < NY; ++j)
      for (int i = 0; i < NX; ++i) {
        const double want = hydrostatic_path(i, j, 0, NP), got = sl_test_column_path(&f[v], i, j);
        worst = fmax(worst, fabs(got / want - 1.0));
        /* R_d 287 against 287.05 and the layers' curvature of density: a few 1e-4. A level read
         * one step off, hPa read as Pa or geopotential as a height are whole factors. */
        CHECK_CLOSE(got, want, 2e-3, 0.0);
      }
    printf("%s: water path against the hydrostatic mass, worst column %.2e relative\n", v ? "CMIP layout" : "ERA5 layout",
           worst);
    /* The grid: from the lowest interface (half a layer under 1000 hPa) to the highest (half a
     * layer above 100 hPa) over all columns. */
    double ground = INFINITY, top = -INFINITY;
    for (int j = 0; j < NY; ++j)
      for (int i = 0; i < NX; ++i) {
        ground = fmin(ground, 1.5 * height_at(i, j, 1e5) - 0.5 * height_at(i, j, 95000.0));
        top = fmax(top, 1.5 * height_at(i, j, 1e4) - 0.5 * height_at(i, j, 15000.0));
      }
    CHECK_CLOSE(f[v].terrain_min, ground, 0.0, 0.05);
    CHECK_CLOSE(f[v].model_top, top, 0.0, 0.05);
    CHECK(f[v].volume.nz >= 2 * NP);
  }
  if (ok[0] && ok[1]) {
    /* The two layouts are the same air: ERA5's geopotential (m2 s-2) and CMIP's height (m) differ
     * only in their float rounding. */
    double worst = 0.0;
    for (int j = 0; j < NY; ++j)
      for (int i = 0; i < NX; ++i) worst = fmax(worst, fabs(sl_test_column_path(&f[0], i, j) / sl_test_column_path(&f[1], i, j) - 1.0));
    CHECK(worst < 1e-5);
    CHECK(f[0].volume.nz == f[1].volume.nz);
  }
  for (int v = 0; v < 2; ++v)
    if (ok[v]) sl_storm_frame_free(&f[v]);
}

/* Levels listed from the top down, in hPa, load bit for bit as from the bottom up in Pa. */
static void test_orders_and_units(void)
{
  const layout up = {0}, down = {.top_down = 1, .hpa = 1};
  sl_storm_frame a, b;
  sl_error err = {0};
  if (!CHECK(load(write_storm("up", up), NULL, &a, &err) == SL_OK)) {
    fprintf(stderr, "%s\n", err.message);
    return;
  }
  if (CHECK(load(write_storm("down", down), NULL, &b, &err) == SL_OK)) {
    const size_t n = (size_t)a.volume.nx * a.volume.ny * a.volume.nz;
    CHECK(b.volume.nz == a.volume.nz && memcmp(a.volume.eta[SL_CLOUD], b.volume.eta[SL_CLOUD], n * sizeof(float)) == 0);
    sl_storm_frame_free(&b);
  } else {
    fprintf(stderr, "%s\n", err.message);
  }
  /* --stride 2 on the ERA5 layout (reversed levels and latitudes): every second column and row of
   * the file from its first, so columns (0, 1) and (2, 1) of the north row (the file's first),
   * each with its own water path. */
  sl_load_options strided = {0};
  strided.stride = 2;
  if (CHECK(load(write_storm("strided", (layout){.top_down = 1, .north_south = 1, .hpa = 1, .ecmwf_name = 1}),
                 &strided, &b, &err) == SL_OK)) {
    CHECK(b.volume.nx == 2 && b.volume.ny == 1);
    for (int i = 0; i < 2; ++i) CHECK_CLOSE(sl_test_column_path(&b, i, 0), hydrostatic_path(2 * i, 1, 0, NP), 2e-3, 0.0);
    sl_storm_frame_free(&b);
  } else {
    fprintf(stderr, "%s\n", err.message);
  }
  /* --levels counts from the bottom: levels 3..10 (850 to 500 hPa) hold the cloud's mass there. */
  sl_load_options opt = {0};
  opt.level_first = 3, opt.level_count = 8;
  if (CHECK(load(write_storm("down2", down), &opt, &b, &err) == SL_OK)) {
    for (int j = 0; j < NY; ++j)
      for (int i = 0; i < NX; ++i) CHECK_CLOSE(sl_test_column_path(&b, i, j), hydrostatic_path(i, j, 3, 8), 2e-3, 0.0);
    sl_storm_frame_free(&b);
  } else {
    fprintf(stderr, "%s\n", err.message);
  }
  sl_storm_frame_free(&a);
}

/* A column whose lowest levels lie below its ground, masked with _FillValue (CMIP, xarray's NaN):
 * no air and no cloud there, the rest of the column as before. */
static void test_below_ground(void)
{
  const layout lay = {.below = 1, .top_down = 1, .hpa = 1, .north_south = 1};
  sl_storm_frame f;
  sl_error err = {0};
  if (!CHECK(load(write_storm("below", lay), NULL, &f, &err) == SL_OK)) {
    fprintf(stderr, "%s\n", err.message);
    return;
  }
  for (int j = 0; j < NY; ++j)
    for (int i = 0; i < NX; ++i) CHECK_CLOSE(sl_test_column_path(&f, i, j), hydrostatic_path(i, j, 0, NP), 2e-3, 0.0);
  /* The grid starts at the lowest interface above a ground: the other columns' (the masked one's
   * lowest level above its ground is 900 hPa). */
  double ground = INFINITY;
  for (int j = 0; j < NY; ++j)
    for (int i = 0; i < NX; ++i)
      if (!(i == 2 && j == 1)) ground = fmin(ground, 1.5 * height_at(i, j, 1e5) - 0.5 * height_at(i, j, 95000.0));
  CHECK_CLOSE(f.terrain_min, ground, 0.0, 0.05);
  sl_storm_frame_free(&f);
  /* Every column masked at 1000 hPa: the grid starts halfway between 950 hPa and the 1000 hPa
   * height extrapolated at 288 K (the documented rule, R_d 287), not half a layer under that. */
  if (!CHECK(load(write_storm("below_all", (layout){.below = 2}), NULL, &f, &err) == SL_OK)) {
    fprintf(stderr, "%s\n", err.message);
    return;
  }
  ground = INFINITY;
  for (int j = 0; j < NY; ++j)
    for (int i = 0; i < NX; ++i) {
      const double z950 = (double)(float)(G0 * height_at(i, j, 95000.0)) / G0;
      const double z1000 = (double)(float)(z950 - 287.0 * 288.0 / G0 * log(1000.0 / 950.0));
      ground = fmin(ground, 0.5 * (z1000 + z950));
      CHECK_CLOSE(sl_test_column_path(&f, i, j), hydrostatic_path(i, j, 0, NP), 2e-3, 0.0);
    }
  CHECK_CLOSE(f.terrain_min, ground, 0.0, 0.05);
  sl_storm_frame_free(&f);
}

/* The remap in blocks of levels (io/remap.c) on the layouts that move a block's levels in the
 * file: levels from the top down (a block of the subset reads the file's levels counted from its
 * end), a column masked below its ground (per column, which of the block's levels hold air), the
 * pressure taken from the coordinate, and a --levels subset. One species: each output cell sums
 * its deposits in the same order whatever the blocks, so the frames agree bit for bit. */
static void test_blocks(void)
{
  const char *path = write_storm("blocks", (layout){.below = 1, .top_down = 1, .hpa = 1, .north_south = 1});
  const int subsets[2][2] = {{0, 0}, {1, 13}};
  for (int s = 0; s < 2; ++s) {
    sl_load_options one = {.level_first = subsets[s][0], .level_count = subsets[s][1], .block_levels = 1000};
    sl_storm_frame whole;
    sl_error err = {0};
    if (!CHECK(load(path, &one, &whole, &err) == SL_OK)) {
      fprintf(stderr, "%s\n", err.message);
      continue;
    }
    const size_t n = (size_t)whole.volume.nx * whole.volume.ny * whole.volume.nz;
    for (int b = 1; b <= 4; ++b) {
      sl_load_options o = one;
      o.block_levels = b;
      sl_storm_frame f;
      if (!CHECK(load(path, &o, &f, &err) == SL_OK)) continue;
      int same = f.volume.nz == whole.volume.nz && f.terrain_min == whole.terrain_min;
      for (int p = 0; same && p < SL_VOLUME_SLOTS; ++p)
        same = !f.volume.eta[p] == !whole.volume.eta[p] &&
               (!f.volume.eta[p] || memcmp(f.volume.eta[p], whole.volume.eta[p], n * sizeof(float)) == 0);
      same = same && f.stats[SL_CLOUD].q_mean == whole.stats[SL_CLOUD].q_mean &&
             f.stats[SL_CLOUD].q_max == whole.stats[SL_CLOUD].q_max;
      CHECK_MSG(same, subsets[s][1] ? "levels 1:13 in blocks" : "all levels in blocks");
      sl_storm_frame_free(&f);
    }
    if (s == 0)
      for (int j = 0; j < NY; ++j)
        for (int i = 0; i < NX; ++i)
          CHECK_CLOSE(sl_test_column_path(&whole, i, j), hydrostatic_path(i, j, 0, NP), 2e-3, 0.0);
    sl_storm_frame_free(&whole);
  }
  /* A missing value above the ground is found in whichever block holds it. */
  const char *hole = write_storm("blocks_hole", (layout){.hole = 1, .below = 1, .top_down = 1});
  for (int b = 1; b <= 3; ++b) {
    sl_load_options o = {.block_levels = b};
    sl_storm_frame f;
    sl_error err = {0};
    const int rc = load(hole, &o, &f, &err);
    if (rc == SL_OK) sl_storm_frame_free(&f);
    CHECK_MSG(rc != SL_OK && strstr(err.message, "'clw' has NaN, Inf or missing values"), "a hole in blocks");
  }
}

/* Terrain-following model levels: the Met Office UM's hybrid height (z = a + b orog, CF appendix
 * D, formula_terms) and, the same levels, as model level numbers with a 3-D altitude. Air from
 * pressure and potential temperature on the levels, as the UM writes it. The same oracle: the
 * hydrostatic mass of each level's layer, now between heights halfway to its neighbours. */
enum { NL = 20 };
static double hybrid_a(int k) { return 200.0 + 600.0 * k; }
static double hybrid_b(int k) { return (1.0 - hybrid_a(k) / 12000.0) * (1.0 - hybrid_a(k) / 12000.0); }
static double orography(int i, int j) { return 300.0 * i + 200.0 * j; }
static double model_height(int i, int j, int k)
{
  if (k < 0) return 2.0 * model_height(i, j, 0) - model_height(i, j, 1);
  if (k >= NL) return 2.0 * model_height(i, j, NL - 1) - model_height(i, j, NL - 2);
  return hybrid_a(k) + hybrid_b(k) * orography(i, j);
}
static double model_cloud(int i, int j, int k) { return k >= 3 && k <= 9 ? 2e-4 * (1.0 + i + 2.0 * j) : 0.0; }

/* hybrid: UM hybrid height (else level numbers with an altitude); north_south: latitudes from the
 * north; km: the hybrid coordinate and its a term in km; top_down: levels listed from the top,
 * numbered from 1 there (as ECMWF numbers them), positive = "down". */
static const char *write_model_levels(const char *name, int hybrid, int north_south, int km, int top_down)
{
  static char out[4][512];
  static int which;
  char *path = out[which++ % 4];
  snprintf(path, 512, "%s/%s.nc", dir, name);
  int nc, d[4], v_lev, v_b, v_orog, v_alt = -1, v_y, v_x, v_cl, v_p, v_th;
  nc_create(path, NC_NETCDF4, &nc);
  nc_def_dim(nc, "time", 1, &d[0]);
  nc_def_dim(nc, "model_level_number", NL, &d[1]);
  nc_def_dim(nc, "latitude", NY, &d[2]);
  nc_def_dim(nc, "longitude", NX, &d[3]);
  if (hybrid) {
    put(nc, "model_level_number", 1, d + 1, "atmosphere_hybrid_height_coordinate", km ? "km" : "m", &v_lev);
    const char *terms = "a: level_height\tb: sigma orog: surface_altitude";
    nc_put_att_text(nc, v_lev, "formula_terms", strlen(terms), terms);
    int v_a;
    put(nc, "level_height", 1, d + 1, NULL, km ? "km" : "m", &v_a);
    put(nc, "sigma", 1, d + 1, NULL, "1", &v_b);
    put(nc, "surface_altitude", 2, d + 2, "surface_altitude", "m", &v_orog);
  } else {
    put(nc, "model_level_number", 1, d + 1, "model_level_number", "1", &v_lev);
    put(nc, "altitude", 4, d, "altitude", "m", &v_alt);
  }
  if (top_down) nc_put_att_text(nc, v_lev, "positive", 4, "down");
  put(nc, "latitude", 1, d + 2, "latitude", "degrees_north", &v_y);
  put(nc, "longitude", 1, d + 3, "longitude", "degrees_east", &v_x);
  put(nc, "cl", 4, d, "mass_fraction_of_cloud_liquid_water_in_air", "kg kg-1", &v_cl);
  put(nc, "p", 4, d, "air_pressure", "Pa", &v_p);
  put(nc, "theta", 4, d, "air_potential_temperature", "K", &v_th);
  nc_enddef(nc);
  float lev[NL], lat[NY], lon[NX];
  static float a[NL], b[NL], orog[NY][NX], alt[NL][NY][NX], cl[NL][NY][NX], p[NL][NY][NX], th[NL][NY][NX];
  const double a_unit = km ? 1e-3 : 1.0;
  for (int k = 0; k < NL; ++k) {
    const int kf = top_down ? NL - 1 - k : k; /* file level k holds model level kf */
    lev[k] = (float)(hybrid ? hybrid_a(kf) * a_unit : k + 1), a[k] = (float)(hybrid_a(kf) * a_unit);
    b[k] = (float)hybrid_b(kf);
  }
  for (int j = 0; j < NY; ++j) lat[j] = (float)(north_south ? 50.02 - 0.02 * j : 50.0 + 0.02 * j);
  for (int i = 0; i < NX; ++i) lon[i] = (float)(-3.0 + 0.03 * i);
  for (int k = 0; k < NL; ++k)
    for (int jf = 0; jf < NY; ++jf)
      for (int i = 0; i < NX; ++i) {
        const int kf = top_down ? NL - 1 - k : k, j = north_south ? NY - 1 - jf : jf;
        orog[jf][i] = (float)orography(i, j);
        /* the heights as the reader forms them from the file's floats */
        const double z = (double)(float)(hybrid_a(kf) * a_unit) / a_unit + (double)(float)hybrid_b(kf) * orog[jf][i];
        const double pa = pressure_at(i, j, z), t = temperature_at(i, j, pa);
        alt[k][jf][i] = (float)z, cl[k][jf][i] = (float)model_cloud(i, j, kf), p[k][jf][i] = (float)pa;
        th[k][jf][i] = (float)(t * pow(1e5 / pa, 2.0 / 7.0));
      }
  nc_put_var_float(nc, v_lev, lev);
  if (hybrid) {
    int id;
    nc_inq_varid(nc, "level_height", &id);
    nc_put_var_float(nc, id, a);
    nc_put_var_float(nc, v_b, b);
    nc_put_var_float(nc, v_orog, &orog[0][0]);
  } else {
    nc_put_var_float(nc, v_alt, &alt[0][0][0]);
  }
  nc_put_var_float(nc, v_y, lat);
  nc_put_var_float(nc, v_x, lon);
  nc_put_var_float(nc, v_cl, &cl[0][0][0]);
  nc_put_var_float(nc, v_p, &p[0][0][0]);
  nc_put_var_float(nc, v_th, &th[0][0][0]);
  nc_close(nc);
  return path;
}

static void test_model_levels(void)
{
  /* Plain; then the hybrid's a in km over latitudes from the north, and the altitude's levels
   * numbered from the top with positive = "down" (sigma's and ECMWF's order). */
  const char *paths[4] = {write_model_levels("um_hybrid", 1, 0, 0, 0), write_model_levels("altitude", 0, 0, 0, 0),
                          write_model_levels("um_hybrid_km_ns", 1, 1, 1, 0),
                          write_model_levels("altitude_top_down", 0, 0, 0, 1)};
  const char *words[4] = {"hybrid height", "heights from altitude", "hybrid height", "heights from altitude"};
  sl_storm_frame f[4];
  int ok[4];
  for (int v = 0; v < 4; ++v) {
    sl_error err = {0};
    sl_storm_info info;
    ok[v] = CHECK(sl_storm_read_info(paths[v], &info, &err) == SL_OK) && CHECK(strstr(info.vertical, words[v]) != NULL) &&
            CHECK(load(paths[v], NULL, &f[v], &err) == SL_OK);
    if (!ok[v]) {
      fprintf(stderr, "%s | %s\n", err.message, info.vertical);
      continue;
    }
    double worst = 0.0;
    for (int j = 0; j < NY; ++j)
      for (int i = 0; i < NX; ++i) {
        double want = 0.0;
        for (int k = 0; k < NL; ++k)
          want += model_cloud(i, j, k) *
                  (pressure_at(i, j, 0.5 * (model_height(i, j, k - 1) + model_height(i, j, k))) -
                   pressure_at(i, j, 0.5 * (model_height(i, j, k) + model_height(i, j, k + 1)))) / G0;
        const double got = sl_test_column_path(&f[v], i, j);
        worst = fmax(worst, fabs(got / want - 1.0));
        CHECK_CLOSE(got, want, 2e-3, 0.0);
      }
    printf("%s: water path against the hydrostatic mass, worst column %.2e relative\n", words[v], worst);
    /* The grid starts half a layer under the lowest level of the lowest column (orography 0). */
    CHECK_CLOSE(f[v].terrain_min, 1.5 * hybrid_a(0) - 0.5 * hybrid_a(1), 0.0, 0.05);
  }
  for (int v = 1; v < 4; ++v)
    if (ok[0] && ok[v]) {
      for (int j = 0; j < NY; ++j)
        for (int i = 0; i < NX; ++i)
          CHECK_CLOSE(sl_test_column_path(&f[0], i, j), sl_test_column_path(&f[v], i, j), 1e-5, 0.0);
    }
  for (int v = 0; v < 4; ++v)
    if (ok[v]) sl_storm_frame_free(&f[v]);
}

static void expect_error(const char *name, layout lay, const char *fragment)
{
  const char *path = write_storm(name, lay);
  sl_storm_frame f;
  sl_error err = {0};
  const int rc = load(path, NULL, &f, &err);
  if (rc == SL_OK) sl_storm_frame_free(&f);
  CHECK_MSG(rc != SL_OK && strstr(err.message, path) && strstr(err.message, fragment), name);
  if (rc == SL_OK || !strstr(err.message, fragment)) fprintf(stderr, "%s: '%s'\n", name, err.message);
}

int main(void)
{
  if (!mkdtemp(dir)) return 1;
  test_hydrostatic_mass();
  test_orders_and_units();
  expect_error("no_geopotential", (layout){.missing_geo = 1}, "geopotential");
  expect_error("sinking_column", (layout){.bad_column = 1}, "does not rise");
  expect_error("sinking_column_era5", (layout){.bad_column = 1, .top_down = 1, .north_south = 1, .hpa = 1}, "does not rise");
  expect_error("one_level", (layout){.one_level = 1}, "one pressure level");
  test_below_ground();
  test_blocks();
  test_model_levels();
  /* Missing above the ground is an error naming the variable, as everywhere. */
  expect_error("cloud_hole", (layout){.hole = 1, .below = 1}, "'clw' has NaN, Inf or missing values");
  expect_error("geopotential_hole", (layout){.hole = 2, .top_down = 1}, "missing at 50000 Pa above the ground");
  char cmd[700];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (getenv("SL_KEEP_TEST_FILES")) printf("files kept in %s\n", dir);
  else if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
  return sl_test_finish("test_reader_pressure");
}
