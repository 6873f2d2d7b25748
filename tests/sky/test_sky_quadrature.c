/* Riley eqs. 11 and 14-15 (corrected) against adaptive quadrature of eqs. 4 and 8 (issue 5
 * acceptance): random configurations and every singular case by name. Usage:
 *   test_sky_quadrature [configurations]   (default 10000) */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "quadrature.h"
#include "sl_sky.h"
#include "sl_testing.h"

static const double kPi = 3.14159265358979323846;
static const double kGamma = 1.0 / 8000.0;

/* xorshift64*: seeded, reproducible. */
static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double uniform(void)
{
  rng_state ^= rng_state >> 12;
  rng_state ^= rng_state << 25;
  rng_state ^= rng_state >> 27;
  return (double)((rng_state * 2685821657736338717ull) >> 11) * (1.0 / 9007199254740992.0);
}
static double log_uniform(double lo, double hi) { return lo * pow(hi / lo, uniform()); }

typedef struct config {
  double beta_sl, z_eye, mu, K, airmass, cos_view_sun;
} config;

static double closed_form(const config *c)
{
  double K = sl_sky_segment_length(c->z_eye, c->mu, c->K, 0.0);
  return sl_sky_inscatter(c->beta_sl, kGamma, c->z_eye, c->mu, K, c->airmass, c->cos_view_sun);
}

static double quadrature(const config *c)
{
  ref_sky s = {c->beta_sl, kGamma, c->z_eye, c->mu, c->airmass, sl_sky_rayleigh_phase(c->cos_view_sun)};
  return ref_sky_radiance(&s, c->K, 1e-10);
}

static double worst_rel = 0.0;
static int check_config(const char *name, const config *c)
{
  double got = closed_form(c), want = quadrature(c);
  double rel = fabs(got - want) / fmax(fabs(want), 1e-300);
  if (isfinite(got) && rel > worst_rel && want > 1e-290) worst_rel = rel;
  int ok = isfinite(got) && got >= 0.0 && fabs(got - want) <= 1e-6 * fabs(want) + 1e-300;
  if (!ok)
    fprintf(stderr, "%s: z=%.17g mu=%.17g K=%.17g m=%.17g beta=%.17g: closed %.17g quadrature %.17g\n", name,
            c->z_eye, c->mu, c->K, c->airmass, c->beta_sl, got, want);
  return CHECK_MSG(ok, name);
}

/* Transparency (eq. 11) against quadrature of eq. 4 with eq. 10. */
typedef struct beta_path {
  double beta_sl, z0, dz_per_m;
} beta_path;
static double beta_along(const void *ctx, double t)
{
  const beta_path *p = ctx;
  return p->beta_sl * exp(-kGamma * (p->z0 + p->dz_per_m * t));
}

static void random_transparency(int n)
{
  double worst = 0.0;
  int bad = 0;
  for (int i = 0; i < n; ++i) {
    double beta = sl_rayleigh_beta_standard_air(380.0 + 340.0 * uniform());
    double z0 = uniform() < 0.2 ? 0.0 : log_uniform(1.0, 1e5);
    double K = log_uniform(1.0, 1e6);
    double mu = uniform() < 0.1 ? 0.0 : 2.0 * uniform() - 1.0;
    if (mu < 0.0 && z0 + mu * K < 0.0) K = z0 / -mu;
    if (!(K > 0.0)) continue;
    double z1 = z0 + mu * K;
    beta_path p = {beta, z0, mu};
    double want = ref_integrate(beta_along, &p, K, 1e-12);
    double got = sl_sky_optical_depth(beta, kGamma, z0, z1, K);
    double back = sl_sky_optical_depth(beta, kGamma, z1, z0, K);
    double rel = fabs(got - want) / want;
    if (rel > worst) worst = rel;
    if (!(rel <= 1e-9) || !(fabs(back - got) <= 1e-12 * got)) ++bad;
  }
  printf("eq. 11 optical depth vs quadrature of eq. 4: %d segments, worst relative error %.3g\n", n, worst);
  CHECK_MSG(bad == 0, "eq. 11 agrees with quadrature of eq. 4 and is symmetric");
}

static double sun_elevation_random(void)
{
  double r = uniform();
  if (r < 0.1) return log_uniform(1e-6, 1.0); /* near the horizon, degrees */
  return 90.0 * uniform();
}

static void random_sky(int n, const sl_atmosphere *round)
{
  int failed = 0;
  worst_rel = 0.0;
  for (int i = 0; i < n; ++i) {
    config c;
    c.beta_sl = sl_rayleigh_beta_standard_air(380.0 + 340.0 * uniform());
    double r = uniform();
    c.z_eye = r < 0.1 ? 0.0 : r < 0.6 ? log_uniform(1.0, 1e5) : 1e5 * uniform();
    double sun_el = sun_elevation_random();
    if (!(sun_el > 0.0)) sun_el = 1e-6;
    double l = sin(sun_el * kPi / 180.0);
    r = uniform();
    if (r < 0.05) c.mu = 0.0;
    else if (r < 0.10) c.mu = l;
    else if (r < 0.15) c.mu = (uniform() < 0.5 ? -1.0 : 1.0) * log_uniform(1e-12, 1e-3);
    else c.mu = 2.0 * uniform() - 1.0;
    c.K = uniform() < 0.2 ? INFINITY : log_uniform(1.0, 1e6);
    /* flat air mass mostly; the round one is just another constant m for the closed form */
    c.airmass = uniform() < 0.8 ? 1.0 / l : sl_sky_airmass(round, c.z_eye, l);
    c.cos_view_sun = 2.0 * uniform() - 1.0;
    char name[64];
    snprintf(name, sizeof name, "random configuration %d", i);
    if (!check_config(name, &c)) ++failed;
  }
  printf("eqs. 14-15 (corrected) vs quadrature of eq. 8: %d configurations, %d failed, worst relative error %.3g\n",
         n, failed, worst_rel);
}

static void singular_cases(void)
{
  const double b = sl_rayleigh_beta_standard_air(440.0);
  const double l30 = 0.5, l_low = sin(0.5 * kPi / 180.0);
  const config cases[] = {
      /* beta, z_eye, mu, K, airmass, cos */
      {b, 0.0, 0.0, 1e4, 1 / l30, 0.3},             /* horizontal view ray, finite */
      {b, 0.0, 0.0, INFINITY, 1 / l30, 0.3},        /* horizontal view ray to infinity */
      {b, 1e4, 0.0, 1e6, 1 / l30, -0.7},            /* horizontal, high eye, 1000 km */
      {b, 0.0, l30, INFINITY, 1 / l30, 1.0},        /* view elevation = sun elevation, to space */
      {b, 0.0, l30, 5e4, 1 / l30, 1.0},             /* view elevation = sun elevation, finite */
      {b, 2e3, l_low, INFINITY, 1 / l_low, 1.0},    /* both at 0.5 degrees */
      {b, 0.0, 0.2, INFINITY, 1e6, 0.2},            /* sun at the horizon: l = 1e-6 */
      {b, 0.0, 0.2, INFINITY, 1e12, 0.2},           /* sun at the horizon: l = 1e-12 */
      {b, 0.0, 1e-9, INFINITY, 1e9, 0.9},           /* sun and view both grazing */
      {b, 1e3, -0.3, INFINITY, 1 / l30, 0.1},       /* looking down to the ground */
      {b, 1e3, -1.0, INFINITY, 1 / l30, -0.5},      /* straight down */
      {b, 1e5, -0.05, INFINITY, 1 / l30, 0.4},      /* from 100 km, down to the ground */
      {b, 1e5, -0.5, 1e4, 1 / l30, 0.4},            /* from 100 km, 10 km segment down */
      {b, 0.0, -0.2, INFINITY, 1 / l30, 0.4},       /* eye at sea level looking down: empty */
      {b, 0.0, 1.0, INFINITY, 1.0, 1.0},            /* zenith view, zenith sun */
      {b, 1e5, 1.0, INFINITY, 1 / l30, 0.5},        /* eye at 100 km looking up */
      {b, 0.0, 0.3, 1.0, 1 / l30, 0.5},             /* 1 m segment */
      {b, 0.0, 0.3, 1e6, 1 / l30, 0.5},             /* 1000 km segment */
      {b, 0.0, -1e-12, 1e6, 1 / l30, 0.5},          /* just below horizontal, 1000 km */
      {b, 5e4, 1e-12, INFINITY, 1 / l30, 0.5},      /* just above horizontal, to space */
  };
  const char *names[] = {
      "horizontal view, 10 km",          "horizontal view, infinite",      "horizontal view, 10 km eye, 1000 km",
      "view elevation = sun elevation, infinite", "view elevation = sun elevation, 50 km",
      "view = sun elevation = 0.5 deg",  "sun at horizon (l = 1e-6)",       "sun at horizon (l = 1e-12)",
      "sun and view grazing",            "looking down to the ground",      "straight down",
      "eye at 100 km, down to ground",   "eye at 100 km, 10 km down",       "eye at sea level looking down",
      "zenith view, zenith sun",         "eye at 100 km looking up",        "1 m segment",
      "1000 km segment",                 "just below horizontal, 1000 km",  "just above horizontal, 50 km eye",
  };
  int n = (int)(sizeof cases / sizeof cases[0]);
  for (int i = 0; i < n; ++i) check_config(names[i], &cases[i]);

  /* night: infinite air mass gives zero, never NaN */
  config night = {b, 0.0, 0.3, INFINITY, INFINITY, 0.5};
  CHECK(closed_form(&night) == 0.0);
  /* the eye far above the air, looking down through all of it */
  config space = {b, 4e6, -1.0, INFINITY, 1 / l30, 0.5};
  CHECK(isfinite(closed_form(&space)) && closed_form(&space) > 0.0);
  /* a segment so long downward that the density overflows: finite */
  config deep = {b, 0.0, -1.0, 1e9, 1 / l30, 0.5};
  deep.z_eye = 1e9;
  CHECK(isfinite(closed_form(&deep)));
}

/* Radiance is continuous across each singular configuration. */
static void continuity(void)
{
  const double b = sl_rayleigh_beta_standard_air(515.0);
  const double l = 0.3, m = 1.0 / l;
  const double deltas[] = {1e-13, 1e-9, 1e-6};
  const double Ks[] = {2e4, INFINITY};
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 3; ++i) {
      double d = deltas[i], K = Ks[k];
      double at = sl_sky_inscatter(b, kGamma, 500.0, l, K, m, 0.8);
      double lo = sl_sky_inscatter(b, kGamma, 500.0, l - d, K, m, 0.8);
      double hi = sl_sky_inscatter(b, kGamma, 500.0, l + d, K, m, 0.8);
      CHECK_CLOSE(lo, at, 10 * d + 1e-14, 0.0);
      CHECK_CLOSE(hi, at, 10 * d + 1e-14, 0.0);
      /* across the horizon; for the infinite ray the downward one ends on the ground */
      double zero = sl_sky_inscatter(b, kGamma, 500.0, 0.0, K, m, 0.8);
      double up = sl_sky_inscatter(b, kGamma, 500.0, d, K, m, 0.8);
      double down = sl_sky_inscatter(b, kGamma, 500.0, -d, sl_sky_segment_length(500.0, -d, K, 0.0), m, 0.8);
      CHECK_CLOSE(up, zero, 10 * d + 1e-14, 0.0);
      CHECK_CLOSE(down, zero, 10 * d + 1e-14, 0.0);
    }
  /* sun to the horizon: radiance goes smoothly to the night value 0 */
  double prev = INFINITY;
  int monotone = 1;
  for (double ls = 1e-2; ls > 1e-300; ls *= 1e-3) {
    double v = sl_sky_inscatter(b, kGamma, 0.0, 0.2, INFINITY, 1.0 / ls, 0.5);
    if (!(v <= prev) || !isfinite(v)) monotone = 0;
    prev = v;
  }
  CHECK_MSG(monotone && prev < 1e-20, "sky fades to zero as the sun reaches the horizon");
}

/* The printed eq. 15 disagrees with the quadrature of eq. 8 by the factor exp(-beta_eye/(gamma mu)). */
static void printed_equation_15(void)
{
  const double b = sl_rayleigh_beta_standard_air(440.0), z = 0.0, mu = 0.1, l = 0.5, K = 3e4;
  const double P = sl_sky_rayleigh_phase(0.4);
  double beta_eye = b * exp(-kGamma * z);
  double A = beta_eye / kGamma * (1.0 / l - 1.0 / mu);
  double printed = P * l / (mu - l) * (exp(-A * exp(-kGamma * mu * K)) - exp(-A));
  ref_sky s = {b, kGamma, z, mu, 1.0 / l, P};
  double want = ref_sky_radiance(&s, K, 1e-10);
  printf("eq. 15 as printed: %.6g, quadrature of eq. 8: %.6g, printed * exp(-beta_eye/(gamma mu)): %.6g\n",
         printed, want, printed * exp(-beta_eye / (kGamma * mu)));
  CHECK_MSG(fabs(printed - want) > 0.1 * want, "the printed eq. 15 is wrong");
  CHECK_CLOSE(printed * exp(-beta_eye / (kGamma * mu)), want, 1e-8, 0.0);
}

int main(int argc, char **argv)
{
  int n = argc > 1 ? atoi(argv[1]) : 10000;
  sl_atmosphere round;
  double w = 550.0;
  sl_atmosphere_init(&round, &w, 1, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, NULL);
  random_transparency(n / 10 > 100 ? n / 10 : 100);
  singular_cases();
  continuity();
  printed_equation_15();
  random_sky(n, &round);
  return sl_test_finish("test_sky_quadrature");
}
