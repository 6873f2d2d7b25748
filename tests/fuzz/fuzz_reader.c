/* libFuzzer target: the storm reader on storm-like NetCDF files built from the fuzzer's bytes.
 * The bytes choose dimensions (WRF, CM1 and CF names (height or pressure levels), lengths 0..5, an unlimited time with 0..3
 * records), variables (the names the readers look for, any numeric or text type, any shape over
 * those dimensions), attributes (packing, fill values, units, standard names, grid mappings,
 * DX/MAP_PROJ/MP_PHYSICS ... with any value, NaN and Inf included) and every data value. The file
 * is written in memory (nc_create_mem, 64-bit offset) and read back through nc_open_mem
 * (sl_storm_load_memory), so every input is a well-formed NetCDF file that means nonsense: the
 * reader must end each in SL_OK or one error, without a crash, a leak or a sanitizer report.
 *
 * Raw byte mutation of NetCDF headers is not fuzzed here: netCDF-C 4.9.0's own netCDF-3 header
 * parser aborts on such files (ncdump too; upstream Unidata/netcdf-c PRs #3376, #3377, #3421), and
 * HDF5 is neither instrumented nor hardened; those crashes are upstream's, not the reader's. */
#include <math.h>
#include <netcdf.h>
#include <netcdf_mem.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sl_storm.h"

typedef struct bytes {
  const uint8_t *p;
  size_t n;
} bytes;

static unsigned take(bytes *b, unsigned range)
{
  if (range <= 1) return 0;
  unsigned v = 0;
  for (int i = 0; i < 2 && b->n; ++i) v = v << 8 | *b->p++, b->n--;
  return v % range;
}

static double take_double(bytes *b)
{
  static const double special[] = {0.0, 1.0, -1.0, 1e-3, 1e3, 9.81, 300.0, 1e5, NAN, INFINITY, -INFINITY, 1e30,
                                   -1e-12, 273.15, 0.1, 65535.0};
  if (take(b, 2)) return special[take(b, sizeof special / sizeof special[0])];
  float f = 0.0f;
  uint8_t raw[4] = {0};
  for (int i = 0; i < 4 && b->n; ++i) raw[i] = *b->p++, b->n--;
  memcpy(&f, raw, sizeof f);
  return f;
}

static const char *const DIMS[] = {"Time", "west_east", "south_north", "bottom_top", "bottom_top_stag", "DateStrLen",
                                   "ni", "nj", "nk", "nkp1", "time", "x", "y", "z"};
static const char *const VARS[] = {"P", "PB", "T", "QVAPOR", "PH", "PHB", "HGT", "XLAT", "XLONG", "QCLOUD", "QRAIN",
                                   "QICE", "QSNOW", "QGRAUP", "QHAIL", "QNRAIN", "QNICE", "Times", "XTIME", "xh",
                                   "yh", "zh", "zf", "qc", "qr", "qg", "prs", "th", "qv", "time", "x", "y", "z",
                                   "cl", "ta", "pa", "hus", "lcc"};
static const char *const ATTS[] = {"scale_factor", "add_offset", "_FillValue", "missing_value", "units",
                                   "standard_name", "grid_mapping", "grid_mapping_name", "positive",
                                   "standard_parallel", "longitude_of_central_meridian"};
static const char *const GLOBALS[] = {"DX", "DY", "MAP_PROJ", "MP_PHYSICS", "TRUELAT1", "TRUELAT2", "STAND_LON",
                                      "SIMULATION_START_DATE"};
static const char *const TEXTS[] = {"km", "m", "degrees_east", "minutes since 2005-08-28 12:00:00",
                                    "hours since 2024-06-15", "seconds", "up", "down", "lcc",
                                    "lambert_conformal_conic", "geostationary", "mercator",
                                    "mass_fraction_of_cloud_liquid_water_in_air", "mass_fraction_of_graupel_in_air",
                                    "air_pressure", "air_temperature", "air_density", "specific_humidity",
                                    "2005-08-28_12:00:00", ""};
static const nc_type TYPES[] = {NC_BYTE, NC_CHAR, NC_SHORT, NC_INT, NC_FLOAT, NC_DOUBLE};
#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

static void put_attribute(int nc, int varid, const char *name, bytes *b)
{
  if (take(b, 3) == 0) {
    const char *t = TEXTS[take(b, COUNT(TEXTS))];
    nc_put_att_text(nc, varid, name, strlen(t), t);
    return;
  }
  double v[2] = {take_double(b), take_double(b)};
  nc_put_att_double(nc, varid, name, TYPES[2 + take(b, 4)], 1 + take(b, 2), v);
}

/* Most CF skeletons get orderly coordinates and heights (evenly spaced latitudes and longitudes,
 * distinct pressures in either order, hybrid-height terms, geopotential and altitude rising by
 * level with the bytes' noise, now and then missing at the bottom), so that the fuzzer reaches the load behind the
 * checks; the bytes' values stay in the rest. */
static void structure_pressure_grid(int nc, int varid, int n, const size_t *count, double *x, bytes *b)
{
  char name[NC_MAX_NAME + 1];
  nc_inq_varname(nc, varid, name);
  size_t total = 1;
  for (int d = 0; d < n; ++d) total *= count[d];
  const double sign = take(b, 2) ? 1.0 : -1.0;
  if (n == 1 && (!strcmp(name, "lat") || !strcmp(name, "lon") || !strcmp(name, "plev") ||
                 !strcmp(name, "level_height") || !strcmp(name, "sigma")))
    for (size_t i = 0; i < total; ++i)
      x[i] = !strcmp(name, "plev")           ? 500.0 + sign * 50.0 * i
             : !strcmp(name, "level_height") ? 100.0 + 500.0 * i
             : !strcmp(name, "sigma")        ? 1.0 / (1.0 + i)
                                             : 10.0 + sign * 0.25 * i;
  if (n == 2 && !strcmp(name, "surface_altitude"))
    for (size_t i = 0; i < total; ++i) x[i] = take(b, 300);
  if (n == 4 && (!strcmp(name, "z") || !strcmp(name, "zg") || !strcmp(name, "t") || !strcmp(name, "altitude") ||
                 !strcmp(name, "pa"))) {
    const size_t plane = count[2] * count[3];
    for (size_t i = 0; i < total; ++i) {
      const size_t k = (i / plane) % count[1];
      x[i] = !strcmp(name, "t")    ? 250.0
             : !strcmp(name, "pa") ? 9e4 - 5e3 * k
                                   : (!strcmp(name, "z") ? 9.80665 : 1.0) * (100.0 + 500.0 * k) + take(b, 100);
      if (k == 0 && take(b, 4) == 0) x[i] = NAN;
    }
  }
}

static size_t build(bytes *b, void **image)
{
  int nc;
  if (nc_create_mem("fuzz.nc", NC_64BIT_OFFSET, 4096, &nc) != NC_NOERR) return 0;
  nc_set_fill(nc, NC_FILL, NULL);
  int dimids[COUNT(DIMS) + 6], ndims = 0;
  int varids[24], nvars = 0;
  /* Three quarters of the inputs start from a complete WRF, CM1 or CF pressure-level skeleton (consistent dimensions, every
   * variable the reader needs, each dropped or retyped now and then), so the fuzzer reaches the
   * remap and not only the checks in front of it. */
  const unsigned mode = take(b, 4);
  if (mode == 3) {
    /* CF on pressure levels (ERA5, CMIP), hybrid height (UM) or level numbers with an altitude:
     * levels in either order and unit, a geopotential or its height, temperature, a cloud by
     * standard name or ECMWF short name; values all the bytes'. */
    static const char *const names[] = {"time", "plev", "lat", "lon"};
    const size_t lens[] = {NC_UNLIMITED, 1 + take(b, 5), 1 + take(b, 4), 1 + take(b, 4)};
    for (int d = 0; d < 4; ++d) nc_def_dim(nc, names[d], lens[d], &dimids[ndims++]);
    static const struct {
      const char *name, *std, *units;
      int nd;
    } vars[] = {{"time", NULL, "hours since 2005-08-29", 1}, {"plev", "air_pressure", "hPa", 1},
                {"lat", "latitude", "degrees_north", 1},      {"lon", "longitude", "degrees_east", 1},
                {"z", "geopotential", "m**2 s**-2", 4},       {"zg", "geopotential_height", "m", 4},
                {"t", "air_temperature", "K", 4},             {"q", "specific_humidity", "kg kg**-1", 4},
                {"clwc", NULL, "kg kg**-1", 4},               {"clw", "mass_fraction_of_cloud_liquid_water_in_air", "1", 4},
                {"level_height", NULL, "m", 1},               {"sigma", NULL, "1", 1},
                {"surface_altitude", "surface_altitude", "m", 2}, {"altitude", "altitude", "m", 4},
                {"pa", "air_pressure", "Pa", 4}};
    /* Now and then the levels are hybrid height (a + b orog, formula_terms) or level numbers. */
    const unsigned levels = take(b, 3);
    for (size_t v = 0; v < COUNT(vars); ++v) {
      if (take(b, 8) == 0) continue;
      int vd[4] = {dimids[0], dimids[1], dimids[2], dimids[3]};
      if (vars[v].nd == 1) vd[0] = dimids[v < 4 ? v : 1]; /* coordinates along their own dimension; terms along z */
      if (vars[v].nd == 2) vd[0] = dimids[2], vd[1] = dimids[3];
      if (nc_def_var(nc, vars[v].name, take(b, 4) ? NC_FLOAT : TYPES[2 + take(b, 4)], vars[v].nd, vd,
                     &varids[nvars]) != NC_NOERR)
        continue;
      const char *std = v == 1 && levels == 1 ? "atmosphere_hybrid_height_coordinate"
                        : v == 1 && levels == 2 ? "model_level_number"
                                                : vars[v].std;
      if (std) nc_put_att_text(nc, varids[nvars], "standard_name", strlen(std), std);
      if (v == 1 && levels == 1) {
        const char *terms = take(b, 4) ? "a: level_height b: sigma orog: surface_altitude" : "a: level_height b:";
        nc_put_att_text(nc, varids[nvars], "formula_terms", strlen(terms), terms);
      }
      const char *units = v == 1 && levels ? (levels == 1 ? "m" : "1") : v == 1 && take(b, 2) ? "Pa" : vars[v].units;
      nc_put_att_text(nc, varids[nvars], "units", strlen(units), units);
      for (unsigned a = take(b, 3); a > 0 && take(b, 2); --a) put_attribute(nc, varids[nvars], ATTS[take(b, 4)], b);
      nvars++;
    }
  } else if (mode > 0) {
    const int wrf = mode == 1;
    const char *const names[] = {wrf ? "Time" : "time", wrf ? "bottom_top" : "nk", wrf ? "south_north" : "nj",
                                 wrf ? "west_east" : "ni", wrf ? "bottom_top_stag" : "nkp1", "DateStrLen"};
    const size_t nz = 1 + take(b, 4);
    const size_t lens[] = {NC_UNLIMITED, nz, 1 + take(b, 4), 1 + take(b, 4), nz + 1, 19};
    for (int d = 0; d < 6; ++d) nc_def_dim(nc, names[d], lens[d], &dimids[ndims++]);
    static const char *const wrf_vars[] = {"P", "PB", "T", "QVAPOR", "PH", "PHB", "HGT", "XLAT", "XLONG",
                                           "QCLOUD", "QRAIN", "QICE", "QSNOW", "QGRAUP", "QNRAIN", "Times"};
    static const char *const cm1_vars[] = {"xh", "yh", "zh", "zf", "prs", "th", "qv", "qc", "qr", "qg", "time"};
    const int count = wrf ? (int)COUNT(wrf_vars) : (int)COUNT(cm1_vars);
    for (int v = 0; v < count; ++v) {
      const char *name = wrf ? wrf_vars[v] : cm1_vars[v];
      if (take(b, 8) == 0) continue;
      int vd[4] = {dimids[0], dimids[1], dimids[2], dimids[3]}, n = 4;
      if (!strcmp(name, "PH") || !strcmp(name, "PHB")) vd[1] = dimids[4];
      if (!strcmp(name, "HGT") || !strcmp(name, "XLAT") || !strcmp(name, "XLONG")) vd[1] = dimids[2], vd[2] = dimids[3], n = 3;
      if (!strcmp(name, "Times")) vd[1] = dimids[5], n = 2;
      if (!strcmp(name, "time")) n = 1;
      if (!strcmp(name, "xh")) vd[0] = dimids[3], n = 1;
      if (!strcmp(name, "yh")) vd[0] = dimids[2], n = 1;
      if (!strcmp(name, "zh")) vd[0] = dimids[1], n = 1;
      if (!strcmp(name, "zf")) vd[0] = dimids[4], n = 1;
      const nc_type type = !strcmp(name, "Times") ? NC_CHAR : take(b, 4) ? NC_FLOAT : TYPES[2 + take(b, 4)];
      if (nc_def_var(nc, name, type, n, vd, &varids[nvars]) != NC_NOERR) continue;
      for (unsigned a = take(b, 3); a > 0 && take(b, 2); --a) put_attribute(nc, varids[nvars], ATTS[take(b, 4)], b);
      nvars++;
    }
    if (wrf) {
      const double dx = 1000.0, proj = 1 + take(b, 7), mp = take(b, 12);
      nc_put_att_double(nc, NC_GLOBAL, "DX", NC_FLOAT, 1, &dx);
      nc_put_att_double(nc, NC_GLOBAL, "DY", NC_FLOAT, 1, &dx);
      nc_put_att_double(nc, NC_GLOBAL, "MAP_PROJ", NC_INT, 1, &proj);
      nc_put_att_double(nc, NC_GLOBAL, "MP_PHYSICS", NC_INT, 1, &mp);
    }
  }
  const unsigned nd = mode ? take(b, 2) : 1 + take(b, 8);
  for (unsigned i = 0; i < nd; ++i) {
    const unsigned which = take(b, COUNT(DIMS));
    const int unlimited = which == 0 || which == 10;
    if (nc_def_dim(nc, DIMS[which], unlimited ? NC_UNLIMITED : 1 + take(b, 5), &dimids[ndims]) == NC_NOERR) ndims++;
  }
  for (unsigned g = take(b, 6); g > 0; --g) put_attribute(nc, NC_GLOBAL, GLOBALS[take(b, COUNT(GLOBALS))], b);
  for (unsigned v = mode ? take(b, 3) : take(b, 16); v > 0 && nvars < 24 && ndims > 0; --v) {
    int vd[4], n = (int)take(b, 5);
    for (int d = 0; d < n; ++d) vd[d] = dimids[take(b, (unsigned)ndims)];
    if (nc_def_var(nc, VARS[take(b, COUNT(VARS))], TYPES[take(b, COUNT(TYPES))], n, vd, &varids[nvars]) != NC_NOERR)
      continue;
    for (unsigned a = take(b, 4); a > 0; --a) put_attribute(nc, varids[nvars], ATTS[take(b, COUNT(ATTS))], b);
    nvars++;
  }
  if (nc_enddef(nc) != NC_NOERR) {
    nc_abort(nc);
    return 0;
  }
  /* Data: up to 3 records of unlimited dimensions, the rest from the bytes. */
  const size_t records = take(b, 4);
  for (int v = 0; v < nvars; ++v) {
    int n, vd[NC_MAX_VAR_DIMS], unlim;
    nc_inq_varndims(nc, varids[v], &n);
    nc_inq_vardimid(nc, varids[v], vd);
    nc_inq_unlimdim(nc, &unlim);
    size_t start[NC_MAX_VAR_DIMS] = {0}, count[NC_MAX_VAR_DIMS], total = 1;
    for (int d = 0; d < n; ++d) {
      nc_inq_dimlen(nc, vd[d], &count[d]);
      if (vd[d] == unlim) count[d] = records;
      total *= count[d];
    }
    if (total == 0 || total > 4096) continue;
    double *x = malloc(total * sizeof(double));
    for (size_t i = 0; i < total; ++i) x[i] = take_double(b);
    if (mode == 3 && take(b, 4)) structure_pressure_grid(nc, varids[v], n, count, x, b);
    nc_type type;
    nc_inq_vartype(nc, varids[v], &type);
    if (type == NC_CHAR) {
      char *t = malloc(total);
      for (size_t i = 0; i < total; ++i) t[i] = (char)(32 + take(b, 95));
      nc_put_vara_text(nc, varids[v], start, count, t);
      free(t);
    } else {
      nc_put_vara_double(nc, varids[v], start, count, x); /* out-of-range values: NC_ERANGE, kept as fill */
    }
    free(x);
  }
  NC_memio memio = {0};
  if (nc_close_memio(nc, &memio) != NC_NOERR) return 0;
  *image = memio.memory;
  return memio.size;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  bytes b = {data, size};
  void *image = NULL;
  const size_t n = build(&b, &image);
  if (n == 0) {
    free(image);
    return 0;
  }
  sl_load_options opt = {0};
  opt.max_memory = 64.0 * 1024 * 1024;
  opt.time_index = (int)take(&b, 3);
  opt.stride = (int)take(&b, 3);
  sl_storm_frame frame;
  sl_error err = {0};
  if (sl_storm_load_memory("fuzz.nc", image, n, &opt, &frame, &err) == SL_OK) sl_storm_frame_free(&frame);
  free(image);
  return 0;
}
