/* WRF wrfout reader: dimensions, projection attributes, times, and one time resampled from
 * terrain-following eta levels to a uniform east-north-up grid. */
#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sl_storm.h"

/* WRF's constants (share/module_model_constants.F): R_d = 287, c_p = 7 R_d / 2, R_v = 461.6,
 * p0 = 1e5 Pa, g = 9.81 m/s2, theta base = 300 K. */
#define WRF_RD 287.0
#define WRF_CP (3.5 * WRF_RD)
#define WRF_RV 461.6
#define WRF_P0 1.0e5
#define WRF_G 9.81
#define WRF_T0 300.0
#define WRF_FREEZE 273.15

double sl_dry_air_density(double pressure, double temperature, double qv)
{
  const double eps = WRF_RD / WRF_RV;
  return pressure / (WRF_RD * temperature * (1.0 + qv / eps));
}

double sl_temperature_from_wrf(double theta_perturbation, double pressure)
{
  return (theta_perturbation + WRF_T0) * pow(pressure / WRF_P0, WRF_RD / WRF_CP);
}

typedef struct nc_file {
  int id;
  const char *path;
} nc_file;

static int nc_check(int status, const nc_file *f, const char *what, sl_error *err)
{
  if (status == NC_NOERR) return SL_OK;
  return sl_fail(err, SL_ERR_FORMAT, "%s: %s: %s", f->path, what, nc_strerror(status));
}

static int dim_length(const nc_file *f, const char *name, int *len, sl_error *err)
{
  int dimid;
  size_t n;
  if (nc_inq_dimid(f->id, name, &dimid) != NC_NOERR)
    return sl_fail(err, SL_ERR_FORMAT, "%s: missing dimension '%s' (not a WRF file?)", f->path, name);
  if (nc_inq_dimlen(f->id, dimid, &n) != NC_NOERR || n == 0 || n > 100000)
    return sl_fail(err, SL_ERR_FORMAT, "%s: dimension '%s' has an absurd length", f->path, name);
  *len = (int)n;
  return SL_OK;
}

static double attr_double(const nc_file *f, int varid, const char *name, double fallback)
{
  double v;
  size_t len;
  if (nc_inq_attlen(f->id, varid, name, &len) != NC_NOERR || len < 1) return fallback;
  if (len == 1 && nc_get_att_double(f->id, varid, name, &v) == NC_NOERR) return v;
  return fallback;
}

/* Reads variable `name` at time t with the expected trailing dimension names, unpacking
 * scale_factor/add_offset; values equal to _FillValue/missing_value become NaN. */
static int read_time_slice(const nc_file *f, const char *name, int t, int ndims, const char *const dims[],
                           const int lens[], double *out, sl_error *err)
{
  int varid, nd, dimids[NC_MAX_VAR_DIMS];
  if (nc_inq_varid(f->id, name, &varid) != NC_NOERR)
    return sl_fail(err, SL_ERR_FORMAT, "%s: missing variable '%s'", f->path, name);
  nc_check(nc_inq_varndims(f->id, varid, &nd), f, name, err);
  /* Time-varying variables lead with Time; some writers store static fields (HGT, XLAT, XLONG
   * in cropped or processed files) without it, which holds for every time. */
  const int has_time = nd == ndims + 1;
  if (!has_time && nd != ndims)
    return sl_fail(err, SL_ERR_FORMAT, "%s: variable '%s' has %d dimensions, expected %d", f->path, name, nd,
                   ndims + 1);
  nc_inq_vardimid(f->id, varid, dimids);
  size_t start[NC_MAX_VAR_DIMS] = {0}, count[NC_MAX_VAR_DIMS];
  const int off = has_time ? 1 : 0;
  if (has_time) {
    start[0] = (size_t)t;
    count[0] = 1;
  }
  size_t total = 1;
  for (int d = 0; d < ndims; ++d) {
    char dname[NC_MAX_NAME + 1];
    size_t dlen;
    nc_inq_dim(f->id, dimids[d + off], dname, &dlen);
    if (strcmp(dname, dims[d]) != 0 || (int)dlen != lens[d])
      return sl_fail(err, SL_ERR_FORMAT, "%s: variable '%s' dimension %d is %s=%zu, expected %s=%d", f->path, name,
                     d + 1 + off, dname, dlen, dims[d], lens[d]);
    start[d + off] = 0;
    count[d + off] = dlen;
    total *= dlen;
  }
  int status = nc_get_vara_double(f->id, varid, start, count, out);
  if (status != NC_NOERR)
    return sl_fail(err, SL_ERR_FORMAT, "%s: cannot read '%s' at time %d: %s", f->path, name, t, nc_strerror(status));
  const double fill = attr_double(f, varid, "_FillValue", NAN);
  const double missing = attr_double(f, varid, "missing_value", NAN);
  const double scale = attr_double(f, varid, "scale_factor", 1.0);
  const double offset = attr_double(f, varid, "add_offset", 0.0);
  for (size_t i = 0; i < total; ++i) {
    double v = out[i];
    if (v == fill || v == missing) v = NAN;
    out[i] = v * scale + offset;
  }
  return SL_OK;
}

static int file_open(const char *path, nc_file *f, sl_error *err)
{
  f->path = path;
  f->id = -1;
  int status = nc_open(path, NC_NOWRITE, &f->id);
  if (status == NC_NOERR) return SL_OK;
  if (status == NC_ENOTNC || status == NC_EHDFERR)
    return sl_fail(err, SL_ERR_FORMAT, "%s: not a NetCDF file (or truncated)", path);
  return sl_fail(err, SL_ERR_IO, "%s: cannot open: %s", path, nc_strerror(status));
}

/* Without Times: XTIME (minutes since a date in its units, else since START_DATE /
 * SIMULATION_START_DATE). Leaves has_times 0 when neither is usable (index-only). */
static void times_from_xtime(const nc_file *f, sl_storm_info *info)
{
  int vid;
  if (nc_inq_varid(f->id, "XTIME", &vid) != NC_NOERR) return;
  char units[256] = "";
  size_t len = 0;
  if (nc_inq_attlen(f->id, vid, "units", &len) == NC_NOERR && len < sizeof units)
    nc_get_att_text(f->id, vid, "units", units), units[len] = '\0';
  struct tm tm = {0};
  const char *since = strstr(units, "since ");
  int ok = 0;
  if (since && sscanf(since + 6, "%d-%d-%d%*[ _T]%d:%d:%d", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour,
                      &tm.tm_min, &tm.tm_sec) == 6)
    ok = 1;
  if (!ok && strncmp(units, "minutes", 7) == 0) {
    char start[64] = "";
    if (nc_inq_attlen(f->id, NC_GLOBAL, "SIMULATION_START_DATE", &len) == NC_NOERR && len < sizeof start)
      nc_get_att_text(f->id, NC_GLOBAL, "SIMULATION_START_DATE", start), start[len] = '\0';
    ok = sscanf(start, "%d-%d-%d_%d:%d:%d", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour, &tm.tm_min,
                &tm.tm_sec) == 6;
  }
  if (!ok || strncmp(units, "minutes", 7) != 0) return;
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  const time_t base = timegm(&tm);
  double *minutes = malloc((size_t)info->ntimes * sizeof(double));
  if (!minutes) return;
  if (nc_get_var_double(f->id, vid, minutes) == NC_NOERR) {
    for (int t = 0; t < info->ntimes; ++t) {
      const time_t at = base + (time_t)llround(minutes[t] * 60.0);
      struct tm u;
      gmtime_r(&at, &u);
      char text[64];
      snprintf(text, sizeof text, "%04d-%02d-%02d_%02d:%02d:%02d", u.tm_year + 1900, u.tm_mon + 1, u.tm_mday,
               u.tm_hour, u.tm_min, u.tm_sec);
      snprintf(info->times[t], sizeof info->times[t], "%.19s", text);
    }
    info->has_times = 1;
  }
  free(minutes);
}

int sl_storm_read_info(const char *path, sl_storm_info *info, sl_error *err)
{
  memset(info, 0, sizeof *info);
  snprintf(info->path, sizeof info->path, "%s", path);
  nc_file f;
  if (file_open(path, &f, err)) return err->code;
  int rc = SL_OK;
  if ((rc = dim_length(&f, "west_east", &info->nx, err)) || (rc = dim_length(&f, "south_north", &info->ny, err)) ||
      (rc = dim_length(&f, "bottom_top", &info->nz, err)) || (rc = dim_length(&f, "Time", &info->ntimes, err)))
    goto done;
  if (info->ntimes > SL_MAX_TIMES) {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: %d times, more than this reader handles (%d)", path, info->ntimes,
                 SL_MAX_TIMES);
    goto done;
  }
  nc_inq_format(f.id, &info->format);
  info->dx = attr_double(&f, NC_GLOBAL, "DX", NAN);
  info->dy = attr_double(&f, NC_GLOBAL, "DY", NAN);
  if (!(info->dx > 0.0 && info->dx < 1e6) || !(info->dy > 0.0 && info->dy < 1e6)) {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: missing or absurd grid spacing attributes DX/DY", path);
    goto done;
  }
  info->map_proj = (int)attr_double(&f, NC_GLOBAL, "MAP_PROJ", 0);
  info->truelat1 = attr_double(&f, NC_GLOBAL, "TRUELAT1", NAN);
  info->truelat2 = attr_double(&f, NC_GLOBAL, "TRUELAT2", NAN);
  info->stand_lon = attr_double(&f, NC_GLOBAL, "STAND_LON", NAN);
  info->pole_lat = attr_double(&f, NC_GLOBAL, "POLE_LAT", 90.0);
  info->pole_lon = attr_double(&f, NC_GLOBAL, "POLE_LON", 0.0);
  info->mp_physics = (int)attr_double(&f, NC_GLOBAL, "MP_PHYSICS", -1);

  /* Times(Time, <string dim>): the string dimension's name varies between writers. */
  int tid;
  if (nc_inq_varid(f.id, "Times", &tid) == NC_NOERR) {
    int nd, dimids[NC_MAX_VAR_DIMS];
    nc_type type;
    nc_inq_vartype(f.id, tid, &type);
    nc_inq_varndims(f.id, tid, &nd);
    nc_inq_vardimid(f.id, tid, dimids);
    size_t slen = 0;
    if (type == NC_CHAR && nd == 2) nc_inq_dimlen(f.id, dimids[1], &slen);
    if (slen > 0 && slen < 64) {
      char *buf = calloc((size_t)info->ntimes, slen);
      if (buf && nc_get_var_text(f.id, tid, buf) == NC_NOERR) {
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
  if (!info->has_times) times_from_xtime(&f, info);
done:
  nc_close(f.id);
  return rc;
}

/* Which WRF variable feeds which particle type. Simple-ice WSM3 (MP_PHYSICS 3) puts cloud ice
 * in QCLOUD and snow in QRAIN below 0 C; the split happens per cell in sl_storm_load. */
static const char *const FIELD_VARIABLE[SL_PARTICLE_COUNT] = {"QCLOUD", "QRAIN", "QICE", "QSNOW"};

typedef struct column_grid {
  int nx, ny, nz;
  double *z_stag;   /* (nz+1) x ny x nx interface heights */
  double *z_mass;   /* nz x ny x nx */
  double *hgt;      /* ny x nx */
} column_grid;

/* Conservative remap of one column: model layer l spans the interfaces [zs_l, zs_{l+1}] with
 * the constant number concentration values[l]; output cell [z0, z0 + dz] gets the
 * overlap-weighted mean, so the column's particle path (sum of eta times thickness), and with
 * it the water path, is the model's exactly wherever the output spans the model column. */
static double column_mean(const double *values, const double *zs, int nz, size_t stride, double z0, double dz)
{
  const double z1 = z0 + dz;
  double sum = 0.0;
  for (int l = 0; l < nz; ++l) {
    const double a = zs[(size_t)l * stride], b = zs[(size_t)(l + 1) * stride];
    if (b <= z0) continue;
    if (a >= z1) break;
    const double overlap = (b < z1 ? b : z1) - (a > z0 ? a : z0);
    if (overlap > 0.0) sum += values[(size_t)l * stride] * overlap;
  }
  return sum / dz;
}

static int all_finite(const nc_file *f, const char *name, int t, const double *v, size_t n, sl_error *err)
{
  for (size_t i = 0; i < n; ++i)
    if (!isfinite(v[i]))
      return sl_fail(err, SL_ERR_DATA, "%s: variable '%s' has NaN, Inf or missing values at time %d", f->path,
                     name, t);
  return SL_OK;
}

int sl_storm_load(const char *path, const sl_load_options *opt, sl_storm_frame *frame, sl_error *err)
{
  memset(frame, 0, sizeof *frame);
  sl_storm_info *info = malloc(sizeof *info);
  if (!info) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
  int rc = sl_storm_read_info(path, info, err);
  if (rc) {
    free(info);
    return rc;
  }
  const int t = opt ? opt->time_index : 0;
  const int nx = info->nx, ny = info->ny, nz = info->nz;
  if (t < 0 || t >= info->ntimes) {
    rc = sl_fail(err, SL_ERR_ARG, "%s: time index %d out of range (the file has %d times)", path, t, info->ntimes);
    free(info);
    return rc;
  }
  nc_file f;
  if ((rc = file_open(path, &f, err))) {
    free(info);
    return rc;
  }
  const size_t n2 = (size_t)nx * ny, n3 = n2 * nz, n3s = n2 * (nz + 1);
  double *p = malloc(n3 * sizeof(double)), *pb = malloc(n3 * sizeof(double));
  double *theta = malloc(n3 * sizeof(double)), *qv = malloc(n3 * sizeof(double));
  double *ph = malloc(n3s * sizeof(double)), *phb = malloc(n3s * sizeof(double));
  double *hgt = malloc(n2 * sizeof(double));
  double *lat = malloc(n2 * sizeof(double)), *lon = malloc(n2 * sizeof(double));
  double *rho = malloc(n3 * sizeof(double)), *temp = malloc(n3 * sizeof(double));
  double *q = malloc(n3 * sizeof(double));
  double *drop = NULL; /* per column, m: the sphere's depth below the world's tangent plane */
  double *eta_native[SL_PARTICLE_COUNT] = {0};
  if (!p || !pb || !theta || !qv || !ph || !phb || !hgt || !lat || !lon || !rho || !temp || !q) {
    rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory for a %dx%dx%d grid", path, nx, ny, nz);
    goto done;
  }
  const char *const d3[] = {"bottom_top", "south_north", "west_east"};
  const char *const d3s[] = {"bottom_top_stag", "south_north", "west_east"};
  const char *const d2[] = {"south_north", "west_east"};
  const int l3[] = {nz, ny, nx}, l3s[] = {nz + 1, ny, nx}, l2[] = {ny, nx};
  struct {
    const char *name;
    double *buf;
    int nd;
    const char *const *dims;
    const int *lens;
    size_t n;
  } state[] = {{"P", p, 3, d3, l3, n3},      {"PB", pb, 3, d3, l3, n3},     {"T", theta, 3, d3, l3, n3},
               {"QVAPOR", qv, 3, d3, l3, n3}, {"PH", ph, 3, d3s, l3s, n3s}, {"PHB", phb, 3, d3s, l3s, n3s},
               {"HGT", hgt, 2, d2, l2, n2},   {"XLAT", lat, 2, d2, l2, n2},  {"XLONG", lon, 2, d2, l2, n2}};
  for (size_t s = 0; s < sizeof state / sizeof state[0]; ++s) {
    if ((rc = read_time_slice(&f, state[s].name, t, state[s].nd, state[s].dims, state[s].lens, state[s].buf, err)))
      goto done;
    if ((rc = all_finite(&f, state[s].name, t, state[s].buf, state[s].n, err))) goto done;
  }
  /* Geopotential to height on the layer interfaces. */
  for (size_t i = 0; i < n3s; ++i) ph[i] = (ph[i] + phb[i]) / WRF_G;
  for (size_t i = 0; i < n3; ++i) {
    const double pressure = p[i] + pb[i];
    const double qvap = qv[i] > 0.0 ? qv[i] : 0.0;
    if (!(pressure > 0.0)) {
      rc = sl_fail(err, SL_ERR_DATA, "%s: non-positive pressure P+PB at time %d", path, t);
      goto done;
    }
    temp[i] = sl_temperature_from_wrf(theta[i], pressure);
    rho[i] = sl_dry_air_density(pressure, temp[i], qvap);
  }
  for (size_t k = 0; k + 1 <= (size_t)nz; ++k)
    for (size_t c = 0; c < n2; ++c)
      if (!(ph[(k + 1) * n2 + c] > ph[k * n2 + c])) {
        rc = sl_fail(err, SL_ERR_DATA, "%s: geopotential heights (PH+PHB)/g do not increase upward at time %d", path,
                     t);
        goto done;
      }

  /* Mixing ratios to number concentration on the model grid, with WSM3's split by temperature. */
  int any_field = 0;
  const int simple_ice = info->mp_physics == 3;
  for (int pt = 0; pt < SL_PARTICLE_COUNT; ++pt) {
    int varid;
    if (nc_inq_varid(f.id, FIELD_VARIABLE[pt], &varid) != NC_NOERR) continue;
    if ((rc = read_time_slice(&f, FIELD_VARIABLE[pt], t, 3, d3, l3, q, err))) goto done;
    if ((rc = all_finite(&f, FIELD_VARIABLE[pt], t, q, n3, err))) goto done;
    sl_field_stats *st = &frame->stats[pt];
    st->present = 1;
    st->q_min = INFINITY;
    st->q_max = -INFINITY;
    double sum = 0.0;
    for (size_t i = 0; i < n3; ++i) {
      if (q[i] < st->q_min) st->q_min = q[i];
      if (q[i] > st->q_max) st->q_max = q[i];
      if (q[i] < 0.0) {
        st->negative_count++;
        q[i] = 0.0;
      }
      if (q[i] > 0.1) {
        rc = sl_fail(err, SL_ERR_DATA, "%s: %s = %g kg/kg at time %d is not a physical mixing ratio", path,
                     FIELD_VARIABLE[pt], q[i], t);
        goto done;
      }
      sum += q[i];
    }
    st->q_mean = sum / (double)n3;
    any_field = 1;
    /* A simple-ice scheme's liquid names hold ice below freezing. */
    sl_particle warm = (sl_particle)pt, cold = (sl_particle)pt;
    if (simple_ice && pt == SL_CLOUD) cold = SL_ICE;
    if (simple_ice && pt == SL_RAIN) cold = SL_SNOW;
    for (int which = 0; which < 2; ++which) {
      const sl_particle target = which ? cold : warm;
      if (which && cold == warm) break;
      if (!eta_native[target]) {
        eta_native[target] = calloc(n3, sizeof(double));
        if (!eta_native[target]) {
          rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
          goto done;
        }
      }
      const double mass = sl_particle_mass(target);
      for (size_t i = 0; i < n3; ++i) {
        const int frozen = temp[i] < WRF_FREEZE;
        if (cold != warm && frozen != which) continue;
        eta_native[target][i] += sl_number_concentration(rho[i], q[i], mass);
      }
    }
  }
  if (!any_field) {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: no hydrometeor variables (QCLOUD, QRAIN, QICE, QSNOW)", path);
    goto done;
  }

  /* Georeferencing (io/georef.c): this time's XLAT/XLONG place the grid, so a moving nest sits
   * where it was; the projection from the attributes is checked against them. */
  if ((rc = sl_georef_build(&frame->georef, info->map_proj, info->truelat1, info->truelat2, info->stand_lon,
                            info->pole_lat, info->pole_lon, nx, ny, info->dx, info->dy, lat, lon, path, err)))
    goto done;
  if (opt && opt->has_origin) sl_georef_place(&frame->georef, opt->origin_lat, opt->origin_lon);
  const sl_georef *geo = &frame->georef;

  /* The uniform grid: horizontal samples at the model's mass points, spaced by the ground distance
   * between them at the centre (DX over the map factor) and centred on the grid centre's ENU
   * position; vertical from the lowest ground (less the largest curvature drop) to the model top. */
  double ground = INFINITY, top = -INFINITY, hmax = -INFINITY;
  for (size_t c = 0; c < n2; ++c) {
    if (hgt[c] < ground) ground = hgt[c];
    if (hgt[c] > hmax) hmax = hgt[c];
    if (ph[(size_t)nz * n2 + c] > top) top = ph[(size_t)nz * n2 + c];
  }
  double dz = opt && opt->dz > 0.0 ? opt->dz : (top - ground) / (2.0 * nz);
  const double spacing_h[2] = {geo->ground_dx, geo->ground_dy};
  const double corner_xy[2] = {geo->center_enu[0] - 0.5 * (nx - 1) * spacing_h[0],
                               geo->center_enu[1] - 0.5 * (ny - 1) * spacing_h[1]};
  double max_drop = 0.0;
  if (opt && opt->earth_curvature) {
    if (!(drop = malloc(n2 * sizeof(double)))) {
      rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
      goto done;
    }
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double d = sl_curvature_drop(hypot(corner_xy[0] + i * spacing_h[0], corner_xy[1] + j * spacing_h[1]));
        drop[(size_t)j * nx + i] = d;
        if (d > max_drop) max_drop = d;
      }
  }
  int nzo = (int)ceil((top - ground + max_drop) / dz);
  if (nzo < 1) nzo = 1;
  if (nzo > 4096) {
    rc = sl_fail(err, SL_ERR_ARG, "%s: vertical spacing %g m gives %d levels, more than 4096", path, dz, nzo);
    goto done;
  }
  const double origin[3] = {corner_xy[0], corner_xy[1], ground - max_drop + 0.5 * dz};
  const double spacing[3] = {spacing_h[0], spacing_h[1], dz};
  if ((rc = sl_volume_init(&frame->volume, nx, ny, nzo, origin, spacing, err))) goto done;
  for (int pt = 0; pt < SL_PARTICLE_COUNT; ++pt) {
    if (!eta_native[pt]) continue;
    if ((rc = sl_volume_add_field(&frame->volume, (sl_particle)pt, err))) goto done;
    float *out = frame->volume.eta[pt];
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const size_t c = (size_t)j * nx + i;
        for (int k = 0; k < nzo; ++k)
          out[sl_volume_index(&frame->volume, i, j, k)] =
              (float)column_mean(eta_native[pt] + c, ph + c, nz, n2,
                                 ground - max_drop + (drop ? drop[c] : 0.0) + k * dz, dz);
      }
  }
  frame->center_lat = geo->center_lat;
  frame->center_lon = geo->center_lon;
  frame->terrain_min = ground;
  frame->terrain_max = hmax;
  frame->model_top = top;
  frame->time_index = t;
done:
  if (rc) sl_volume_free(&frame->volume);
  nc_close(f.id);
  for (int pt = 0; pt < SL_PARTICLE_COUNT; ++pt) free(eta_native[pt]);
  free(p);
  free(pb);
  free(theta);
  free(qv);
  free(ph);
  free(phb);
  free(hgt);
  free(lat);
  free(lon);
  free(rho);
  free(temp);
  free(q);
  free(drop);
  free(info);
  return rc;
}

void sl_storm_frame_free(sl_storm_frame *frame) { sl_volume_free(&frame->volume); }
