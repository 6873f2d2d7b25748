/* WRF wrfout reader: dimensions, projection attributes, times, and one time read variable by
 * variable from terrain-following eta levels onto a uniform east-north-up grid (remap.c). Also the
 * load entry points, which dispatch by content to this reader or cf_read.c. */
#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef __GLIBC__
#include <malloc.h> /* malloc_trim */
#endif

#include "sl_large_alloc.h"
#include "storm_internal.h"

/* WRF's constants (share/module_model_constants.F): R_d = 287, c_p = 7 R_d / 2, R_v = 461.6,
 * p0 = 1e5 Pa, g = 9.81 m/s2, theta base = 300 K. */
#define WRF_RD 287.0
#define WRF_CP (3.5 * WRF_RD)
#define WRF_RV 461.6
#define WRF_P0 1.0e5
#define WRF_G 9.81
#define WRF_T0 300.0

double sl_dry_air_density(double pressure, double temperature, double qv)
{
  const double eps = WRF_RD / WRF_RV;
  return pressure / (WRF_RD * temperature * (1.0 + qv / eps));
}

double sl_temperature_from_theta(double theta, double pressure)
{
  return theta * pow(pressure / WRF_P0, WRF_RD / WRF_CP);
}

double sl_temperature_from_wrf(double theta_perturbation, double pressure)
{
  return sl_temperature_from_theta(theta_perturbation + WRF_T0, pressure);
}

/* Without Times: XTIME (minutes since a date in its units, else since START_DATE /
 * SIMULATION_START_DATE). Leaves has_times 0 when neither is usable (index-only). */
static void times_from_xtime(const sl_nc *f, sl_storm_info *info)
{
  int vid;
  if (nc_inq_varid(f->id, "XTIME", &vid) != NC_NOERR || !sl_nc_var_is_1d(f, vid, (size_t)info->ntimes, NULL)) return;
  char units[256] = "";
  size_t len = 0;
  if (nc_inq_attlen(f->id, vid, "units", &len) == NC_NOERR && len < sizeof units)
    nc_get_att_text(f->id, vid, "units", units), units[len] = '\0';
  int base[6] = {0};
  const char *since = strstr(units, "since ");
  int ok = 0;
  if (since && sscanf(since + 6, "%d-%d-%d%*[ _T]%d:%d:%d", &base[0], &base[1], &base[2], &base[3], &base[4],
                      &base[5]) == 6)
    ok = 1;
  if (!ok && strncmp(units, "minutes", 7) == 0) {
    char start[64] = "";
    if (nc_inq_attlen(f->id, NC_GLOBAL, "SIMULATION_START_DATE", &len) == NC_NOERR && len < sizeof start)
      nc_get_att_text(f->id, NC_GLOBAL, "SIMULATION_START_DATE", start), start[len] = '\0';
    ok = sscanf(start, "%d-%d-%d_%d:%d:%d", &base[0], &base[1], &base[2], &base[3], &base[4], &base[5]) == 6;
  }
  /* WRF counts on the Gregorian calendar. */
  if (!ok || strncmp(units, "minutes", 7) != 0 || !sl_calendar_valid(SL_CAL_STANDARD, base)) return;
  double *minutes = malloc((size_t)info->ntimes * sizeof(double));
  if (!minutes) return;
  size_t start = 0, count = (size_t)info->ntimes;
  if (nc_get_vara_double(f->id, vid, &start, &count, minutes) == NC_NOERR) {
    info->has_times = 1;
    for (int t = 0; t < info->ntimes && info->has_times; ++t) {
      int at[6];
      if (!sl_calendar_add_seconds(SL_CAL_STANDARD, base, minutes[t] * 60.0, at)) {
        info->has_times = 0; /* absurd offsets: index-only times */
        break;
      }
      sl_calendar_format(at, info->times[t]);
    }
  }
  free(minutes);
}

static int dim_length(const sl_nc *f, const char *name, int *len, sl_error *err)
{
  int dimid;
  size_t n;
  if (nc_inq_dimid(f->id, name, &dimid) != NC_NOERR)
    return sl_fail(err, SL_ERR_FORMAT, "%s: missing dimension '%s' (not a WRF file?)", f->path, name);
  if (nc_inq_dimlen(f->id, dimid, &n) != NC_NOERR || n > 100000)
    return sl_fail(err, SL_ERR_DATA, "%s: dimension '%s' has an absurd length", f->path, name);
  if (n == 0)
    return sl_fail(err, SL_ERR_DATA, "%s: dimension '%s' is empty (the file has no %s)", f->path, name,
                   strcmp(name, "Time") == 0 ? "time records" : "grid points");
  *len = (int)n;
  return SL_OK;
}

/* WRF's projections (MAP_PROJ): 0 idealised (no projection), 1 Lambert conformal, 2 polar
 * stereographic, 3 Mercator, 6 latitude-longitude (rotated or not). */
/* An integer code held in a floating attribute (MAP_PROJ, MP_PHYSICS): -1 when it is not finite
 * or out of int range (a fuzzed or corrupt file must not make the cast undefined). */
static int attr_code(double v)
{
  return isfinite(v) && v > -1e6 && v < 1e6 ? (int)v : -1;
}

static int map_proj_supported(int map_proj) { return map_proj == 0 || map_proj == 1 || map_proj == 2 || map_proj == 3 || map_proj == 6; }

static int wrf_read_info(const sl_nc *f, sl_storm_info *info, sl_error *err)
{
  const char *path = f->path;
  int rc = SL_OK;
  info->kind = SL_STORM_WRF;
  snprintf(info->vertical, sizeof info->vertical, "model levels (eta), heights (PH+PHB)/g per column");
  if ((rc = dim_length(f, "west_east", &info->nx, err)) || (rc = dim_length(f, "south_north", &info->ny, err)) ||
      (rc = dim_length(f, "bottom_top", &info->nz, err)) || (rc = dim_length(f, "Time", &info->ntimes, err)))
    return rc;
  if (info->ntimes > SL_MAX_TIMES)
    return sl_fail(err, SL_ERR_FORMAT, "%s: %d times, more than this reader handles (%d)", path, info->ntimes,
                   SL_MAX_TIMES);
  info->dx = sl_nc_attr_double(f, NC_GLOBAL, "DX", NAN);
  info->dy = sl_nc_attr_double(f, NC_GLOBAL, "DY", NAN);
  if (!(info->dx > 0.0 && info->dx < 1e6) || !(info->dy > 0.0 && info->dy < 1e6))
    return sl_fail(err, SL_ERR_FORMAT, "%s: missing or absurd grid spacing attributes DX/DY", path);
  const double map_proj = sl_nc_attr_double(f, NC_GLOBAL, "MAP_PROJ", NAN);
  if (isnan(map_proj))
    return sl_fail(err, SL_ERR_FORMAT, "%s: missing the global attribute MAP_PROJ (the map projection of the grid)", path);
  info->map_proj = attr_code(map_proj);
  if (!map_proj_supported(info->map_proj) || info->map_proj != map_proj)
    return sl_fail(err, SL_ERR_FORMAT,
                   "%s: unsupported map projection MAP_PROJ=%g (supported: 1 Lambert conformal, 2 polar "
                   "stereographic, 3 Mercator, 6 latitude-longitude)",
                   path, map_proj);
  info->truelat1 = sl_nc_attr_double(f, NC_GLOBAL, "TRUELAT1", NAN);
  info->truelat2 = sl_nc_attr_double(f, NC_GLOBAL, "TRUELAT2", NAN);
  info->stand_lon = sl_nc_attr_double(f, NC_GLOBAL, "STAND_LON", NAN);
  info->pole_lat = sl_nc_attr_double(f, NC_GLOBAL, "POLE_LAT", 90.0);
  info->pole_lon = sl_nc_attr_double(f, NC_GLOBAL, "POLE_LON", 0.0);
  info->mp_physics = attr_code(sl_nc_attr_double(f, NC_GLOBAL, "MP_PHYSICS", -1));
  sl_species_wrf(f, info->mp_physics, info);

  /* Times(Time, <string dim>): the string dimension's name varies between writers. */
  int tid;
  if (nc_inq_varid(f->id, "Times", &tid) == NC_NOERR) {
    int nd, dimids[NC_MAX_VAR_DIMS];
    nc_type type;
    nc_inq_vartype(f->id, tid, &type);
    nc_inq_varndims(f->id, tid, &nd);
    size_t slen = 0, tlen = 0;
    if (type == NC_CHAR && nd == 2) {
      nc_inq_vardimid(f->id, tid, dimids);
      nc_inq_dimlen(f->id, dimids[0], &tlen);
      nc_inq_dimlen(f->id, dimids[1], &slen);
    }
    /* Only the first ntimes strings are read: a Times longer than the Time dimension (or along
     * another one) must not overrun the buffer. */
    if (slen > 0 && slen < 64 && tlen >= (size_t)info->ntimes) {
      char *buf = calloc((size_t)info->ntimes, slen);
      const size_t start[2] = {0, 0}, count[2] = {(size_t)info->ntimes, slen};
      if (buf && nc_get_vara_text(f->id, tid, start, count, buf) == NC_NOERR) {
        for (int t = 0; t < info->ntimes; ++t) {
          size_t n = slen < 23 ? slen : 23;
          memcpy(info->times[t], buf + (size_t)t * slen, n);
          info->times[t][n] = '\0';
        }
        info->has_times = 1;
      }
      free(buf);
    }
  }
  if (!info->has_times) times_from_xtime(f, info);
  return SL_OK;
}

/* Dispatch by content: WRF's dimension names, else CF / CM1. */
static int read_info_nc(const sl_nc *f, sl_storm_info *info, sl_error *err)
{
  memset(info, 0, sizeof *info);
  snprintf(info->path, sizeof info->path, "%s", f->path);
  nc_inq_format(f->id, &info->format);
  info->mp_physics = -1;
  info->cm1_ptype = -1;
  int dimid, rc;
  if (nc_inq_dimid(f->id, "west_east", &dimid) == NC_NOERR || nc_inq_dimid(f->id, "bottom_top", &dimid) == NC_NOERR)
    rc = wrf_read_info(f, info, err);
  else
    rc = sl_cf_read_info(f, info, err);
  if (!info->calendar[0]) snprintf(info->calendar, sizeof info->calendar, "standard");
  for (int t = 0; info->has_times && t < info->ntimes && t < SL_MAX_TIMES; ++t)
    if (!info->sun_times[t][0]) memcpy(info->sun_times[t], info->times[t], sizeof info->times[t]);
  return rc;
}

int sl_storm_read_info(const char *path, sl_storm_info *info, sl_error *err)
{
  sl_nc f;
  memset(info, 0, sizeof *info);
  snprintf(info->path, sizeof info->path, "%s", path);
  if (sl_nc_open(path, NULL, 0, &f, err)) return err->code;
  const int rc = read_info_nc(&f, info, err);
  nc_close(f.id);
  return rc;
}

/* The WRF reader behind the remap: PH/PHB interfaces, P/PB/T/QVAPOR air state and the
 * hydrometeor variables, each read once over the subset's levels and columns. */
typedef struct wrf_levels {
  const sl_nc *f;
  int t;
  const sl_subset *s;
  size_t n2;
  sl_nc_var ph, phb, p, pb, theta, qv;
  sl_var_cache cache;
  size_t l3[3];
  float *scratch[2]; /* two_buffers' arrays, kept from block to block (freed by the load) */
  size_t scratch_n;
} wrf_levels;

static int wrf_slab(wrf_levels *w, const sl_nc_var *v, int k, double *out, sl_error *err)
{
  int rc = sl_nc_read_slab(w->f, v, w->t, k, w->s, out, err);
  if (!rc) rc = sl_all_finite(w->f, v->name, w->t, out, w->n2, err);
  return rc;
}

/* Two float work arrays of n floats, read whole (on huge pages: remap.c). They are the same two
 * from block to block, so that each block does not fault in fresh pages (a block of 1000 x 1000
 * columns and 27 levels is 216 MB of them); the load frees them. */
static int two_buffers(wrf_levels *w, size_t n, float **a, float **b, sl_error *err)
{
  if (n > w->scratch_n) {
    for (int i = 0; i < 2; ++i) free(w->scratch[i]), w->scratch[i] = sl__huge_alloc(n * sizeof(float));
    w->scratch_n = w->scratch[0] && w->scratch[1] ? n : 0;
    if (!w->scratch_n) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", w->f->path);
  }
  *a = w->scratch[0], *b = w->scratch[1];
  return SL_OK;
}

static int wrf_interfaces(void *ctx, int k0, int nk, double *z, sl_error *err)
{
  wrf_levels *w = ctx;
  const size_t n = (size_t)nk * w->n2;
  float *ph = NULL, *phb = NULL;
  int rc = two_buffers(w, n, &ph, &phb, err);
  if (!rc) rc = sl_nc_read_block(w->f, &w->ph, w->t, w->s->k0 + k0, nk, w->s, ph, err);
  if (!rc) rc = sl_nc_read_block(w->f, &w->phb, w->t, w->s->k0 + k0, nk, w->s, phb, err);
  if (rc) return rc;
  /* Geopotential to height. */
#pragma omp parallel for simd schedule(dynamic, SL_IO_CHUNK) if (n > SL_IO_CHUNK)
  for (size_t i = 0; i < n; ++i) z[i] = ((double)ph[i] + (double)phb[i]) / WRF_G;
  return SL_OK;
}

static int wrf_air(void *ctx, int k_block, int nk, float *rho_dry, float *rho_moist, unsigned char *frozen,
                   sl_error *err)
{
  wrf_levels *w = ctx;
  const int k0 = w->s->k0 + k_block;
  const size_t n = (size_t)nk * w->n2;
  float *pb = NULL, *theta = NULL, *qv = rho_dry; /* rho_dry holds P + PB first */
  float *p = rho_dry;
  int rc = two_buffers(w, n, &pb, &theta, err);
  if (!rc) rc = sl_nc_read_block(w->f, &w->p, w->t, k0, nk, w->s, p, err);
  if (!rc) rc = sl_nc_read_block(w->f, &w->pb, w->t, k0, nk, w->s, pb, err);
  if (!rc) {
    int bad = 0;
#pragma omp parallel for simd schedule(dynamic, SL_IO_CHUNK) reduction(| : bad) if (n > SL_IO_CHUNK)
    for (size_t i = 0; i < n; ++i) {
      pb[i] += p[i];
      bad |= !(pb[i] > 0.0f);
    }
    if (bad) rc = sl_fail(err, SL_ERR_DATA, "%s: non-positive pressure P+PB at time %d", w->f->path, w->t);
  }
  if (!rc) rc = sl_nc_read_block(w->f, &w->theta, w->t, k0, nk, w->s, theta, err);
  if (!rc) rc = sl_nc_read_block(w->f, &w->qv, w->t, k0, nk, w->s, qv, err);
  if (rc) return rc;
  /* Cell by cell, so shared among the threads (the reads above stay on this one: netCDF's). */
#pragma omp parallel for schedule(dynamic, SL_IO_CHUNK) if (n > SL_IO_CHUNK)
  for (size_t i = 0; i < n; ++i) {
    const double pressure = pb[i], qvap = qv[i] > 0.0f ? qv[i] : 0.0;
    const double temperature = sl_temperature_from_wrf(theta[i], pressure);
    frozen[i] = temperature < SL_FREEZING_K;
    const double rho = sl_dry_air_density(pressure, temperature, qvap);
    rho_dry[i] = (float)rho;
    if (rho_moist) rho_moist[i] = (float)(rho * (1.0 + qvap));
  }
  return SL_OK;
}

static int wrf_field(void *ctx, const char *name, int k0, int nk, float *out, sl_error *err)
{
  wrf_levels *w = ctx;
  const char *const d3[] = {"bottom_top", "south_north", "west_east"};
  const size_t l3[] = {w->l3[0], w->l3[1], w->l3[2]};
  const sl_nc_var *v;
  const int rc = sl_var_cache_get(&w->cache, w->f, name, d3, l3, &v, err);
  return rc ? rc : sl_nc_read_block(w->f, v, w->t, w->s->k0 + k0, nk, w->s, out, err);
}

/* The remap's blocks follow the largest chunk layer of the variables it reads (WRF writes one
 * chunking for all where it compresses). */
static int wrf_chunk_levels(wrf_levels *w, const sl_species *species, int nspecies, int *levels, sl_error *err)
{
  const char *const d3[] = {"bottom_top", "south_north", "west_east"};
  const sl_nc_var *const air[] = {&w->p, &w->pb, &w->theta, &w->qv, &w->ph, &w->phb};
  *levels = 1;
  for (size_t i = 0; i < sizeof air / sizeof air[0]; ++i) {
    const int e = sl_nc_chunk_levels(w->f, air[i]);
    if (e > *levels) *levels = e;
  }
  return sl_species_chunk_levels(&w->cache, w->f, d3, w->l3, species, nspecies, levels, err);
}

/* Columns inside lat0..lat1, lon0..lon1 at time t: their bounding box in grid indices. */
static int wrf_region(const sl_nc *f, const sl_storm_info *info, int t, const double region[4], sl_subset *s,
                      sl_error *err)
{
  const char *const d2[] = {"south_north", "west_east"};
  const size_t l2[] = {(size_t)info->ny, (size_t)info->nx};
  const size_t n2 = (size_t)info->nx * info->ny;
  sl_nc_var vlat, vlon;
  sl_subset all = {0, 0, 1, info->nx, info->ny, 0, 0};
  double *lat = malloc(n2 * sizeof(double)), *lon = malloc(n2 * sizeof(double));
  int rc = !lat || !lon ? sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", f->path) : SL_OK;
  if (!rc && !(rc = sl_nc_var_open(f, "XLAT", 2, d2, l2, &vlat, err)) &&
      !(rc = sl_nc_var_open(f, "XLONG", 2, d2, l2, &vlon, err)) && !(rc = sl_nc_read_slab(f, &vlat, t, -1, &all, lat, err)))
    rc = sl_nc_read_slab(f, &vlon, t, -1, &all, lon, err);
  int i0 = info->nx, i1 = -1, j0 = info->ny, j1 = -1;
  const double lon1 = region[3] >= region[2] ? region[3] : region[3] + 360.0;
  for (int j = 0; !rc && j < info->ny; ++j)
    for (int i = 0; i < info->nx; ++i) {
      const double la = lat[(size_t)j * info->nx + i];
      double lo = lon[(size_t)j * info->nx + i];
      lo = region[2] + fmod(fmod(lo - region[2], 360.0) + 360.0, 360.0);
      if (la < region[0] || la > region[1] || lo > lon1) continue;
      if (i < i0) i0 = i;
      if (i > i1) i1 = i;
      if (j < j0) j0 = j;
      if (j > j1) j1 = j;
    }
  if (!rc && i1 < 0)
    rc = sl_fail(err, SL_ERR_ARG, "%s: --region %g,%g,%g,%g holds no grid column at time %d", f->path, region[0],
                 region[1], region[2], region[3], t);
  if (!rc) {
    s->i0 = i0, s->j0 = j0;
    s->nx = (i1 - i0) / s->stride + 1, s->ny = (j1 - j0) / s->stride + 1;
  }
  free(lat);
  free(lon);
  return rc;
}

/* The subset of columns and levels the options ask for (whole grid by default). */
static int load_subset(const sl_nc *f, const sl_storm_info *info, const sl_load_options *opt, sl_subset *s,
                       sl_error *err)
{
  s->stride = opt && opt->stride > 1 ? opt->stride : 1;
  s->i0 = s->j0 = 0;
  s->nx = (info->nx - 1) / s->stride + 1, s->ny = (info->ny - 1) / s->stride + 1;
  s->k0 = opt ? opt->level_first : 0;
  s->nz = opt && opt->level_count > 0 ? opt->level_count : info->nz - s->k0;
  if (s->k0 < 0 || s->k0 >= info->nz || s->nz < 1 || s->k0 + s->nz > info->nz)
    return sl_fail(err, SL_ERR_ARG, "%s: --levels %d:%d outside the file's %d model levels", f->path, s->k0,
                   s->k0 + s->nz - 1, info->nz);
  if (opt && opt->has_region) {
    if (info->kind != SL_STORM_WRF)
      return sl_fail(err, SL_ERR_ARG, "%s: --region needs XLAT/XLONG (a WRF file)", f->path);
    if (info->map_proj == 0)
      return sl_fail(err, SL_ERR_ARG, "%s: --region needs latitudes: MAP_PROJ 0 (an idealized run) has none", f->path);
    return wrf_region(f, info, opt->time_index, opt->region, s, err);
  }
  return SL_OK;
}

/* The scene around the storm: terrain height, latitude/longitude and the optional surface
 * fields per column, kept for the terrain surface and the map overlays (app/terrain_scene). */
static int keep_optional_column_field(wrf_levels *w, const char *name, const size_t *l2, double *scratch,
                                      float **out, sl_error *err)
{
  if (!sl_nc_has_var(w->f, name)) return SL_OK;
  const char *const d2[] = {"south_north", "west_east"};
  sl_nc_var v;
  int rc = sl_nc_var_open(w->f, name, 2, d2, l2, &v, err);
  if (!rc) rc = wrf_slab(w, &v, -1, scratch, err);
  if (rc) return rc;
  *out = malloc(w->n2 * sizeof(float));
  if (!*out) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", w->f->path);
  for (size_t c = 0; c < w->n2; ++c) (*out)[c] = (float)scratch[c];
  return SL_OK;
}

static int keep_columns(sl_storm_frame *frame, wrf_levels *w, const size_t *l2, const sl_nc_var *hgt,
                        const sl_nc_var *xlat, const sl_nc_var *xlong, double *scratch, sl_error *err)
{
  const size_t n2 = w->n2;
  int rc;
  if ((rc = keep_optional_column_field(w, "ALBEDO", l2, scratch, &frame->surface_albedo, err))) return rc;
  if ((rc = keep_optional_column_field(w, "LANDMASK", l2, scratch, &frame->land_mask, err))) return rc;
  if (!frame->land_mask) {
    if ((rc = keep_optional_column_field(w, "XLAND", l2, scratch, &frame->land_mask, err))) return rc;
    for (size_t c = 0; frame->land_mask && c < n2; ++c) frame->land_mask[c] = frame->land_mask[c] < 1.5f ? 1.0f : 0.0f;
  }
  frame->terrain_height = malloc(n2 * sizeof(float));
  if (!frame->terrain_height) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", w->f->path);
  if ((rc = wrf_slab(w, hgt, -1, scratch, err))) return rc;
  for (size_t c = 0; c < n2; ++c) frame->terrain_height[c] = (float)scratch[c];
  if (!xlat) return SL_OK; /* a grid without latitudes (MAP_PROJ 0) */
  frame->column_lat = malloc(n2 * sizeof(double));
  frame->column_lon = malloc(n2 * sizeof(double));
  if (!frame->column_lat || !frame->column_lon) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", w->f->path);
  if ((rc = wrf_slab(w, xlat, -1, frame->column_lat, err))) return rc;
  return wrf_slab(w, xlong, -1, frame->column_lon, err);
}

/* Georeferencing (io/georef.c) on the whole grid: this time's XLAT/XLONG place it, so a moving
 * nest sits where it was; the projection from the attributes is checked against them. The
 * subset's columns are then the whole grid's, every stride-th from (i0, j0). An idealized run
 * (no xlat) is a flat plane; --origin moves the world frame's tangent point. */
static int wrf_georeference(const sl_nc *f, const sl_storm_info *info, const sl_load_options *opt, int t,
                            const sl_nc_var *xlat, const sl_nc_var *xlong, sl_georef *georef, sl_error *err)
{
  if (!xlat) {
    sl_georef_flat(georef, info->nx, info->ny, info->dx, info->dy);
    return SL_OK;
  }
  const size_t nfull = (size_t)info->nx * info->ny;
  const sl_subset whole = {.stride = 1, .nx = info->nx, .ny = info->ny, .nz = 1};
  double *lat_full = malloc(nfull * sizeof(double)), *lon_full = malloc(nfull * sizeof(double));
  int rc = SL_OK;
  if (!lat_full || !lon_full) rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", f->path);
  if (!rc) rc = sl_nc_read_slab(f, xlat, t, -1, &whole, lat_full, err);
  if (!rc) rc = sl_nc_read_slab(f, xlong, t, -1, &whole, lon_full, err);
  if (!rc)
    rc = sl_georef_build(georef, info->map_proj, info->truelat1, info->truelat2, info->stand_lon, info->pole_lat,
                         info->pole_lon, info->nx, info->ny, info->dx, info->dy, lat_full, lon_full, f->path, err);
  free(lat_full);
  free(lon_full);
  if (!rc && opt && opt->has_origin) sl_georef_place(georef, opt->origin_lat, opt->origin_lon);
  return rc;
}

static int wrf_load(const sl_nc *f, const sl_storm_info *info, const sl_load_options *opt, const sl_species *species,
                    int nspecies, sl_storm_frame *frame, sl_error *err)
{
  const char *path = f->path;
  const int t = opt ? opt->time_index : 0;
  sl_subset s;
  int rc;
  /* Before reading anything large: the output grid at the default resolution and the buffers. */
  const double whole = opt && opt->has_region ? 2.0 * info->nx * info->ny * sizeof(double) : 0.0;
  frame->memory_estimate = sl_storm_memory_estimate(info, opt) + whole;
  if ((rc = sl_check_memory(path, frame->memory_estimate, opt, err))) return rc;
  if ((rc = load_subset(f, info, opt, &s, err))) return rc;
  const size_t n2 = (size_t)s.nx * s.ny;
  wrf_levels w = {.f = f, .t = t, .s = &s, .n2 = n2, .l3 = {(size_t)info->nz, (size_t)info->ny, (size_t)info->nx}};
  const char *const d3[] = {"bottom_top", "south_north", "west_east"};
  const char *const d3s[] = {"bottom_top_stag", "south_north", "west_east"};
  const char *const d2[] = {"south_north", "west_east"};
  const size_t l3[] = {(size_t)info->nz, (size_t)info->ny, (size_t)info->nx};
  const size_t l3s[] = {(size_t)info->nz + 1, (size_t)info->ny, (size_t)info->nx};
  const size_t l2[] = {(size_t)info->ny, (size_t)info->nx};
  sl_nc_var hgt, xlat, xlong;
  if ((rc = sl_nc_var_open(f, "P", 3, d3, l3, &w.p, err)) || (rc = sl_nc_var_open(f, "PB", 3, d3, l3, &w.pb, err)) ||
      (rc = sl_nc_var_open(f, "T", 3, d3, l3, &w.theta, err)) ||
      (rc = sl_nc_var_open(f, "QVAPOR", 3, d3, l3, &w.qv, err)) ||
      (rc = sl_nc_var_open(f, "PH", 3, d3s, l3s, &w.ph, err)) ||
      (rc = sl_nc_var_open(f, "PHB", 3, d3s, l3s, &w.phb, err)) || (rc = sl_nc_var_open(f, "HGT", 2, d2, l2, &hgt, err)))
    return rc;
  /* An idealized run (MAP_PROJ 0: em_quarter_ss, em_squall2d, ...) has no place on the earth, and
   * its XLAT/XLONG, where written at all, hold zeros. */
  const int flat = info->map_proj == 0;
  if (!flat && ((rc = sl_nc_var_open(f, "XLAT", 2, d2, l2, &xlat, err)) ||
                (rc = sl_nc_var_open(f, "XLONG", 2, d2, l2, &xlong, err))))
    return rc;
  double *a = malloc(n2 * sizeof(double)), *b = malloc(n2 * sizeof(double));
  double *drop = NULL; /* per column, m: the sphere's depth below the world's tangent plane */
  if (!a || !b) {
    rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory for %zu columns", path, n2);
    goto done;
  }
  /* The output grid spans the lowest ground (or the lowest interface read) to the highest top. */
  double ground = INFINITY, top = -INFINITY, hmax = -INFINITY;
  if ((rc = wrf_slab(&w, &hgt, -1, a, err))) goto done;
  for (size_t c = 0; c < n2; ++c) ground = fmin(ground, a[c]), hmax = fmax(hmax, a[c]);
  if (s.k0 > 0) {
    if ((rc = wrf_interfaces(&w, 0, 1, a, err))) goto done;
    ground = INFINITY;
    for (size_t c = 0; c < n2; ++c) ground = fmin(ground, a[c]);
  }
  if ((rc = wrf_interfaces(&w, s.nz, 1, b, err))) goto done;
  for (size_t c = 0; c < n2; ++c) top = fmax(top, b[c]);
  if (!(top > ground)) {
    rc = sl_fail(err, SL_ERR_DATA, "%s: the model top lies below the ground at time %d", path, t);
    goto done;
  }
  const double dz = opt && opt->dz > 0.0 ? opt->dz : (top - ground) / (2.0 * s.nz);
  const double nzo = ceil((top - ground) / dz);
  sl_level_reader r = {&w, wrf_interfaces, wrf_air, wrf_field, 1, s.k0, opt ? opt->block_levels : 0};
  if ((rc = wrf_chunk_levels(&w, species, nspecies, &r.chunk_levels, err))) goto done;
  frame->memory_estimate = sl_load_bytes((size_t)s.nx, (size_t)s.ny, (size_t)sl_remap_block_levels(&r, s.nz, n2),
                                         nzo > 1 ? (size_t)fmin(nzo, 1e9) : 1, sl_species_type_count(species, nspecies));
  if (nzo <= 4096 && (rc = sl_check_memory(path, frame->memory_estimate, opt, err))) goto done;
  if ((rc = wrf_georeference(f, info, opt, t, flat ? NULL : &xlat, flat ? NULL : &xlong, &frame->georef, err)))
    goto done;
  const sl_georef *geo = &frame->georef;
  /* Ground distance between columns at the centre (DX over the map factor), ENU corner. */
  const double spacing_h[2] = {geo->ground_dx * s.stride, geo->ground_dy * s.stride};
  const double corner_xy[2] = {geo->center_enu[0] - 0.5 * (info->nx - 1) * geo->ground_dx + s.i0 * geo->ground_dx,
                               geo->center_enu[1] - 0.5 * (info->ny - 1) * geo->ground_dy + s.j0 * geo->ground_dy};
  double max_drop = 0.0;
  if (opt && opt->earth_curvature) {
    if (!(drop = malloc(n2 * sizeof(double)))) {
      rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
      goto done;
    }
    for (int j = 0; j < s.ny; ++j)
      for (int i = 0; i < s.nx; ++i) {
        const double d = sl_curvature_drop(hypot(corner_xy[0] + i * spacing_h[0], corner_xy[1] + j * spacing_h[1]));
        drop[(size_t)j * s.nx + i] = d;
        if (d > max_drop) max_drop = d;
      }
  }
  if ((rc = sl_remap_levels(path, &r, &s, species, nspecies, ground - max_drop, top, dz, spacing_h, corner_xy, drop,
                            opt ? opt->max_fields : 0, frame, err)))
    goto done;
  if ((rc = keep_columns(frame, &w, l2, &hgt, flat ? NULL : &xlat, flat ? NULL : &xlong, a, err))) goto done;
  /* The ground sinks with its columns, so the terrain surface stays under its storm. */
  if (drop)
    for (size_t c = 0; c < n2; ++c) frame->terrain_height[c] -= (float)drop[c];
  /* Where the grid sits on the earth: the whole grid's centre (between columns when a count is
   * even) from the georeference, a subset's centre column from its own latitudes/longitudes. */
  const size_t centre = (size_t)(s.ny / 2) * s.nx + s.nx / 2;
  const int whole_grid = s.stride == 1 && s.nx == info->nx && s.ny == info->ny;
  if (flat) {
    /* --origin says where the idealized storm stands (its centre), for a sun from a date. */
    frame->center_lat = opt && opt->has_origin ? opt->origin_lat : NAN;
    frame->center_lon = opt && opt->has_origin ? opt->origin_lon : NAN;
  } else {
    frame->center_lat = whole_grid ? geo->center_lat : frame->column_lat[centre];
    frame->center_lon = whole_grid ? geo->center_lon : frame->column_lon[centre];
  }
  frame->terrain_min = ground;
  frame->terrain_max = hmax;
  frame->model_top = top;
  frame->time_index = t;
done:
  free(a);
  free(b);
  free(drop);
  free(w.scratch[0]);
  free(w.scratch[1]);
  return rc;
}

double sl_storm_memory_estimate(const sl_storm_info *info, const sl_load_options *opt)
{
  const int stride = opt && opt->stride > 1 ? opt->stride : 1;
  const size_t nx = (size_t)(info->nx - 1) / stride + 1, ny = (size_t)(info->ny - 1) / stride + 1;
  const int nz = opt && opt->level_count > 0 ? opt->level_count : info->nz - (opt ? opt->level_first : 0);
  sl_species species[SL_MAX_SPECIES];
  int n = info->nspecies;
  memcpy(species, info->species, sizeof species);
  for (int p = 0; opt && p < SL_PARTICLE_COUNT; ++p)
    if (opt->field_variable[p] && strcmp(opt->field_variable[p], "none") != 0 && n < SL_MAX_SPECIES)
      species[n].warm = species[n].cold = p, ++n;
  /* Default dz: two output levels per model level. */
  const int levels = nz > 0 ? nz : 1;
  return sl_load_bytes(nx, ny, (size_t)sl_remap_block_levels(NULL, levels, nx * ny), 2 * (size_t)levels,
                       sl_species_type_count(species, n));
}

static int load_nc(const sl_nc *f, const sl_load_options *opt, sl_storm_frame *frame, sl_error *err)
{
  sl_storm_info *info = malloc(sizeof *info);
  if (!info) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", f->path);
  int rc = read_info_nc(f, info, err);
  const int t = opt ? opt->time_index : 0;
  if (!rc && (t < 0 || t >= info->ntimes))
    rc = sl_fail(err, SL_ERR_ARG, "%s: time index %d out of range (the file has %d times)", f->path, t,
                 info->ntimes);
  sl_species species[SL_MAX_SPECIES];
  int nspecies = 0;
  if (!rc) rc = sl_map_species_nc(f, info, opt, species, &nspecies, err);
  if (!rc && nspecies == 0)
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: no hydrometeor variables (%s)", f->path,
                 info->kind == SL_STORM_WRF ? "QCLOUD, QRAIN, QICE, QSNOW, QGRAUP, QHAIL"
                                            : "qc, qr, qi, qs, qg or a CF standard_name mass_fraction_of_..._in_air");
  if (!rc)
    rc = info->kind == SL_STORM_WRF ? wrf_load(f, info, opt, species, nspecies, frame, err)
                                    : sl_cf_load(f, info, opt, species, nspecies, frame, err);
  if (rc) sl_storm_frame_free(frame);
  free(info);
  return rc;
}

/* A load frees more than it keeps: each block's reader arrays, and netCDF's and HDF5's own work
 * memory. glibc serves blocks under its sliding mmap threshold (up to 32 MiB) from the heap, and
 * what they leave there stays the process's once freed, under the fields that outlive them (on a
 * 1000 x 1000 x 80 deck, 170 MB with netCDF's chunk caches on, through every later phase of its
 * render: docs/PERFORMANCE.md, "A large storm"). Given back to the kernel at the load's end. */
static void return_freed_heap(void)
{
#ifdef __GLIBC__
  (void)malloc_trim(0);
#endif
}

int sl_storm_load(const char *path, const sl_load_options *opt, sl_storm_frame *frame, sl_error *err)
{
  memset(frame, 0, sizeof *frame);
  sl_nc f;
  if (sl_nc_open(path, NULL, 0, &f, err)) return err->code;
  const int rc = load_nc(&f, opt, frame, err);
  nc_close(f.id);
  return_freed_heap();
  return rc;
}

int sl_storm_load_memory(const char *name, const void *data, size_t size, const sl_load_options *opt,
                         sl_storm_frame *frame, sl_error *err)
{
  memset(frame, 0, sizeof *frame);
  sl_nc f;
  if (sl_nc_open(name, data, size, &f, err)) return err->code;
  const int rc = load_nc(&f, opt, frame, err);
  nc_close(f.id);
  return_freed_heap();
  return rc;
}

void sl_storm_frame_free(sl_storm_frame *frame)
{
  sl_volume_free(&frame->volume);
  free(frame->terrain_height);
  free(frame->column_lat);
  free(frame->column_lon);
  free(frame->surface_albedo);
  free(frame->land_mask);
  frame->surface_albedo = frame->land_mask = NULL;
  frame->terrain_height = NULL;
  frame->column_lat = frame->column_lon = NULL;
}
