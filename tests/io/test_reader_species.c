/* Microphysics species, air density and the CF/CM1 readers on tiny files written from CDL by
 * ncgen, whose values are chosen here so that the expected concentrations follow by hand; and
 * the subset options and the series API on the real Katrina file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "homogeneous_reference.h"
#include "sl_optics.h"
#include "sl_series.h"
#include "sl_storm.h"
#include "ncgen_file.h"
#include "sl_testing.h"
#include "column_path.h"

static char dir[] = "/tmp/sl_test_species_XXXXXX";

/* Writes CDL text to NAME.cdl and NAME.nc (netCDF-4) and returns the .nc path. */
static const char *make(const char *name, const char *cdl)
{
  static char nc[8][512];
  static int which;
  char *out = nc[which++ % 8];
  sl_test_ncgen(dir, name, cdl, out, sizeof nc[0]);
  return out;
}

/* One model layer from 0 to 1000 m over 2x2 columns at two times: p = 85000 Pa, theta = 300 K +
 * theta_pert, qv = 0.01; `decl` and `data` add the hydrometeors (8 values each). */
static const char *wrf(const char *name, int mp, double theta_pert, const char *times, const char *decl,
                       const char *data)
{
  char cdl[8192];
  const double t = theta_pert;
  snprintf(cdl, sizeof cdl,
           "netcdf %s {\n dimensions: Time = UNLIMITED ; DateStrLen = 19 ; west_east = 2 ; south_north = 2 ;"
           " bottom_top = 1 ; bottom_top_stag = 2 ;\n variables:\n char Times(Time, DateStrLen) ;\n"
           " float P(Time, bottom_top, south_north, west_east) ; float PB(Time, bottom_top, south_north, west_east) ;\n"
           " float T(Time, bottom_top, south_north, west_east) ; float QVAPOR(Time, bottom_top, south_north, west_east) ;\n"
           " float PH(Time, bottom_top_stag, south_north, west_east) ; float PHB(Time, bottom_top_stag, south_north, west_east) ;\n"
           " float HGT(Time, south_north, west_east) ; float XLAT(Time, south_north, west_east) ;"
           " float XLONG(Time, south_north, west_east) ;\n %s\n"
           " :DX = 1000.f ; :DY = 1000.f ; :MAP_PROJ = 3 ; :MP_PHYSICS = %d ;\n data:\n Times = %s ;\n"
           " P = 5000, 5000, 5000, 5000, 5000, 5000, 5000, 5000 ;\n"
           " PB = 80000, 80000, 80000, 80000, 80000, 80000, 80000, 80000 ;\n"
           " T = %g, %g, %g, %g, %g, %g, %g, %g ; QVAPOR = 0.01, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01 ;\n"
           " PH = 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0 ;\n"
           " PHB = 0, 0, 0, 0, 9810, 9810, 9810, 9810, 0, 0, 0, 0, 9810, 9810, 9810, 9810 ;\n"
           " HGT = 0, 0, 0, 0, 0, 0, 0, 0 ; XLAT = 25, 25, 25.01, 25.01, 25, 25, 25.01, 25.01 ;\n"
           " XLONG = -89, -88.99, -89, -88.99, -89, -88.99, -89, -88.99 ;\n %s\n}\n",
           name, decl, mp, times, t, t, t, t, t, t, t, t, data);
  return make(name, cdl);
}

#define Q3 "(Time, bottom_top, south_north, west_east) ;"
#define TWO_TIMES "\"2005-08-28_12:00:00\", \"2005-08-28_13:00:00\""

/* Dry-air density by hand with textbook constants (Wallace & Hobbs 2006: R_d = 287.05, R_v = 461.5
 * J/(kg K), kappa = 0.2857), independent of the reader's own constants: T = theta (p/p0)^kappa,
 * virtual temperature T_v = T (1 + qv / eps) / (1 + qv), moist density p / (R_d T_v), dry density
 * that over (1 + qv). For p = 85000 Pa, theta = 305 K, qv = 0.01: T = 291.162 K, rho_d = 1.00092. */
static double hand_rho_dry(double p, double theta, double qv)
{
  const double T = theta * pow(p / 1e5, 0.2857), eps = 287.05 / 461.5;
  const double Tv = T * (1.0 + qv / eps) / (1.0 + qv);
  return p / (287.05 * Tv) / (1.0 + qv);
}

static double sphere_mass(double r, double density) { return density * 4.0 / 3.0 * M_PI * r * r * r; }

/* The value of field p in column (i, j) at the bottom output cell (inside the single layer). */
/* Type p's particles at column (i, j), bottom cell, counted with the extinction per mass of p's own
 * tables: a field of tables at effective radius R holds R / r_own times as many for the same
 * extinction (io/size_bins.c), so the fields of p add up as eta_k r_own / R_k. */
static double eta_at(const sl_storm_frame *f, sl_particle p, int i, int j)
{
  const double r_own = sl_particle_properties(p)->effective_radius_m;
  double sum = 0.0;
  for (int k = 0; k < SL_VOLUME_SLOTS; ++k) {
    if (!f->volume.eta[k] || sl_volume_field_type(&f->volume, k) != p) continue;
    const double R = f->volume.effective_radius_m[k] > 0.0 ? f->volume.effective_radius_m[k] : r_own;
    sum += f->volume.eta[k][sl_volume_index(&f->volume, i, j, 0)] * r_own / R;
  }
  return sum;
}

static int load(const char *path, const sl_load_options *opt, sl_storm_frame *f)
{
  sl_error err = {0};
  sl_load_options zero = {0};
  const int rc = sl_storm_load(path, opt ? opt : &zero, f, &err);
  if (rc) fprintf(stderr, "%s\n", err.message);
  return rc;
}

static void test_density_and_single_moment(void)
{
  const double rho = hand_rho_dry(85000.0, 305.0, 0.01);
  CHECK_CLOSE(rho, 1.00092, 2e-5, 0.0);
  CHECK_CLOSE(sl_dry_air_density(85000.0, sl_temperature_from_wrf(5.0, 85000.0), 0.01), rho, 1e-3, 0.0);
  /* Goddard (MP_PHYSICS 7): single moment with no sizes in Stormlight's table. */
  const char *path = wrf("goddard", 7, 5.0, TWO_TIMES, "float QCLOUD" Q3 " float QGRAUP" Q3 " float QHAIL" Q3,
                         "QCLOUD = 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3 ;\n"
                         "QGRAUP = 1e-3, 0, 0, 0, 1e-3, 0, 0, 0 ; QHAIL = 0, 1e-3, 0, 0, 0, 1e-3, 0, 0 ;");
  sl_storm_frame f;
  if (load(path, NULL, &f)) return;
  /* Cloud: eta = rho_d q / m, m of a 10 um water sphere (Riley et al. 2004, Table 2). */
  const double cloud_rho = eta_at(&f, SL_CLOUD, 1, 1) * sphere_mass(10e-6, 1000.0) / 1e-3;
  printf("air density from the loaded cloud: %.6f kg/m3, by hand %.6f (%.3f %%)\n", cloud_rho, rho,
         100.0 * (cloud_rho / rho - 1.0));
  CHECK_CLOSE(cloud_rho, rho, 1e-3, 0.0);
  /* Graupel and hail are their own types (no sizes here): eta = rho_d q / m with the
   * representative spheres, graupel 1 mm at 400 kg/m3, hail 2.5862 mm at 900 kg/m3. */
  CHECK_CLOSE(eta_at(&f, SL_GRAUPEL, 0, 0), rho * 1e-3 / sphere_mass(1e-3, 400.0), 1e-3, 0.0);
  CHECK_CLOSE(eta_at(&f, SL_HAIL, 1, 0), rho * 1e-3 / sphere_mass(2.5862e-3, 900.0), 1e-3, 0.0);
  CHECK(f.volume.eta[SL_SNOW] == NULL);
  CHECK(f.nspecies == 3);
  sl_storm_frame_free(&f);

  /* --field snow=QGRAUP: graupel becomes the snow type itself (snow's particle mass); hail stays
   * hail, QCLOUD unchanged. */
  sl_load_options o = {0};
  o.field_variable[SL_SNOW] = "QGRAUP";
  if (!load(path, &o, &f)) {
    CHECK_CLOSE(eta_at(&f, SL_SNOW, 0, 0), rho * 1e-3 / sphere_mass(1.498e-3, 100.0), 1e-3, 0.0);
    CHECK_CLOSE(eta_at(&f, SL_SNOW, 1, 0), 0.0, 0.0, 0.0);
    CHECK(f.volume.eta[SL_GRAUPEL] == NULL && eta_at(&f, SL_HAIL, 1, 0) > 0.0);
    CHECK(f.nspecies == 3);
    sl_storm_frame_free(&f);
  }
  o.field_variable[SL_SNOW] = "QNOPE";
  sl_error err = {0};
  CHECK(sl_storm_load(path, &o, &f, &err) == SL_ERR_ARG && strstr(err.message, "QNOPE"));
  o.field_variable[SL_SNOW] = NULL;
  o.field_variable[SL_CLOUD] = "none";
  if (!load(path, &o, &f)) {
    CHECK(f.volume.eta[SL_CLOUD] == NULL);
    sl_storm_frame_free(&f);
  }
}

static void test_split_and_double_moment(void)
{
  /* Kessler (warm rain) at theta = 280 K (T = 267 K): its cloud water is drawn as cloud ice. */
  const char *kessler = wrf("kessler", 1, -20.0, TWO_TIMES, "float QCLOUD" Q3,
                            "QCLOUD = 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3 ;");
  sl_storm_frame f;
  if (!load(kessler, NULL, &f)) {
    const double rho = hand_rho_dry(85000.0, 280.0, 0.01);
    CHECK_CLOSE(eta_at(&f, SL_CLOUD, 0, 0), 0.0, 0.0, 0.0);
    CHECK_CLOSE(eta_at(&f, SL_ICE, 0, 0), rho * 1e-3 / sphere_mass(5.382e-4, 917.0), 1e-3, 0.0);
    sl_storm_frame_free(&f);
  }
  /* The same file as WSM6 (MP_PHYSICS 6, which has ice of its own): no split. */
  const char *wsm6 = wrf("nosplit", 6, -20.0, TWO_TIMES, "float QCLOUD" Q3,
                         "QCLOUD = 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3 ;");
  if (!load(wsm6, NULL, &f)) {
    CHECK(f.volume.eta[SL_ICE] == NULL && eta_at(&f, SL_CLOUD, 0, 0) > 0.0);
    sl_storm_frame_free(&f);
  }
  /* Morrison (double moment): rain is exponential in D (mu = 0) at 997 kg/m3, so q / QN fixes the
   * slope, lambda^3 = 997 pi QN / q, and the effective radius 3 / (2 lambda). Against rain's tables
   * (a lognormal of median 1 mm, s = 0.25: r_eff = 1 mm exp(2.5 s^2), water 1000 kg/m3) the cell holds
   * eta = (rho q / m_rain) (1000 r_t) / (997 r_eff) representative drops. Eight times as many drops
   * of the same mass have half the effective radius: twice the extinction. */
  const double m_rain = sphere_mass(1e-3, 1000.0), n1 = 1e-3 / m_rain;
  char data[512];
  snprintf(data, sizeof data, "QRAIN = 1e-3, 1e-3, 0, 0, 1e-3, 1e-3, 0, 0 ; QNRAIN = %.9g, %.9g, 0, 0, %.9g, %.9g, 0, 0 ;",
           n1, 8 * n1, n1, 8 * n1);
  const char *morrison = wrf("morrison", 10, 5.0, TWO_TIMES, "float QRAIN" Q3 " float QNRAIN" Q3, data);
  if (!load(morrison, NULL, &f)) {
    const double rho = sl_dry_air_density(85000.0, sl_temperature_from_wrf(5.0, 85000.0), 0.01);
    const double lambda = cbrt(997.0 * M_PI * (float)n1 / (float)1e-3), r_eff = 1.5 / lambda;
    const double r_t = 1e-3 * exp(2.5 * 0.25 * 0.25);
    CHECK_CLOSE(eta_at(&f, SL_RAIN, 0, 0), rho * (float)1e-3 / m_rain * 1000.0 * r_t / (997.0 * r_eff), 1e-5, 0.0);
    CHECK_CLOSE(eta_at(&f, SL_RAIN, 1, 0), 2.0 * eta_at(&f, SL_RAIN, 0, 0), 1e-5, 0.0);
    CHECK(strcmp(f.species[0].number_variable, "QNRAIN") == 0);
    CHECK_CLOSE(f.species_stats[0].r_eff_max, r_eff, 1e-6, 0.0);
    CHECK_CLOSE(f.species_stats[0].r_eff_min, 0.5 * r_eff, 1e-6, 0.0);
    /* Two radii a factor 2 apart (rain's tables may be 3 apart): two tables, on the 2^(k/8) um
     * lattice, bracketing both cells' radii. */
    CHECK(f.sizes.count[SL_RAIN] == 2 && !f.sizes.limited[SL_RAIN]);
    const double R0 = f.sizes.radius_m[SL_RAIN][0], R1 = f.sizes.radius_m[SL_RAIN][1];
    CHECK(R0 <= 0.5 * r_eff * (1 + 1e-6) && R1 >= r_eff * (1 - 1e-6) && R1 / R0 < 2.0 * pow(2.0, 2.0 / 8.0) + 1e-9);
    CHECK_CLOSE(8.0 * log2(R0 / 1e-6), round(8.0 * log2(R0 / 1e-6)), 0.0, 1e-9);
    sl_storm_frame_free(&f);
  }
  /* One field in all: rain takes one table at its median, and says it asked for more. */
  sl_load_options one = {.max_fields = 1};
  if (!load(morrison, &one, &f)) {
    CHECK(f.sizes.count[SL_RAIN] == 1 && f.sizes.limited[SL_RAIN] && sl_volume_field_count(&f.volume) == 1);
    CHECK_CLOSE(eta_at(&f, SL_RAIN, 1, 0), 2.0 * eta_at(&f, SL_RAIN, 0, 0), 1e-5, 0.0);
    sl_storm_frame_free(&f);
  }
  /* --particles representative: Riley's one particle per type, the number ignored. */
  sl_load_options rep = {0};
  rep.representative_particles = 1;
  if (!load(morrison, &rep, &f)) {
    const double rho = sl_dry_air_density(85000.0, sl_temperature_from_wrf(5.0, 85000.0), 0.01);
    CHECK_CLOSE(eta_at(&f, SL_RAIN, 1, 0), rho * 1e-3 / m_rain, 1e-5, 0.0);
    CHECK(f.species[0].number_variable[0] == '\0');
    sl_storm_frame_free(&f);
  }
  /* Bad numbers: negative (clamped and counted) and zero where q > 0 (counted; the representative
   * particle there, since rain has no fixed number); never NaN. */
  const char *bad = wrf("badnumber", 10, 5.0, TWO_TIMES, "float QRAIN" Q3 " float QNRAIN" Q3,
                        "QRAIN = 1e-3, 1e-3, 0, 0, 1e-3, 1e-3, 0, 0 ; QNRAIN = -5, 0, 7, 0, 1, 1, 1, 1 ;");
  if (!load(bad, NULL, &f)) {
    const double rho = sl_dry_air_density(85000.0, sl_temperature_from_wrf(5.0, 85000.0), 0.01);
    CHECK(f.species_stats[0].number_negative == 1 && f.species_stats[0].number_missing == 2);
    CHECK_CLOSE(eta_at(&f, SL_RAIN, 0, 0), rho * 1e-3 / m_rain, 1e-5, 0.0);
    CHECK(isfinite(eta_at(&f, SL_RAIN, 1, 0)) && eta_at(&f, SL_RAIN, 1, 0) > 0.0);
    sl_storm_frame_free(&f);
  }
  /* A negative mixing ratio: advection noise (-1e-3) clamped and counted; -0.5 kg/kg is no noise
   * but a wrong field, refused naming the variable. */
  const char *noise = wrf("noise", 10, 5.0, TWO_TIMES, "float QRAIN" Q3, "QRAIN = -1e-3, 1e-3, 0, 0, 1e-3, 1e-3, 0, 0 ;");
  if (!load(noise, NULL, &f)) {
    CHECK(f.stats[SL_RAIN].negative_count == 1);
    sl_storm_frame_free(&f);
  }
  const char *wrong = wrf("wrongsign", 10, 5.0, TWO_TIMES, "float QRAIN" Q3, "QRAIN = -0.5, 1e-3, 0, 0, 1e-3, 1e-3, 0, 0 ;");
  sl_error e = {0};
  sl_load_options zero = {0};
  CHECK(sl_storm_load(wrong, &zero, &f, &e) == SL_ERR_DATA && strstr(e.message, "QRAIN = -0.5") &&
        strstr(e.message, "not a physical mixing ratio"));
}

/* Shape rules typed from the schemes' papers, independently of render/core: Morrison et al. 2005
 * after Martin et al. 1994, and Thompson et al. 2008 (N in m^-3). */
static double mu_martin(double n)
{
  const double e = 0.0005714 * n * 1e-6 + 0.2714, mu = 1.0 / (e * e) - 1.0;
  return fmin(10.0, fmax(2.0, mu));
}
static double mu_thompson(double n) { return fmin(15.0, round(1000.0 / (n * 1e-6)) + 2.0); }

/* Effective radius of n(D) = N0 D^mu exp(-lambda D) spheres of density rho holding mass M (kg/m3)
 * in N (m^-3) particles, by Simpson quadrature of I_k = int x^(k+mu) exp(-x) dx (x = lambda D):
 * M / N = rho pi / 6 I3 / (I0 lambda^3) fixes lambda, and r_eff = M3 / (2 M2) = I3 / (2 I2 lambda). */
static double quadrature_reff(double mu, double rho, double M, double N)
{
  double I[4] = {0};
  const int n = 400000;
  const double h = 200.0 / n;
  for (int i = 0; i <= n; ++i) {
    const double x = i * h, w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    for (int k = 0; k < 4; ++k) I[k] += w * pow(x, k + mu) * exp(-x);
  }
  const double lambda = cbrt(rho * M_PI / 6.0 * N * I[3] / (I[0] * M));
  return I[3] / (2.0 * I[2] * lambda);
}

/* The same for a single-moment exponential of fixed intercept N0 (m^-4): M = rho pi / 6 N0 I3 / lambda^4
 * fixes lambda. */
static double quadrature_reff_intercept(double rho, double M, double N0)
{
  double I[4] = {0};
  const int n = 400000;
  const double h = 200.0 / n;
  for (int i = 0; i <= n; ++i) {
    const double x = i * h, w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    for (int k = 0; k < 4; ++k) I[k] += w * pow(x, k) * exp(-x);
  }
  const double lambda = pow(rho * M_PI / 6.0 * N0 * (I[3] * h / 3.0) / M, 0.25);
  return I[3] / (2.0 * I[2] * lambda);
}

/* The renderer's transparency straight down through the middle of a loaded volume: no sun, a sky
 * of 1, the low-albedo model with the tables' (grey) cross-sections. */
static double slab_transparency(const sl_storm_frame *f, const sl_optics_tables *T)
{
  double lo[3], hi[3];
  sl_volume_bounds(&f->volume, lo, hi);
  sl_scene sc = {.volume = &f->volume, .sun_direction = {0.3, 0.2, 0.9}, .slices = 64, .optics = T,
                 .lighting = SL_LIGHTING_LOW_ALBEDO};
  for (int c = 0; c < SL_CHANNELS; ++c) sc.sky_radiance[c] = 1.0;
  const double cx = 0.5 * (lo[0] + hi[0]), cy = 0.5 * (lo[1] + hi[1]);
  sl_camera cam = {.position = {cx, cy, hi[2] + 3000.0}, .target = {cx, cy, lo[2]}, .up = {0, 1, 0}, .fov_deg = 1,
                   .width = 3, .height = 3};
  sl_image img;
  if (render_frame(&sc, &cam, &img)) return NAN;
  const double t = img.rgba[4 * 4];
  sl_image_free(&img);
  return t;
}

/* Sizes from the microphysics (docs/DATA.md, "Sizes"): every scheme's distribution in the table
 * gives a cell's effective radius equal to the gamma moment ratio by quadrature; doubling the
 * droplet number at fixed mass multiplies the cloud's optical depth by 2^(1/3) (Twomey), through the
 * renderer; the same mass of graupel casts a darker shadow than of hail, by the ratio of extinctions
 * their distributions predict. */
static void test_sizes(void)
{
  const double rho = sl_dry_air_density(85000.0, sl_temperature_from_wrf(5.0, 85000.0), 0.01);
  const float q = 1e-3f;
  /* Number per kg of dry air for cloud, rain, ice, snow, graupel, hail. */
  const float qn[6] = {(float)(100e6 / rho), 3e3f, 1e5f, 1e4f, 2e3f, 200.0f};
  const char *vars[6][2] = {{"QCLOUD", "QNCLOUD"}, {"QRAIN", "QNRAIN"},   {"QICE", "QNICE"},
                            {"QSNOW", "QNSNOW"},   {"QGRAUP", "QNGRAUPEL"}, {"QHAIL", "QNHAIL"}};
  /* Per scheme: shape rule (0 fixed mu, 1 Martin, 2 Thompson), mu, density; density 0: not sized. */
  const struct {
    int mp, count;
    double rule[6], mu[6], rho[6];
  } schemes[] = {
      {10, 6, {1, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0}, {997, 997, 500, 100, 400, 900}},  /* Morrison */
      {28, 3, {2, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0}, {1000, 1000, 890, 0, 0, 0}},      /* Thompson */
      {17, 6, {1, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0}, {1000, 1000, 917, 100, 400, 900}}, /* default */
  };
  for (size_t k = 0; k < sizeof schemes / sizeof schemes[0]; ++k) {
    char decl[1024] = "", data[2048] = "", name[32];
    for (int s = 0; s < schemes[k].count; ++s) {
      char d[512];
      snprintf(d, sizeof d, " float %s" Q3 " float %s" Q3, vars[s][0], vars[s][1]);
      strcat(decl, d);
      snprintf(d, sizeof d, " %s = %.9g, %.9g, %.9g, %.9g, %.9g, %.9g, %.9g, %.9g ; %s = %.9g, %.9g, %.9g, %.9g, %.9g, "
               "%.9g, %.9g, %.9g ;\n", vars[s][0], q, q, q, q, q, q, q, q, vars[s][1], qn[s], qn[s], qn[s], qn[s],
               qn[s], qn[s], qn[s], qn[s]);
      strcat(data, d);
    }
    snprintf(name, sizeof name, "sizes%d", schemes[k].mp);
    sl_storm_frame f;
    if (load(wrf(name, schemes[k].mp, 5.0, TWO_TIMES, decl, data), NULL, &f)) continue;
    for (int s = 0; s < f.nspecies; ++s) {
      const int t = f.species[s].warm;
      const double M = rho * q, N = rho * qn[t];
      const double mu = schemes[k].rule[t] == 1 ? mu_martin(N) : schemes[k].rule[t] == 2 ? mu_thompson(N) : schemes[k].mu[t];
      const double want = schemes[k].rho[t] > 0 ? quadrature_reff(mu, schemes[k].rho[t], M, N) : 0.0;
      printf("MP_PHYSICS %d %s: r_eff %.6g m (quadrature %.6g, mu %.3f)\n", schemes[k].mp, vars[t][0],
             f.species_stats[s].r_eff_max, want, mu);
      CHECK_CLOSE(f.species_stats[s].r_eff_max, want, 1e-6, 0.0);
      CHECK_CLOSE(f.species_stats[s].r_eff_min, want, 1e-6, 0.0);
    }
    sl_storm_frame_free(&f);
  }

  /* Single-moment schemes' fixed intercepts: WSM6's rain (8e6 m^-4, 1000 kg/m3) and graupel (4e6,
   * 500), WSM7's hail (4e4, 912), Lin's snow (3e6, 100). */
  const struct {
    int mp;
    const char *var;
    double n0, rho;
  } intercepts[] = {{6, "QRAIN", 8e6, 1000.0}, {6, "QGRAUP", 4e6, 500.0}, {24, "QHAIL", 4e4, 912.0}, {2, "QSNOW", 3e6, 100.0}};
  for (size_t k = 0; k < sizeof intercepts / sizeof intercepts[0]; ++k) {
    char decl[128], data[256], name[32];
    snprintf(decl, sizeof decl, "float %s" Q3, intercepts[k].var);
    snprintf(data, sizeof data, "%s = 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3 ;", intercepts[k].var);
    snprintf(name, sizeof name, "n0_%s_%d", intercepts[k].var, intercepts[k].mp);
    sl_storm_frame f;
    if (load(wrf(name, intercepts[k].mp, 5.0, TWO_TIMES, decl, data), NULL, &f)) continue;
    const double want = quadrature_reff_intercept(intercepts[k].rho, rho * (float)1e-3, intercepts[k].n0);
    printf("MP_PHYSICS %d %s: r_eff %.6g m (quadrature with N0 %g: %.6g)\n", intercepts[k].mp, intercepts[k].var,
           f.species_stats[0].r_eff_max, intercepts[k].n0, want);
    CHECK_CLOSE(f.species_stats[0].r_eff_max, want, 1e-6, 0.0);
    sl_storm_frame_free(&f);
  }

  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.use_cache = 0;
  req.particles = (1u << SL_CLOUD) | (1u << SL_GRAUPEL) | (1u << SL_HAIL);
  req.angle_step_deg = 0.5;
  req.radius_samples = 32;
  sl_error err = {0};
  sl_optics_tables *T = sl_optics_build(&req, &err);
  CHECK_MSG(T != NULL, err.message);
  if (!T) return;
  /* Twomey: Thompson's droplets below 70 cm^-3 keep mu = 15, so at fixed q the effective radius goes
   * as N^(-1/3) and the optical depth, 3 Q / (4 rho r) per unit mass, as N^(1/3) times the ratio of
   * the extinction efficiencies Q of the tables each slab takes (one each: its radius is uniform). */
  double tau[2], q_eff[2] = {NAN, NAN};
  for (int i = 0; i < 2; ++i) {
    char data[512];
    const float n = (float)((i ? 60e6 : 30e6) / rho);
    snprintf(data, sizeof data, "QCLOUD = 1e-5, 1e-5, 1e-5, 1e-5, 1e-5, 1e-5, 1e-5, 1e-5 ; QNCLOUD = %.9g, %.9g, "
             "%.9g, %.9g, %.9g, %.9g, %.9g, %.9g ;", n, n, n, n, n, n, n, n);
    sl_storm_frame f;
    tau[i] = NAN;
    if (load(wrf(i ? "twomey2" : "twomey1", 28, 5.0, TWO_TIMES, "float QCLOUD" Q3 " float QNCLOUD" Q3, data), NULL, &f))
      continue;
    CHECK(f.sizes.count[SL_CLOUD] == 1 && f.volume.effective_radius_m[SL_CLOUD] > 0.0);
    sl_optics_request sized = req;
    sl_optics_request_fields(&sized, &f.volume);
    sl_optics_tables *Ts = sl_optics_build(&sized, &err);
    CHECK_MSG(Ts != NULL, err.message);
    if (Ts) {
      /* Q of the table: sigma_ext = 3 Q m_cloud / (4 rho_w R), the mean over wavelengths as drawn. */
      const double R = f.volume.effective_radius_m[SL_CLOUD];
      double sigma = 0.0;
      for (int w = 0; w < req.n_wavelengths; ++w) sigma += sl_optics_table_sized(Ts, SL_CLOUD, R, w)->sigma_ext / req.n_wavelengths;
      q_eff[i] = sigma * 4.0 * 1000.0 * R / (3.0 * sl_particle_mass(SL_CLOUD));
      tau[i] = -log(slab_transparency(&f, Ts));
      sl_optics_free(Ts);
    }
    sl_storm_frame_free(&f);
  }
  printf("Twomey: optical depth %.5f at 30 cm^-3, %.5f at 60 cm^-3, ratio %.6f; 2^(1/3) Q2 / Q1 = %.6f (Q %.4f, %.4f)\n",
         tau[0], tau[1], tau[1] / tau[0], cbrt(2.0) * q_eff[1] / q_eff[0], q_eff[0], q_eff[1]);
  CHECK_CLOSE(tau[1] / tau[0], cbrt(2.0) * q_eff[1] / q_eff[0], 1e-5, 0.0);
  /* The extinction paradox: droplets of a few micrometres (x near 50) extinguish about twice their area. */
  CHECK(fabs(q_eff[0] - 2.0) < 0.2 && fabs(q_eff[1] - 2.0) < 0.2);
  /* Graupel and hail of the same mass (0.5 g/kg, Morrison's names without numbers: the representative
   * distributions): optical depths in the ratio of Q lambda / (2 rho), (1500 / 400) / (580 / 900). */
  for (int i = 0; i < 2; ++i) {
    char decl[128], data[256];
    const char *v = i ? "QHAIL" : "QGRAUP";
    snprintf(decl, sizeof decl, "float %s" Q3, v);
    snprintf(data, sizeof data, "%s = 5e-4, 5e-4, 5e-4, 5e-4, 5e-4, 5e-4, 5e-4, 5e-4 ;", v);
    sl_storm_frame f;
    tau[i] = NAN;
    if (load(wrf(v, 10, 5.0, TWO_TIMES, decl, data), NULL, &f)) continue;
    tau[i] = -log(slab_transparency(&f, T));
    sl_storm_frame_free(&f);
  }
  printf("shadow: graupel optical depth %.5f, hail %.5f, ratio %.4f (distributions: %.4f)\n", tau[0], tau[1],
         tau[0] / tau[1], (1500.0 / 400.0) / (580.0 / 900.0));
  CHECK(tau[0] > tau[1]);
  CHECK_CLOSE(tau[0] / tau[1], (1500.0 / 400.0) / (580.0 / 900.0), 0.01, 0.0);
  /* And the absolute depth: 2 lambda / (2 rho) m2/kg times rho_d q times the 1000 m layer. */
  CHECK_CLOSE(tau[0], 1500.0 / 400.0 * rho * 5e-4 * 1000.0, 0.01, 0.0);
  sl_optics_free(T);
}

/* The same synthetic two-moment storm written with CM1's names (ptype 5) and with WRF's (Morrison,
 * MP_PHYSICS 10): the readers must fill the same volume, numbers and sizes included. */
static void test_cm1_wrf_numbers(void)
{
  const char *q4 = "1e-3, 2e-4, 0, 5e-5", *n_rain = "1000, 30000, 0, 10", *n_ice = "1e5, 2e6, 0, 3e4";
  const char *n_snow = "1e4, 1e3, 0, 50", *n_graupel = "2000, 10, 0, 1";
  char data[4096];
  snprintf(data, sizeof data,
           " qc = %s ; qr = %s ; qi = %s ; qs = %s ; qg = %s ;\n ncr = %s ; nci = %s ; ncs = %s ; ncg = %s ;\n", q4, q4,
           q4, q4, q4, n_rain, n_ice, n_snow, n_graupel);
  char cdl[8192];
  snprintf(cdl, sizeof cdl,
           "netcdf cm1n {\n dimensions: ni = 2 ; nj = 2 ; nk = 1 ; nkp1 = 2 ; time = UNLIMITED ;\n"
           " variables: float xh(ni) ; xh:units = \"km\" ; float yh(nj) ; yh:units = \"km\" ;\n"
           " float zh(nk) ; zh:units = \"km\" ; float zf(nkp1) ; zf:units = \"km\" ;"
           " float time(time) ; time:units = \"seconds\" ;\n"
           " float qc(time, nk, nj, ni) ; float qr(time, nk, nj, ni) ; float qi(time, nk, nj, ni) ;"
           " float qs(time, nk, nj, ni) ; float qg(time, nk, nj, ni) ; float ncr(time, nk, nj, ni) ;"
           " float nci(time, nk, nj, ni) ; float ncs(time, nk, nj, ni) ; float ncg(time, nk, nj, ni) ;\n"
           " float prs(time, nk, nj, ni) ; float th(time, nk, nj, ni) ; float qv(time, nk, nj, ni) ;\n"
           " :ptype = 5 ;\n data:\n xh = -0.5, 0.5 ; yh = -0.5, 0.5 ; zh = 0.5 ; zf = 0, 1 ; time = 0 ;\n%s"
           " prs = 85000, 85000, 85000, 85000 ; th = 305, 305, 305, 305 ; qv = 0.01, 0.01, 0.01, 0.01 ;\n}\n",
           data);
  const char *cm1 = make("cm1numbers", cdl);
  snprintf(data, sizeof data,
           " QCLOUD = %s, %s ; QRAIN = %s, %s ; QICE = %s, %s ; QSNOW = %s, %s ; QGRAUP = %s, %s ;\n"
           " QNRAIN = %s, %s ; QNICE = %s, %s ; QNSNOW = %s, %s ; QNGRAUPEL = %s, %s ;\n",
           q4, q4, q4, q4, q4, q4, q4, q4, q4, q4, n_rain, n_rain, n_ice, n_ice, n_snow, n_snow, n_graupel, n_graupel);
  const char *wrf_file = wrf("wrfnumbers", 10, 5.0, TWO_TIMES,
                             "float QCLOUD" Q3 " float QRAIN" Q3 " float QICE" Q3 " float QSNOW" Q3 " float QGRAUP" Q3
                             " float QNRAIN" Q3 " float QNICE" Q3 " float QNSNOW" Q3 " float QNGRAUPEL" Q3,
                             data);
  sl_storm_frame a, b;
  if (load(cm1, NULL, &a)) return;
  if (load(wrf_file, NULL, &b)) {
    sl_storm_frame_free(&a);
    return;
  }
  CHECK(a.volume.nx == b.volume.nx && a.volume.ny == b.volume.ny && a.volume.nz == b.volume.nz);
  CHECK(a.nspecies == 5 && b.nspecies == 5);
  for (int s = 0; s < a.nspecies && s < b.nspecies; ++s) {
    CHECK(a.species[s].warm == b.species[s].warm);
    CHECK((a.species[s].number_variable[0] != 0) == (b.species[s].number_variable[0] != 0));
    CHECK_CLOSE(a.species_stats[s].r_eff_max, b.species_stats[s].r_eff_max, 1e-6, 0.0);
  }
  double worst = 0.0;
  int compared = 0;
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p) {
    CHECK((a.volume.eta[p] == NULL) == (b.volume.eta[p] == NULL));
    if (!a.volume.eta[p] || !b.volume.eta[p]) continue;
    for (size_t i = 0; i < sl_volume_count(&a.volume); ++i) {
      const double x = a.volume.eta[p][i], y = b.volume.eta[p][i];
      if (x != 0.0 || y != 0.0) worst = fmax(worst, fabs(x - y) / fmax(fabs(x), fabs(y))), ++compared;
    }
  }
  printf("CM1 and WRF names, same two-moment storm: %d cells compared, worst relative difference %.2g\n", compared,
         worst);
  CHECK(compared > 10);
  CHECK(worst < 1e-5);
  sl_storm_frame_free(&a);
  sl_storm_frame_free(&b);
}

static void test_cm1_and_cf(void)
{
  /* CM1: coordinates in km, zf interfaces, mixing ratios with prs and th. */
  const char *cm1 = make("cm1",
                         "netcdf cm1 {\n dimensions: ni = 3 ; nj = 2 ; nk = 2 ; nkp1 = 3 ; time = UNLIMITED ;\n"
                         " variables: float xh(ni) ; xh:units = \"km\" ; float yh(nj) ; yh:units = \"km\" ;\n"
                         " float zh(nk) ; zh:units = \"km\" ; float zf(nkp1) ; zf:units = \"km\" ;"
                         " float time(time) ; time:units = \"seconds\" ;\n"
                         " float qc(time, nk, nj, ni) ; float qg(time, nk, nj, ni) ; float prs(time, nk, nj, ni) ;"
                         " float th(time, nk, nj, ni) ; float qv(time, nk, nj, ni) ;\n data:\n"
                         " xh = 0.25, 0.75, 1.25 ; yh = 0.25, 0.75 ; zh = 0.25, 0.75 ; zf = 0, 0.5, 1 ; time = 0 ;\n"
                         " qc = 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 0, 0, 0, 0, 0, 0 ;\n"
                         " qg = 0, 0, 0, 0, 0, 0, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3 ;\n"
                         " prs = 85000, 85000, 85000, 85000, 85000, 85000, 85000, 85000, 85000, 85000, 85000, 85000 ;\n"
                         " th = 305, 305, 305, 305, 305, 305, 305, 305, 305, 305, 305, 305 ;\n"
                         " qv = 0.01, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01, 0.01 ;\n}\n");
  sl_storm_info *info = malloc(sizeof *info);
  sl_error err = {0};
  if (CHECK(sl_storm_read_info(cm1, info, &err) == SL_OK)) {
    CHECK(info->kind == SL_STORM_CM1 && info->nx == 3 && info->ny == 2 && info->nz == 2 && info->nspecies == 2);
    CHECK_CLOSE(info->dx, 500.0, 1e-9, 0.0);
  } else {
    fprintf(stderr, "%s\n", err.message);
  }
  sl_storm_frame f;
  if (!load(cm1, NULL, &f)) {
    const double rho = hand_rho_dry(85000.0, 305.0, 0.01);
    /* Bottom layer 0..500 m: cloud; top layer 500..1000 m: graupel (no ptype: no sizes, the
     * representative 1 mm sphere of 400 kg/m3). Default dz = 250 m. */
    CHECK_CLOSE(f.volume.spacing[2], 250.0, 1e-9, 0.0);
    CHECK_CLOSE(eta_at(&f, SL_CLOUD, 2, 1), rho * 1e-3 / sphere_mass(10e-6, 1000.0), 1e-3, 0.0);
    CHECK_CLOSE(f.volume.eta[SL_GRAUPEL][sl_volume_index(&f.volume, 2, 1, 3)], rho * 1e-3 / sphere_mass(1e-3, 400.0),
                1e-3, 0.0);
    CHECK_CLOSE(f.volume.eta[SL_GRAUPEL][sl_volume_index(&f.volume, 2, 1, 1)], 0.0, 0.0, 0.0);
    sl_storm_frame_free(&f);
  }
  /* Generic CF: standard names, a Lambert grid_mapping, mass fractions per kg of moist air, a time
   * coordinate with units. */
  const char *cf_text =
      "netcdf cf {\n dimensions: time = 1 ; z = 1 ; y = 2 ; x = 2 ;\n variables:\n"
      " double time(time) ; time:units = \"hours since 2024-06-15 00:00:00\" ;\n"
      " float z(z) ; z:units = \"m\" ; z:positive = \"up\" ; float y(y) ; y:units = \"km\" ;"
      " y:standard_name = \"projection_y_coordinate\" ; float x(x) ; x:units = \"km\" ;"
      " x:standard_name = \"projection_x_coordinate\" ;\n int lcc ; lcc:grid_mapping_name = \"%s\" ;"
      " lcc:standard_parallel = 30., 60. ; lcc:longitude_of_central_meridian = -97. ;\n"
      " float cl(time, z, y, x) ; cl:standard_name = \"mass_fraction_of_cloud_liquid_water_in_air\" ;"
      " cl:grid_mapping = \"lcc\" ;\n float ta(time, z, y, x) ; ta:standard_name = \"air_temperature\" ;\n"
      " float pa(time, z, y, x) ; pa:standard_name = \"air_pressure\" ;\n"
      " float hus(time, z, y, x) ; hus:standard_name = \"specific_humidity\" ;\n data:\n"
      " time = 22 ; z = 500 ; y = 0, 3 ; x = 0, 3 ; lcc = 0 ; cl = 1e-3, 1e-3, 1e-3, 1e-3 ;\n"
      " ta = 291.162, 291.162, 291.162, 291.162 ; pa = 85000, 85000, 85000, 85000 ; hus = 0.01, 0.01, 0.01, 0.01 ;\n}\n";
  char text[4096];
  snprintf(text, sizeof text, cf_text, "lambert_conformal_conic");
  const char *cf = make("cf", text);
  if (CHECK(sl_storm_read_info(cf, info, &err) == SL_OK)) {
    CHECK(info->kind == SL_STORM_CF && info->map_proj == 1 && info->has_times);
    CHECK(strcmp(info->times[0], "2024-06-15_22:00:00") == 0);
    CHECK_CLOSE(info->truelat2, 60.0, 0.0, 0.0);
    CHECK_CLOSE(info->dx, 3000.0, 1e-9, 0.0);
  } else {
    fprintf(stderr, "%s\n", err.message);
  }
  if (!load(cf, NULL, &f)) {
    /* Moist density p / (R_d T_v) with the specific humidity (textbook constants): the mass
     * fraction is per kg of moist air. */
    const double eps = 287.05 / 461.5, tv = 291.162 * (1.0 + 0.01 * (1.0 / eps - 1.0));
    CHECK_CLOSE(eta_at(&f, SL_CLOUD, 1, 1), 85000.0 / (287.05 * tv) * 1e-3 / sphere_mass(10e-6, 1000.0), 1e-3, 0.0);
    CHECK_CLOSE(f.model_top, 1000.0, 1e-9, 0.0); /* one level at 500 m: interfaces 0 and 1000 */
    sl_storm_frame_free(&f);
  }
  /* The same air and cloud in the units people write: g/kg, degrees Celsius, hPa. Read as SI they
   * made a cloud 1000x too dense in air 100x too thin; converted, the same densities as above. */
  const char *cf_units =
      "netcdf cfu {\n dimensions: time = 1 ; z = 1 ; y = 2 ; x = 2 ;\n variables:\n"
      " double time(time) ; time:units = \"hours since 2024-06-15 00:00:00\" ;\n"
      " float z(z) ; z:units = \"m\" ; z:positive = \"up\" ; float y(y) ; y:units = \"km\" ;"
      " float x(x) ; x:units = \"km\" ;\n"
      " float cl(time, z, y, x) ; cl:standard_name = \"mass_fraction_of_cloud_liquid_water_in_air\" ;"
      " cl:units = \"g kg-1\" ;\n float ta(time, z, y, x) ; ta:standard_name = \"air_temperature\" ;"
      " ta:units = \"%s\" ;\n float pa(time, z, y, x) ; pa:standard_name = \"air_pressure\" ; pa:units = \"hPa\" ;\n"
      " float hus(time, z, y, x) ; hus:standard_name = \"specific_humidity\" ; hus:units = \"kg/kg\" ;\n data:\n"
      " time = 22 ; z = 500 ; y = 0, 3 ; x = 0, 3 ; cl = 1, 1, 1, 1 ;\n"
      " ta = 18.012, 18.012, 18.012, 18.012 ; pa = 850, 850, 850, 850 ; hus = 0.01, 0.01, 0.01, 0.01 ;\n}\n";
  snprintf(text, sizeof text, cf_units, "degC");
  const char *cfu = make("cfu", text);
  if (!load(cfu, NULL, &f)) {
    const double eps = 287.05 / 461.5, tv = 291.162 * (1.0 + 0.01 * (1.0 / eps - 1.0));
    CHECK_CLOSE(eta_at(&f, SL_CLOUD, 1, 1), 85000.0 / (287.05 * tv) * 1e-3 / sphere_mass(10e-6, 1000.0), 1e-3, 0.0);
    sl_storm_frame_free(&f);
  }
  snprintf(text, sizeof text, cf_units, "degF");
  const char *cff = make("cff", text);
  sl_error_clear(&err);
  CHECK(sl_storm_load(cff, NULL, &f, &err) == SL_ERR_FORMAT && strstr(err.message, "'ta'") &&
        strstr(err.message, "degF"));
  printf("%s\n", err.message);
  /* A projected grid without 2-D latitudes is placed by its grid_mapping's origin: a tangent
   * cone at 30 N whose centre column sits at the false easting (on the central meridian) and
   * 111.177 km north of the origin: one degree of meridian on WRF's sphere (R = 6370 km), where
   * a tangent cone's scale is 1 to second order (error ~ (111/6370)^2 deg). */
  const char *cf_origin =
      "netcdf cfo {\n dimensions: time = 1 ; z = 1 ; y = 3 ; x = 3 ;\n variables:\n"
      " double time(time) ; time:units = \"hours since 2024-06-15 00:00:00\" ;\n"
      " float z(z) ; z:units = \"m\" ; z:positive = \"up\" ; float y(y) ; y:units = \"km\" ;"
      " y:standard_name = \"projection_y_coordinate\" ; float x(x) ; x:units = \"km\" ;"
      " x:standard_name = \"projection_x_coordinate\" ;\n int lcc ; lcc:grid_mapping_name = \"lambert_conformal_conic\" ;"
      " lcc:standard_parallel = 30. ; lcc:longitude_of_central_meridian = -97. ; lcc:latitude_of_projection_origin = 30. ;"
      " lcc:false_easting = 400. ;\n"
      " float cl(time, z, y, x) ; cl:standard_name = \"mass_fraction_of_cloud_liquid_water_in_air\" ; cl:grid_mapping = \"lcc\" ;\n"
      " float ta(time, z, y, x) ; ta:standard_name = \"air_temperature\" ;\n"
      " float pa(time, z, y, x) ; pa:standard_name = \"air_pressure\" ;\n data:\n"
      " time = 22 ; z = 500 ; y = 108.177, 111.177, 114.177 ; x = 397, 400, 403 ; lcc = 0 ; cl = 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4 ;\n"
      " ta = 291, 291, 291, 291, 291, 291, 291, 291, 291 ; pa = 85000, 85000, 85000, 85000, 85000, 85000, 85000, 85000, 85000 ;\n}\n";
  const char *cfo = make("cfo", cf_origin);
  if (!load(cfo, NULL, &f)) {
    printf("projected CF centre: %.5f N %.5f E (expected 31, -97)\n", f.center_lat, f.center_lon);
    CHECK_CLOSE(f.center_lat, 31.0, 0.0, 0.01);
    CHECK_CLOSE(f.center_lon, -97.0, 0.0, 1e-9);
    sl_storm_frame_free(&f);
  }
  /* Air at 0 K (or below) has no density; heights of 5000 km are metres labelled km. Both are
   * refused, naming the problem (read as it stands, 0 K would give a negative cloud concentration). */
  const char *cf_bad =
      "netcdf cfb {\n dimensions: z = 2 ; y = 2 ; x = 2 ;\n variables:\n"
      " float z(z) ; z:units = \"%s\" ; float y(y) ; y:units = \"km\" ; float x(x) ; x:units = \"km\" ;\n"
      " float cl(z, y, x) ; cl:standard_name = \"mass_fraction_of_cloud_liquid_water_in_air\" ;\n"
      " float ta(z, y, x) ; ta:standard_name = \"air_temperature\" ;\n"
      " float pa(z, y, x) ; pa:standard_name = \"air_pressure\" ;\n data:\n"
      " z = 250, 750 ; y = 0, 3 ; x = 0, 3 ; cl = 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4 ;\n"
      " ta = %s ; pa = 85000, 85000, 85000, 85000, 85000, 85000, 85000, 85000 ;\n}\n";
  snprintf(text, sizeof text, cf_bad, "m", "290, 290, 290, 0, 290, 290, 290, 290");
  const char *cold = make("cold", text);
  sl_error_clear(&err);
  CHECK(sl_storm_load(cold, NULL, &f, &err) == SL_ERR_DATA && strstr(err.message, "non-positive air temperature"));
  printf("%s\n", err.message);
  snprintf(text, sizeof text, cf_bad, "km", "290, 290, 290, 290, 290, 290, 290, 290");
  const char *tall = make("tall", text);
  sl_error_clear(&err);
  CHECK(sl_storm_load(tall, NULL, &f, &err) == SL_ERR_DATA && strstr(err.message, "not an atmosphere"));
  printf("%s\n", err.message);
  /* A square grid stored (z, x, y): by position alone x and y would swap without a word; the
   * coordinates say which axis they are, and the load refuses. */
  const char *cf_swapped =
      "netcdf cfs {\n dimensions: z = 1 ; y = 2 ; x = 2 ;\n variables:\n"
      " float z(z) ; z:units = \"m\" ; float y(y) ; y:units = \"km\" ; y:axis = \"Y\" ;"
      " float x(x) ; x:units = \"km\" ; x:standard_name = \"projection_x_coordinate\" ;\n"
      " float cl(z, x, y) ; cl:standard_name = \"mass_fraction_of_cloud_liquid_water_in_air\" ;\n"
      " float ta(z, x, y) ; ta:standard_name = \"air_temperature\" ;\n"
      " float pa(z, x, y) ; pa:standard_name = \"air_pressure\" ;\n data:\n"
      " z = 500 ; y = 0, 3 ; x = 0, 3 ; cl = 1e-4, 0, 0, 0 ; ta = 290, 290, 290, 290 ;"
      " pa = 85000, 85000, 85000, 85000 ;\n}\n";
  const char *swapped = make("swapped", cf_swapped);
  sl_error_clear(&err);
  CHECK(sl_storm_read_info(swapped, info, &err) == SL_ERR_FORMAT && strstr(err.message, "expected (time,) z, y, x"));
  printf("%s\n", err.message);
  snprintf(text, sizeof text, cf_text, "geostationary");
  const char *geos = make("geos", text);
  sl_error_clear(&err);
  CHECK(sl_storm_read_info(geos, info, &err) == SL_ERR_FORMAT && strstr(err.message, "unsupported projection"));
  free(info);
}

static void test_subsets(const char *katrina)
{
  sl_storm_frame full, sub;
  if (!CHECK(load(katrina, NULL, &full) == 0)) return;  /* the shared data beside the checkout */
  /* Stride 2: every other column, each column's water path unchanged (the vertical remap is per
   * column and conservative). */
  sl_load_options o = {.stride = 2};
  if (!load(katrina, &o, &sub)) {
    CHECK(sub.volume.nx == 24 && sub.volume.ny == 24);
    /* Every other column: twice the whole grid's spacing (ground distance, DX over the map factor). */
    CHECK_CLOSE(sub.volume.spacing[0], 2.0 * full.volume.spacing[0], 1e-12, 0.0);
    double worst = 0.0;
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i) {
        const double a = sl_test_column_path(&sub, i, j), b = sl_test_column_path(&full, 2 * i, 2 * j);
        if (b > 1e-3) worst = fmax(worst, fabs(a - b) / b);
      }
    printf("stride 2: worst column water path difference %.2e\n", worst);
    CHECK(worst < 1e-4);
    sl_storm_frame_free(&sub);
  }
  /* Region: one degree around the centre; the subset is smaller and centred inside it. */
  sl_load_options r = {.has_region = 1,
                       .region = {full.center_lat - 1, full.center_lat + 1, full.center_lon - 1, full.center_lon + 1}};
  if (!load(katrina, &r, &sub)) {
    CHECK(sub.volume.nx < 48 && sub.volume.nx >= 15 && sub.volume.ny < 48);
    CHECK(fabs(sub.center_lat - full.center_lat) < 0.2 && fabs(sub.center_lon - full.center_lon) < 0.2);
    sl_storm_frame_free(&sub);
  }
  /* Levels 0..6 of 14: a lower top, never more water than the whole column. */
  sl_load_options l = {.level_first = 0, .level_count = 7};
  if (!load(katrina, &l, &sub)) {
    CHECK(sub.model_top < 0.7 * full.model_top);
    CHECK(sl_test_column_path(&sub, 24, 24) <= sl_test_column_path(&full, 24, 24) * (1 + 1e-6));
    sl_storm_frame_free(&sub);
  }
  /* A limit below the estimate: refused before reading, naming the way out. */
  sl_load_options m = {.max_memory = 1e5};
  sl_error err = {0};
  CHECK(sl_storm_load(katrina, &m, &sub, &err) == SL_ERR_NOMEM && strstr(err.message, "--region") &&
        strstr(err.message, "--stride"));
  printf("%s\n", err.message);
  sl_storm_frame_free(&full);
}

static void test_series(void)
{
  /* One file per time, given out of order, plus a glob: frames come back in time order. */
  const char *a = wrf("series_b", 6, 5.0, "\"2005-08-28_14:00:00\", \"2005-08-28_15:00:00\"", "float QCLOUD" Q3,
                      "QCLOUD = 0, 0, 0, 0, 0, 0, 0, 0 ;");
  const char *b = wrf("series_a", 6, 5.0, TWO_TIMES, "float QCLOUD" Q3, "QCLOUD = 0, 0, 0, 0, 0, 0, 0, 0 ;");
  const char *list[2] = {a, b};
  sl_series s;
  sl_error err = {0};
  if (CHECK(sl_series_open(list, 2, &s, &err) == SL_OK)) {
    CHECK(s.count == 4 && s.has_times);
    CHECK(strcmp(s.frames[0].time, "2005-08-28_12:00:00") == 0 && strcmp(s.frames[0].path, b) == 0);
    CHECK(strcmp(s.frames[3].time, "2005-08-28_15:00:00") == 0 && s.frames[3].time_index == 1);
    sl_series_free(&s);
  }
  char pattern[600];
  snprintf(pattern, sizeof pattern, "%s/series_*.nc", dir);
  const char *glob_list[1] = {pattern};
  if (CHECK(sl_series_open(glob_list, 1, &s, &err) == SL_OK)) {
    CHECK(s.count == 4 && s.npaths == 2);
    sl_series_free(&s);
  }
  const char *twice[2] = {b, b};
  sl_error_clear(&err);
  CHECK(sl_series_open(twice, 2, &s, &err) == SL_ERR_DATA && strstr(err.message, "appears twice"));
  snprintf(pattern, sizeof pattern, "%s/nothing_*.nc", dir);
  sl_error_clear(&err);
  CHECK(sl_series_open(glob_list, 1, &s, &err) == SL_ERR_IO);

  /* CM1: seconds since the start, no date. Files given out of order (and a name order that is not
   * the time order) come back in the order of their seconds; info keeps the seconds. */
  const char *cm1_times[3] = {"1200", "600", "3600"};
  const char *cm1_files[3];
  for (int i = 0; i < 3; ++i) {
    char cdl[2048], name[32];
    snprintf(cdl, sizeof cdl,
             "netcdf cm1t {\n dimensions: ni = 2 ; nj = 2 ; nk = 1 ; time = UNLIMITED ;\n"
             " variables: float xh(ni) ; xh:units = \"km\" ; float yh(nj) ; yh:units = \"km\" ; float zh(nk) ;"
             " zh:units = \"km\" ; float time(time) ; time:units = \"seconds\" ;\n"
             " float qc(time, nk, nj, ni) ; float prs(time, nk, nj, ni) ; float th(time, nk, nj, ni) ;\n"
             " :ptype = 5 ;\n data:\n xh = -0.5, 0.5 ; yh = -0.5, 0.5 ; zh = 0.5 ; time = %s ;\n"
             " qc = 0, 1e-4, 0, 0 ; prs = 85000, 85000, 85000, 85000 ; th = 300, 300, 300, 300 ;\n}\n",
             cm1_times[i]);
    snprintf(name, sizeof name, "cm1out_00000%d", i + 1);
    cm1_files[i] = strdup(make(name, cdl));
  }
  sl_error_clear(&err);
  if (CHECK(sl_series_open(cm1_files, 3, &s, &err) == SL_OK)) {
    CHECK(s.count == 3 && !s.has_times && s.has_elapsed);
    CHECK(s.frames[0].elapsed_s == 600.0 && s.frames[1].elapsed_s == 1200.0 && s.frames[2].elapsed_s == 3600.0);
    CHECK(strcmp(s.frames[0].path, cm1_files[1]) == 0 && strcmp(s.frames[2].path, cm1_files[2]) == 0);
    sl_series_free(&s);
  }
  sl_storm_info *info = malloc(sizeof *info);
  if (CHECK(sl_storm_read_info(cm1_files[0], info, &err) == SL_OK)) {
    CHECK(info->has_elapsed && info->elapsed_s[0] == 1200.0 && !info->has_times);
    CHECK(info->cm1_ptype == 5 && strstr(info->scheme, "Morrison"));
  }
  free(info);
  const char *same[2] = {cm1_files[0], cm1_files[0]};
  sl_error_clear(&err);
  CHECK(sl_series_open(same, 2, &s, &err) == SL_ERR_DATA && strstr(err.message, "1200 s appears twice"));
  for (int i = 0; i < 3; ++i) free((void *)cm1_files[i]);
}

/* The same air written with decreasing coordinates loads to the same frame: latitudes from north
 * to south (ERA5, GFS), longitudes from east to west, levels from the top down, each reversed on
 * read. A 5 x 4 x 3 lat-lon grid whose cloud, temperature and pressure differ in every cell, so a
 * reversal forgotten or applied twice moves values; compared bit for bit with the increasing
 * file, and the centre too. Also an odd layout's message: a one-column grid. */
static void cf_grid_cdl(char *out, size_t cap, const char *name, int flip_x, int flip_y, int flip_z, int nx)
{
  enum { NY = 4, NZ = 3 };
  size_t n = 0;
  n += snprintf(out + n, cap - n,
                "netcdf %s {\n dimensions: time = 1 ; z = %d ; y = %d ; x = %d ;\n variables:\n"
                " double time(time) ; time:units = \"hours since 2024-06-15 00:00:00\" ;\n"
                " float z(z) ; z:units = \"m\" ; z:positive = \"up\" ; float y(y) ; y:units = \"degrees_north\" ;"
                " float x(x) ; x:units = \"degrees_east\" ;\n"
                " float cl(time, z, y, x) ; cl:standard_name = \"mass_fraction_of_cloud_liquid_water_in_air\" ;\n"
                " float ta(time, z, y, x) ; ta:standard_name = \"air_temperature\" ;\n"
                " float pa(time, z, y, x) ; pa:standard_name = \"air_pressure\" ;\n data:\n time = 0 ;\n z =",
                name, NZ, NY, nx);
  for (int k = 0; k < NZ; ++k) n += snprintf(out + n, cap - n, "%s %d", k ? "," : "", 250 + 500 * (flip_z ? NZ - 1 - k : k));
  n += snprintf(out + n, cap - n, " ;\n y =");
  for (int j = 0; j < NY; ++j) n += snprintf(out + n, cap - n, "%s %g", j ? "," : "", 35.0 + 0.02 * (flip_y ? NY - 1 - j : j));
  n += snprintf(out + n, cap - n, " ;\n x =");
  for (int i = 0; i < nx; ++i) n += snprintf(out + n, cap - n, "%s %g", i ? "," : "", -97.0 + 0.02 * (flip_x ? nx - 1 - i : i));
  for (int v = 0; v < 3; ++v) {
    n += snprintf(out + n, cap - n, " ;\n %s =", v == 0 ? "cl" : v == 1 ? "ta" : "pa");
    for (int k = 0; k < NZ; ++k)
      for (int j = 0; j < NY; ++j)
        for (int i = 0; i < nx; ++i) {
          /* The value of the physical cell this file position holds. */
          const int pi = flip_x ? nx - 1 - i : i, pj = flip_y ? NY - 1 - j : j, pk = flip_z ? NZ - 1 - k : k;
          const double value = v == 0 ? 1e-4 * (1 + pi + 10 * pj + 100 * pk)
                               : v == 1 ? 290.0 - 3.0 * pk + 0.1 * pi - 0.05 * pj
                                        : 90000.0 - 5000.0 * pk + 10.0 * pi + 3.0 * pj;
          n += snprintf(out + n, cap - n, "%s %.9g", k + j + i ? "," : "", value);
        }
  }
  snprintf(out + n, cap - n, " ;\n}\n");
}

static void test_decreasing_coordinates(void)
{
  static char text[16384];
  static sl_storm_frame ref, got;
  cf_grid_cdl(text, sizeof text, "inc", 0, 0, 0, 5);
  if (!CHECK(load(make("inc", text), NULL, &ref) == SL_OK)) return;
  /* The centre is grid position ((nx - 1) / 2, (ny - 1) / 2): x point 2 of 5, y between points 1
   * and 2 of 4 (35.02 and 35.04), not point 2 half a cell north. */
  char centre[160];
  snprintf(centre, sizeof centre, "lat-lon grid centre %.6f %.6f (want 35.030000 -96.960000)", ref.center_lat,
           ref.center_lon);
  CHECK_MSG(fabs(ref.center_lat - 35.03) < 1e-5 && fabs(ref.center_lon + 96.96) < 1e-5, centre); /* float coordinates */
  const int flips[][3] = {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {1, 1, 1}};
  for (size_t c = 0; c < sizeof flips / sizeof flips[0]; ++c) {
    char name[16];
    snprintf(name, sizeof name, "dec%zu", c);
    cf_grid_cdl(text, sizeof text, name, flips[c][0], flips[c][1], flips[c][2], 5);
    if (!CHECK(load(make(name, text), NULL, &got) == SL_OK)) continue;
    const sl_volume *a = &ref.volume, *b = &got.volume;
    long differ = a->nx != b->nx || a->ny != b->ny || a->nz != b->nz;
    for (int p = 0; !differ && p < SL_PARTICLE_COUNT; ++p) {
      if (!a->eta[p] != !b->eta[p]) differ = 1;
      for (size_t i = 0; a->eta[p] && b->eta[p] && i < sl_volume_count(a); ++i) differ += a->eta[p][i] != b->eta[p][i];
    }
    char what[200];
    snprintf(what, sizeof what,
             "x %s, y %s, z %s: the same frame as increasing coordinates (%ld cells differ; centre %.4f %.4f against "
             "%.4f %.4f)",
             flips[c][0] ? "east to west" : "up", flips[c][1] ? "north to south" : "up", flips[c][2] ? "top down" : "up",
             differ, got.center_lat, got.center_lon, ref.center_lat, ref.center_lon);
    CHECK_MSG(differ == 0 && got.center_lat == ref.center_lat && got.center_lon == ref.center_lon, what);
    sl_storm_frame_free(&got);
  }
  sl_storm_frame_free(&ref);
  /* Degrees where they do not belong: a projection coordinate in degrees (a Lambert grid_mapping
   * was ignored and the grid read as lat-lon), longitudes on the y axis (refused as the X axis). */
  const struct {
    const char *from, *to, *want;
  } wrong[] = {{"x:units = \"degrees_east\" ;", "x:units = \"degrees\" ; x:standard_name = \"projection_x_coordinate\" ;",
                "lengths"},
               {"y:units = \"degrees_north\" ;", "y:units = \"degree_E\" ;", "X axis"}};
  for (int w = 0; w < 2; ++w) {
    cf_grid_cdl(text, sizeof text, "deg", 0, 0, 0, 5);
    char *at = strstr(text, wrong[w].from);
    if (!CHECK(at != NULL)) continue;
    static char edited[16384];
    snprintf(edited, sizeof edited, "%.*s%s%s", (int)(at - text), text, wrong[w].to, at + strlen(wrong[w].from));
    sl_error e = {0};
    static sl_storm_info winfo;
    CHECK_MSG(sl_storm_read_info(make(w ? "deg1" : "deg0", edited), &winfo, &e) != SL_OK && strstr(e.message, wrong[w].want),
              e.message);
  }
  /* One column: named as such, not "must increase". */
  cf_grid_cdl(text, sizeof text, "one", 0, 0, 0, 1);
  sl_error err = {0};
  static sl_storm_info info;
  CHECK_MSG(sl_storm_read_info(make("one", text), &info, &err) != SL_OK && strstr(err.message, "at least 2"),
            err.message);
}

/* A CF time coordinate counts in its calendar: 400 and 401.5 days since 2000-01-01 are
 * 2001-02-05 and 2001-02-06 12:00 in a noleap calendar (2000-01-01 + 400 Gregorian days would be
 * 2001-02-04), 2001-02-11 and 2001-02-12 12:00 in a 360_day one; the sun takes the 360_day dates
 * at the same fraction of the year (day 40 of 360 is day 40.6 of 365: Feb 10). A calendar the
 * reader does not know leaves the times index-only and is named. */
static void test_calendars(void)
{
  const char *cdl =
      "netcdf cal {\n dimensions: time = 2 ; z = 1 ; y = 2 ; x = 2 ;\n variables:\n"
      " double time(time) ; time:units = \"days since 2000-01-01 00:00:00\" ; time:calendar = \"%s\" ;\n"
      " float z(z) ; z:units = \"m\" ; float y(y) ; y:units = \"km\" ; float x(x) ; x:units = \"km\" ;\n"
      " float cl(time, z, y, x) ; cl:standard_name = \"mass_fraction_of_cloud_liquid_water_in_air\" ;\n"
      " float ta(time, z, y, x) ; ta:standard_name = \"air_temperature\" ;\n"
      " float pa(time, z, y, x) ; pa:standard_name = \"air_pressure\" ;\n data:\n"
      " time = 400, 401.5 ; z = 500 ; y = 0, 3 ; x = 0, 3 ; cl = 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3 ;\n"
      " ta = 291, 291, 291, 291, 291, 291, 291, 291 ; pa = 85000, 85000, 85000, 85000, 85000, 85000, 85000, 85000 ;\n}\n";
  const struct {
    const char *calendar, *t0, *t1, *sun0;
  } cases[] = {{"noleap", "2001-02-05_00:00:00", "2001-02-06_12:00:00", "2001-02-05_00:00:00"},
               {"360_day", "2001-02-11_00:00:00", "2001-02-12_12:00:00", "2001-02-10_00:00:00"},
               {"proleptic_gregorian", "2001-02-04_00:00:00", "2001-02-05_12:00:00", "2001-02-04_00:00:00"},
               {"mars_sol", "", "", ""}};
  static sl_storm_info info;
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    char text[2048], name[32];
    snprintf(text, sizeof text, cdl, cases[c].calendar);
    snprintf(name, sizeof name, "cal%zu", c);
    sl_error err = {0};
    if (!CHECK_MSG(sl_storm_read_info(make(name, text), &info, &err) == SL_OK, err.message)) continue;
    char what[300];
    snprintf(what, sizeof what, "calendar %s: times %s %s (sun %s), calendar '%s'; want %s %s (sun %s)", cases[c].calendar,
             info.has_times ? info.times[0] : "-", info.has_times ? info.times[1] : "-",
             info.has_times ? info.sun_times[0] : "-", info.calendar, cases[c].t0[0] ? cases[c].t0 : "index-only",
             cases[c].t1, cases[c].sun0);
    const int want_times = cases[c].t0[0] != 0;
    CHECK_MSG(info.has_times == want_times && strcmp(info.calendar, cases[c].calendar) == 0 &&
                  (!want_times || (strcmp(info.times[0], cases[c].t0) == 0 && strcmp(info.times[1], cases[c].t1) == 0 &&
                                   strcmp(info.sun_times[0], cases[c].sun0) == 0)),
              what);
  }
}

/* A WRF idealized run (MAP_PROJ 0: em_quarter_ss, em_squall2d) has no place on the earth: it
 * loads flat, its columns DX apart (its Mercator twin, placed by XLAT/XLONG 0.01 degrees apart at
 * 25 N, has them 1008 m apart), with the same cells as that twin, no latitudes, and a centre only
 * where --origin gives one; --region (latitudes) is refused. */
static void test_idealized_wrf(void)
{
  const char *merc = wrf("ideal_merc", 4, 5.0, TWO_TIMES, "float QCLOUD" Q3, " QCLOUD = 1e-3, 2e-3, 3e-3, 4e-3, 1e-3, 2e-3, 3e-3, 4e-3 ;");
  char cdl_path[600];
  snprintf(cdl_path, sizeof cdl_path, "%s/ideal_merc.cdl", dir);
  static char text[16384];
  FILE *in = fopen(cdl_path, "r");
  if (!CHECK(in != NULL)) return;
  const size_t n = fread(text, 1, sizeof text - 1, in);
  fclose(in);
  text[n] = 0;
  /* MAP_PROJ 0 and zero latitudes, as ideal.exe writes them. */
  char *at = strstr(text, ":MAP_PROJ = 3");
  char *lat = strstr(text, "XLAT = "), *lon = strstr(text, "XLONG = ");
  if (!CHECK(at && lat && lon)) return;
  at[12] = '0';
  for (char *c = lat + 7; *c != ';'; ++c)
    if (*c != ',' && *c != ' ') *c = *c == '-' ? ' ' : '0';
  for (char *c = lon + 8; *c != ';'; ++c)
    if (*c != ',' && *c != ' ') *c = *c == '-' ? ' ' : '0';
  char *name_end = strstr(text, "ideal_merc");
  if (name_end) memcpy(name_end, "ideal_flat", 10);
  const char *flat = make("ideal_flat", text);
  static sl_storm_frame a, b;
  if (!CHECK(load(merc, NULL, &a) == SL_OK) || !CHECK(load(flat, NULL, &b) == SL_OK)) return;
  long differ = a.volume.nx != b.volume.nx || a.volume.ny != b.volume.ny || a.volume.nz != b.volume.nz;
  for (size_t i = 0; !differ && i < sl_volume_count(&a.volume); ++i)
    differ += a.volume.eta[SL_CLOUD][i] != b.volume.eta[SL_CLOUD][i];
  char what[200];
  snprintf(what, sizeof what, "idealized WRF: spacing %.1f x %.1f m (want 1000), Mercator twin %.1f; %ld cells differ; "
           "centre %g %g, placed %d",
           b.volume.spacing[0], b.volume.spacing[1], a.volume.spacing[0], differ, b.center_lat, b.center_lon,
           b.georef.placed);
  CHECK_MSG(b.volume.spacing[0] == 1000.0 && b.volume.spacing[1] == 1000.0 &&
                differ == 0 && isnan(b.center_lat) && !b.column_lat && !b.georef.placed,
            what);
  sl_storm_frame_free(&b);
  sl_load_options opt = {0};
  opt.has_origin = 1, opt.origin_lat = 35.0, opt.origin_lon = -97.0;
  if (CHECK(load(flat, &opt, &b) == SL_OK))
    CHECK_MSG(b.center_lat == 35.0 && b.center_lon == -97.0, "idealized WRF with --origin: centred there");
  sl_storm_frame_free(&b);
  sl_load_options region = {0};
  region.has_region = 1;
  const double box[4] = {-1, 1, -1, 1};
  memcpy(region.region, box, sizeof box);
  sl_error err = {0};
  CHECK_MSG(sl_storm_load(flat, &region, &b, &err) != SL_OK && strstr(err.message, "MAP_PROJ 0"), err.message);
  sl_storm_frame_free(&a);
}

/* Water vapour past any humidity the air can hold (15 "kg/kg": g/kg mislabelled) or far below
 * zero is refused naming it; a little below zero is advection noise and loads. */
static void test_vapour_bounds(void)
{
  const char *cdl =
      "netcdf hus {\n dimensions: time = 1 ; z = 1 ; y = 2 ; x = 2 ;\n variables:\n"
      " double time(time) ; time:units = \"hours since 2024-06-15 00:00:00\" ;\n"
      " float z(z) ; z:units = \"m\" ; float y(y) ; y:units = \"km\" ; float x(x) ; x:units = \"km\" ;\n"
      " float cl(time, z, y, x) ; cl:standard_name = \"mass_fraction_of_cloud_liquid_water_in_air\" ;\n"
      " float ta(time, z, y, x) ; ta:standard_name = \"air_temperature\" ;\n"
      " float pa(time, z, y, x) ; pa:standard_name = \"air_pressure\" ;\n"
      " float hus(time, z, y, x) ; hus:standard_name = \"specific_humidity\" ; hus:units = \"kg/kg\" ;\n data:\n"
      " time = 0 ; z = 500 ; y = 0, 3 ; x = 0, 3 ; cl = 1e-3, 1e-3, 1e-3, 1e-3 ;\n"
      " ta = 291, 291, 291, 291 ; pa = 85000, 85000, 85000, 85000 ; hus = 0.01, %s, 0.01, 0.01 ;\n}\n";
  const char *values[] = {"15", "-0.5", "-1e-4"};
  for (int v = 0; v < 3; ++v) {
    char text[2048], name[16];
    snprintf(text, sizeof text, cdl, values[v]);
    snprintf(name, sizeof name, "hus%d", v);
    sl_error err = {0};
    static sl_storm_frame f;
    sl_load_options opt = {0};
    const int rc = sl_storm_load(make(name, text), &opt, &f, &err);
    char what[600];
    snprintf(what, sizeof what, "specific humidity %s: %s", values[v], rc ? err.message : "loaded");
    CHECK_MSG(v < 2 ? rc != SL_OK && strstr(err.message, "water vapour") : rc == SL_OK, what);
    if (!rc) sl_storm_frame_free(&f);
  }
}

/* A CF mass fraction's number concentration through ancillary_variables (CF 3.4): taken where the
 * linked variable is a number per kg (the sizes then follow from q and N: more droplets of the
 * same water are smaller, and extinguish more, as N^(1/3) for a fixed shape), passed over where
 * it is a flag. */
static void test_cf_numbers(void)
{
  const char *cdl =
      "netcdf cfn {\n dimensions: z = 1 ; y = 2 ; x = 2 ;\n variables:\n"
      " float z(z) ; z:units = \"m\" ; float y(y) ; y:units = \"km\" ; float x(x) ; x:units = \"km\" ;\n"
      " float cl(z, y, x) ; cl:standard_name = \"mass_fraction_of_cloud_liquid_water_in_air\" ;"
      " cl:ancillary_variables = \"%s\" ;\n float cl_flag(z, y, x) ; cl_flag:units = \"1\" ;\n"
      " float ncl(z, y, x) ; ncl:units = \"kg-1\" ;\n float rho(z, y, x) ; rho:standard_name = \"air_density\" ;\n"
      " data:\n z = 500 ; y = 0, 3 ; x = 0, 3 ; cl = 1e-3, 1e-3, 1e-3, 1e-3 ; cl_flag = 1, 1, 1, 1 ;"
      " ncl = 1e8, 1e9, 1e8, 1e8 ; rho = 1, 1, 1, 1 ;\n}\n";
  char text[2048];
  sl_storm_frame f;
  snprintf(text, sizeof text, cdl, "cl_flag ncl");
  if (!load(make("cfn", text), NULL, &f)) {
    CHECK(strcmp(f.species[0].number_variable, "ncl") == 0 && sl_species_sized(&f.species[0]));
    const double ratio = eta_at(&f, SL_CLOUD, 1, 0) / eta_at(&f, SL_CLOUD, 0, 0);
    CHECK_MSG(ratio > 1.5 && ratio < 3.0, "ten times the droplets: about 10^(1/3) the extinction");
    sl_storm_frame_free(&f);
  }
  snprintf(text, sizeof text, cdl, "cl_flag");
  if (!load(make("cff", text), NULL, &f)) {
    CHECK(f.species[0].number_variable[0] == '\0' && !sl_species_sized(&f.species[0]));
    CHECK_CLOSE(eta_at(&f, SL_CLOUD, 0, 0), 1e-3 / sl_particle_mass(SL_CLOUD), 1e-5, 0.0);
    sl_storm_frame_free(&f);
  }
}

int main(void)
{
  if (!mkdtemp(dir)) return 1;
  test_cf_numbers();
  test_density_and_single_moment();
  test_split_and_double_moment();
  test_sizes();
  test_cm1_wrf_numbers();
  test_cm1_and_cf();
  test_calendars();
  test_decreasing_coordinates();
  test_idealized_wrf();
  test_vapour_bounds();
  const char *shared = getenv("SL_SHARED_DIR");
  char katrina[4096];
  snprintf(katrina, sizeof katrina, "%s/data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc", shared ? shared : "../shared");
  test_subsets(katrina);
  test_series();
  char cmd[700];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
  return sl_test_finish("test_reader_species");
}
