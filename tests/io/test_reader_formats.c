/* The same storm in every NetCDF format gives the same frame: Katrina copied by nccopy -k into
 * netCDF-3 classic, 64-bit offset, CDF5 and netCDF-4 classic model is loaded bit for bit like the
 * original; a copy whose hydrometeors are packed into shorts (scale_factor/add_offset, one of them
 * negative, with a _FillValue) loads to packing precision. */
#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sl_storm.h"
#include "sl_testing.h"

#define NTIMES 4

/* Largest |a - b| over all fields and cells of two frames on the same grid (INFINITY if not). */
static double frame_diff(const sl_storm_frame *a, const sl_storm_frame *b, sl_particle p)
{
  const sl_volume *u = &a->volume, *v = &b->volume;
  if (u->nx != v->nx || u->ny != v->ny || u->nz != v->nz || !u->eta[p] != !v->eta[p]) return INFINITY;
  if (!u->eta[p]) return 0.0;
  double worst = 0.0;
  for (size_t i = 0; i < sl_volume_count(u); ++i) worst = fmax(worst, fabs((double)u->eta[p][i] - v->eta[p][i]));
  return worst;
}

/* Copies `in` to `out` (netCDF-4) with QCLOUD and QRAIN packed into shorts: QCLOUD with a negative
 * scale factor. Returns each packed variable's |scale| (the quantisation step, kg/kg). */
static int write_packed(const char *in, const char *out, double step[2])
{
  int a, b, nd, nv, ng, unlim;
  if (nc_open(in, NC_NOWRITE, &a) || nc_create(out, NC_CLOBBER | NC_NETCDF4, &b)) return 1;
  nc_inq(a, &nd, &nv, &ng, &unlim);
  for (int d = 0; d < nd; ++d) {
    char name[NC_MAX_NAME + 1];
    size_t len;
    int id;
    nc_inq_dim(a, d, name, &len);
    nc_def_dim(b, name, d == unlim ? NC_UNLIMITED : len, &id);
  }
  for (int g = 0; g < ng; ++g) {
    char name[NC_MAX_NAME + 1];
    nc_inq_attname(a, NC_GLOBAL, g, name);
    nc_copy_att(a, NC_GLOBAL, name, b, NC_GLOBAL);
  }
  const char *packed[2] = {"QCLOUD", "QRAIN"};
  double scale[2], offset[2];
  for (int v = 0; v < nv; ++v) {
    char name[NC_MAX_NAME + 1];
    nc_type type;
    int vd, dims[NC_MAX_VAR_DIMS], natts, id;
    nc_inq_var(a, v, name, &type, &vd, dims, &natts);
    int which = -1;
    for (int i = 0; i < 2; ++i)
      if (strcmp(name, packed[i]) == 0) which = i;
    nc_def_var(b, name, which >= 0 ? NC_SHORT : type, vd, dims, &id);
    for (int t = 0; t < natts; ++t) {
      char an[NC_MAX_NAME + 1];
      nc_inq_attname(a, v, t, an);
      nc_copy_att(a, v, an, b, id);
    }
    if (which < 0) continue;
    size_t n = 1, len;
    for (int d = 0; d < vd; ++d) nc_inq_dimlen(a, dims[d], &len), n *= len;
    float *x = malloc(n * sizeof(float));
    nc_get_var_float(a, v, x);
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < n; ++i) lo = fmin(lo, x[i]), hi = fmax(hi, x[i]);
    free(x);
    scale[which] = (hi - lo) / 65000.0 * (which == 0 ? -1.0 : 1.0);
    offset[which] = 0.5 * (hi + lo);
    const short fill = -32768;
    nc_put_att_double(b, id, "scale_factor", NC_DOUBLE, 1, &scale[which]);
    nc_put_att_double(b, id, "add_offset", NC_DOUBLE, 1, &offset[which]);
    nc_def_var_fill(b, id, 0, &fill);
    step[which] = fabs(scale[which]);
  }
  nc_enddef(b);
  for (int v = 0; v < nv; ++v) {
    char name[NC_MAX_NAME + 1];
    nc_type type;
    int vd, dims[NC_MAX_VAR_DIMS], natts;
    nc_inq_var(a, v, name, &type, &vd, dims, &natts);
    size_t n = 1, len;
    for (int d = 0; d < vd; ++d) nc_inq_dimlen(a, dims[d], &len), n *= len;
    int which = -1;
    for (int i = 0; i < 2; ++i)
      if (strcmp(name, packed[i]) == 0) which = i;
    if (type == NC_CHAR) {
      char *c = malloc(n);
      nc_get_var_text(a, v, c), nc_put_var_text(b, v, c);
      free(c);
    } else if (which >= 0) {
      double *x = malloc(n * sizeof(double));
      short *s = malloc(n * sizeof(short));
      nc_get_var_double(a, v, x);
      for (size_t i = 0; i < n; ++i) s[i] = (short)lround((x[i] - offset[which]) / scale[which]);
      nc_put_var_short(b, v, s);
      free(x), free(s);
    } else {
      double *x = malloc(n * sizeof(double));
      nc_get_var_double(a, v, x), nc_put_var_double(b, v, x);
      free(x);
    }
  }
  nc_close(a);
  return nc_close(b);
}

/* Representative particles: eta is then linear in q, which the packing bound below assumes (WSM3's
 * sizes make rain's extinction go as q^(3/4)). */
static int load_time(const char *path, int t, sl_storm_frame *f)
{
  sl_load_options o = {.time_index = t, .representative_particles = 1};
  sl_error err = {0};
  const int rc = sl_storm_load(path, &o, f, &err);
  if (!CHECK(rc == SL_OK)) fprintf(stderr, "%s\n", err.message);
  return rc;
}

int main(void)
{
  const char *shared = getenv("SL_SHARED_DIR");
  char katrina[4096], dir[] = "/tmp/sl_test_formats_XXXXXX", cmd[16384], copy[4200];
  snprintf(katrina, sizeof katrina, "%s/data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc", shared ? shared : "../shared");
  if (!mkdtemp(dir)) return 1;
  static sl_storm_frame original[NTIMES];
  sl_error err = {0};
  for (int t = 0; t < NTIMES; ++t)
    if (load_time(katrina, t, &original[t])) return sl_test_finish("test_reader_formats");
  const struct {
    const char *kind, *name;
    int format;
  } kinds[] = {{"classic", "netCDF-3 classic", NC_FORMAT_CLASSIC},
               {"64-bit offset", "netCDF-3 64-bit offset", NC_FORMAT_64BIT_OFFSET},
               {"cdf5", "netCDF-3 CDF5", NC_FORMAT_CDF5},
               {"netCDF-4 classic model", "netCDF-4 classic model", NC_FORMAT_NETCDF4_CLASSIC}};
  for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k) {
    snprintf(copy, sizeof copy, "%s/copy%zu.nc", dir, k);
    snprintf(cmd, sizeof cmd, "nccopy -k '%s' '%s' '%s'", kinds[k].kind, katrina, copy);
    if (!CHECK_MSG(system(cmd) == 0, kinds[k].kind)) continue;
    sl_storm_info *info = malloc(sizeof *info);
    CHECK(sl_storm_read_info(copy, info, &err) == SL_OK && info->format == kinds[k].format);
    free(info);
    double worst = 0.0;
    for (int t = 0; t < NTIMES; ++t) {
      sl_storm_frame f;
      if (load_time(copy, t, &f)) break;
      for (int p = 0; p < SL_PARTICLE_COUNT; ++p) worst = fmax(worst, frame_diff(&f, &original[t], (sl_particle)p));
      sl_storm_frame_free(&f);
    }
    printf("%-24s largest difference from the netCDF-4 original over %d times: %g\n", kinds[k].name, NTIMES, worst);
    CHECK_MSG(worst == 0.0, kinds[k].name);
    if (kinds[k].format == NC_FORMAT_NETCDF4_CLASSIC) continue;
    /* One byte short: netCDF-C would read the missing byte as zero; the reader refuses the file. */
    char cut[4300];
    snprintf(cut, sizeof cut, "%s.cut", copy);
    snprintf(cmd, sizeof cmd, "head -c $(( $(stat -c %%s '%s') - 1 )) '%s' > '%s'", copy, copy, cut);
    if (CHECK(system(cmd) == 0)) {
      sl_storm_frame f;
      sl_load_options o = {0};
      sl_error_clear(&err);
      CHECK_MSG(sl_storm_load(cut, &o, &f, &err) == SL_ERR_FORMAT && strstr(err.message, "truncated"),
                "a netCDF-3 file one byte short is refused");
    }
  }

  /* Packed shorts: each model value is off by at most half a step; the conservative remap's
   * weights per output cell sum to at most 1, so eta is off by at most rho_d step / 2 / m with
   * rho_d below 1.25 kg/m3 (sea-level air at 0 C is 1.29; the Gulf in August is warmer). */
  snprintf(copy, sizeof copy, "%s/packed.nc", dir);
  double step[2];
  if (CHECK(write_packed(katrina, copy, step) == 0)) {
    const sl_particle from_cloud[2] = {SL_CLOUD, SL_ICE}, from_rain[2] = {SL_RAIN, SL_SNOW};
    double worst_ratio = 0.0;
    for (int t = 0; t < NTIMES; ++t) {
      sl_storm_frame f;
      if (load_time(copy, t, &f)) break;
      for (int i = 0; i < 2; ++i) {
        const sl_particle pc = from_cloud[i], pr = from_rain[i];
        const double bc = 1.25 * step[0] / 2 / sl_particle_mass(pc), br = 1.25 * step[1] / 2 / sl_particle_mass(pr);
        worst_ratio = fmax(worst_ratio, frame_diff(&f, &original[t], pc) / bc);
        worst_ratio = fmax(worst_ratio, frame_diff(&f, &original[t], pr) / br);
      }
      sl_storm_frame_free(&f);
    }
    printf("packed shorts (steps %.3g and %.3g kg/kg): largest difference %.3f of the packing bound\n", step[0], step[1],
           worst_ratio);
    CHECK(worst_ratio > 0.0 && worst_ratio <= 1.0);
  }
  for (int t = 0; t < NTIMES; ++t) sl_storm_frame_free(&original[t]);
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
  return sl_test_finish("test_reader_formats");
}
