/* The vertical resampling conserves each column's water path (computed here straight from the
 * file's variables with the equation of state, independently of the reader), and WSM3's split by
 * temperature sends exactly the file's below-freezing QCLOUD and QRAIN mass to ice and snow.
 * The data README's "about 5 % of QCLOUD and 23 % of QRAIN mass below 0 C" is the mass-weighted
 * fraction (rho_d q dz, summed over the domain) at the file's first time, 12 UTC: 4.92 % and
 * 22.92 %. Pooled over the four times it is 3.98 % and 20.1 %; q dz without density gives 6.0 % and
 * 28.1 % at 12 UTC; the hydrostatic layer mass q dp/g gives 5.10 % and 23.75 % (rounds to 24). The
 * file has no MU/MUB/DNW, so WRF's own dry column mass cannot be formed. */
#include <math.h>
#include <netcdf.h>
#include <stdlib.h>
#include <string.h>

#include "sl_storm.h"
#include "sl_testing.h"

static double *read_var(int nc, const char *name, int t, size_t n)
{
  int id;
  if (nc_inq_varid(nc, name, &id) != NC_NOERR) return NULL;
  int nd;
  nc_inq_varndims(nc, id, &nd);
  size_t start[4] = {(size_t)t, 0, 0, 0}, count[4] = {1, 0, 0, 0};
  int dims[4];
  nc_inq_vardimid(nc, id, dims);
  for (int d = 1; d < nd; ++d) nc_inq_dimlen(nc, dims[d], &count[d]);
  double *v = malloc(n * sizeof(double));
  nc_get_vara_double(nc, id, start, count, v);
  return v;
}

/* Water path (kg/m2) of variable q in every column, from the file: sum of rho_d q dz with
 * rho_d = p / (R_d T (1 + qv R_v / R_d)), T = (T' + 300)(p / 1e5)^(2/7), dz from (PH+PHB)/g. */
static double *model_paths_cold(const char *path, const char *q, int t, int *nx, int *ny, int cold_only)
{
  int nc, d;
  size_t len;
  nc_open(path, NC_NOWRITE, &nc);
  nc_inq_dimid(nc, "west_east", &d), nc_inq_dimlen(nc, d, &len), *nx = (int)len;
  nc_inq_dimid(nc, "south_north", &d), nc_inq_dimlen(nc, d, &len), *ny = (int)len;
  nc_inq_dimid(nc, "bottom_top", &d), nc_inq_dimlen(nc, d, &len);
  const int nz = (int)len;
  const size_t n2 = (size_t)*nx * *ny, n3 = n2 * nz;
  double *p = read_var(nc, "P", t, n3), *pb = read_var(nc, "PB", t, n3), *th = read_var(nc, "T", t, n3);
  double *qv = read_var(nc, "QVAPOR", t, n3), *qq = read_var(nc, q, t, n3);
  double *ph = read_var(nc, "PH", t, n3 + n2), *phb = read_var(nc, "PHB", t, n3 + n2);
  double *w = calloc(n2, sizeof(double));
  for (int k = 0; k < nz; ++k)
    for (size_t c = 0; c < n2; ++c) {
      const size_t i = k * n2 + c;
      const double pres = p[i] + pb[i], temp = (th[i] + 300.0) * pow(pres / 1e5, 2.0 / 7.0);
      const double rho = pres / (287.0 * temp * (1.0 + fmax(qv[i], 0.0) * 461.6 / 287.0));
      const double dz = ((ph[i + n2] + phb[i + n2]) - (ph[i] + phb[i])) / 9.81;
      if (cold_only && !(temp < 273.15)) continue;
      w[c] += rho * fmax(qq[i], 0.0) * dz;
    }
  free(p), free(pb), free(th), free(qv), free(qq), free(ph), free(phb);
  nc_close(nc);
  return w;
}

static double *model_paths(const char *path, const char *q, int t, int *nx, int *ny)
{
  return model_paths_cold(path, q, t, nx, ny, 0);
}

/* Water path in every column of the uniform grid for the particle types fed by one variable. */
static double grid_path(const sl_volume *v, const sl_particle *types, int ntypes, int i, int j)
{
  double w = 0.0;
  for (int t = 0; t < ntypes; ++t) {
    if (!v->eta[types[t]]) continue;
    const double m = sl_particle_mass(types[t]);
    for (int k = 0; k < v->nz; ++k) w += v->eta[types[t]][sl_volume_index(v, i, j, k)] * m * v->spacing[2];
  }
  return w;
}

static void check_paths(const char *path, int t, const char *var, const sl_particle *types, int ntypes)
{
  int nx, ny;
  double *w = model_paths(path, var, t, &nx, &ny);
  sl_storm_frame f;
  /* The remap conserves what it deposits: with representative particles that is the mass (sized
   * species deposit extinction, whose path test_reader_species compares across subsets). */
  sl_load_options lo = {.time_index = t, .representative_particles = 1};
  sl_error err = {0};
  if (!CHECK(sl_storm_load(path, &lo, &f, &err) == SL_OK)) {
    fprintf(stderr, "%s\n", err.message);
    free(w);
    return;
  }
  double wmax = 0.0, worst = 0.0, total_model = 0.0, total_grid = 0.0;
  for (size_t c = 0; c < (size_t)nx * ny; ++c) wmax = fmax(wmax, w[c]);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double model = w[(size_t)j * nx + i], grid = grid_path(&f.volume, types, ntypes, i, j);
      total_model += model, total_grid += grid;
      if (model > 1e-3 * wmax) worst = fmax(worst, fabs(grid - model) / model);
    }
  printf("%s time %d %s: largest column %.4g kg/m2, worst column error %.2e, domain %.6g vs %.6g\n", path, t, var, wmax,
         worst, total_grid, total_model);
  CHECK_MSG(worst < 0.01, "column water path conserved within 1 %");
  sl_storm_frame_free(&f);
  free(w);
}

int main(void)
{
  const char *shared = getenv("SL_SHARED_DIR"), *datasets = getenv("SL_DATASETS_DIR");
  char katrina[4096], cb[4096];
  snprintf(katrina, sizeof katrina, "%s/data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc", shared ? shared : "../shared");
  snprintf(cb, sizeof cb, "%s/cumulonimbus.nc", datasets ? datasets : "datasets");
  const sl_particle cloud[2] = {SL_CLOUD, SL_ICE}, rain[2] = {SL_RAIN, SL_SNOW};
  const sl_particle only_cloud[1] = {SL_CLOUD}, only_rain[1] = {SL_RAIN};
  check_paths(cb, 0, "QCLOUD", only_cloud, 1);
  check_paths(cb, 0, "QRAIN", only_rain, 1);
  for (int t = 0; t < 4; ++t) {
    check_paths(katrina, t, "QCLOUD", cloud, 2);
    check_paths(katrina, t, "QRAIN", rain, 2);
  }
  /* WSM3: the grid's ice and snow against the file's below-freezing mass, over the four times. */
  double ice0_pct = NAN, snow0_pct = NAN;
  double ice = 0, liquid = 0, snow = 0, rainm = 0, cold_cloud = 0, all_cloud = 0, cold_rain = 0, all_rain = 0;
  for (int t = 0; t < 4; ++t) {
    int nx, ny;
    double *wc = model_paths_cold(katrina, "QCLOUD", t, &nx, &ny, 1), *wa = model_paths(katrina, "QCLOUD", t, &nx, &ny);
    double *rc = model_paths_cold(katrina, "QRAIN", t, &nx, &ny, 1), *ra = model_paths(katrina, "QRAIN", t, &nx, &ny);
    for (size_t c = 0; c < (size_t)nx * ny; ++c) cold_cloud += wc[c], all_cloud += wa[c], cold_rain += rc[c], all_rain += ra[c];
    free(wc), free(wa), free(rc), free(ra);
    sl_storm_frame f;
    sl_load_options lo = {.time_index = t, .representative_particles = 1};
    sl_error err = {0};
    if (sl_storm_load(katrina, &lo, &f, &err)) continue;
    for (int j = 0; j < f.volume.ny; ++j)
      for (int i = 0; i < f.volume.nx; ++i) {
        const sl_particle c1[1] = {SL_CLOUD}, c2[1] = {SL_ICE}, r1[1] = {SL_RAIN}, r2[1] = {SL_SNOW};
        liquid += grid_path(&f.volume, c1, 1, i, j);
        ice += grid_path(&f.volume, c2, 1, i, j);
        rainm += grid_path(&f.volume, r1, 1, i, j);
        snow += grid_path(&f.volume, r2, 1, i, j);
      }
    sl_storm_frame_free(&f);
    if (t == 0) ice0_pct = 100.0 * ice / (ice + liquid), snow0_pct = 100.0 * snow / (snow + rainm);
  }
  const double ice_pct = 100.0 * ice / (ice + liquid), snow_pct = 100.0 * snow / (snow + rainm);
  printf("Katrina WSM3 at 12 UTC: %.2f %% of QCLOUD mass is ice, %.2f %% of QRAIN is snow (README: 5 %%, 23 %%)\n",
         ice0_pct, snow0_pct);
  CHECK_CLOSE(round(ice0_pct), 5.0, 0.0, 0.0);
  CHECK_CLOSE(round(snow0_pct), 23.0, 0.0, 0.0);
  printf("Katrina WSM3: %.2f %% of QCLOUD mass is ice (file: %.2f %% below 0 C), %.2f %% of QRAIN is snow (file: %.2f %%)\n",
         ice_pct, 100.0 * cold_cloud / all_cloud, snow_pct, 100.0 * cold_rain / all_rain);
  CHECK_CLOSE(ice_pct, 100.0 * cold_cloud / all_cloud, 1e-4, 0.0);
  CHECK_CLOSE(snow_pct, 100.0 * cold_rain / all_rain, 1e-4, 0.0);
  return sl_test_finish("test_water_path");
}
