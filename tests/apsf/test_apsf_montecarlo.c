/* The glow model (render/apsf) against the Monte Carlo reference's point source (render/reference,
 * sl_ref_point_source), issue 8's acceptance point 3. Both sides give the same quantity in the same
 * unit: S of sl_apsf.h (L = I0 sigma^2 S / (4 pi)) at optical distance T, as a function of the angle
 * theta between the light's direction and the outward radial (0: looking at the source), averaged
 * over the same 5-degree bins in solid angle, with the unscattered beam kept apart on both sides (the
 * reference scores only scattered light; sl_apsf_profile carries the direct beam as its Dirac).
 *
 * Regular run (seconds):
 *   1. where the model is expected to hold: T = 1 (render/apsf's single-scattering regime) with a
 *      low albedo, where the reference's field is single scattering plus a second order of relative
 *      size ~W0 — agreement within 4 sigma + 2 W0;
 *   2. the measured model error at T = 4, q = 0.8, W0 = 0.9 (docs/ACCURACY.md): profile / Monte Carlo
 *      per bin within the stated band, and the evidence that it is a model error, not a mismatch of
 *      geometry or normalisation (the bounded sphere of the paper's own check changes the forward
 *      bins by under 2 %; peak-normalised shapes disagree as much as absolute values).
 * `--table` (ctest label slow): the full table of docs/ACCURACY.md, 8 points, 10^6 photons each,
 * with the best fit of the series' shape family over free (T_eff, q_eff). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sl_apsf.h"
#include "sl_reference.h"
#include "sl_testing.h"

#define BINS 36
#define DEG (3.14159265358979323846 / 180.0)

static const int report_bins[] = {0, 2, 6, 12, 18, 30}; /* centres 2.5, 12.5, 32.5, 62.5, 92.5, 152.5 deg */
#define N_REPORT 6

/* Solid-angle average of f over [lo, hi] (midpoint rule in theta, weight sin theta). */
static double bin_average(double (*f)(void *, double), void *ctx, double lo, double hi)
{
  const int n = 64;
  double num = 0.0, den = 0.0;
  for (int i = 0; i < n; ++i) {
    const double t = lo + (hi - lo) * (i + 0.5) / n, w = sin(t);
    num += w * f(ctx, t), den += w;
  }
  return num / den;
}

static double series_at(void *ctx, double theta) { return sl_apsf_series_eval(ctx, cos(theta)); }

typedef struct {
  sl_apsf_profile *p;
  double T;
} profile_ctx;
/* The profile's fluence weight T^2 S_eff / (4 pi) back to S. */
static double profile_at(void *ctx, double theta)
{
  const profile_ctx *c = ctx;
  return sl_apsf_profile_eval(c->p, theta) * 4.0 * 3.14159265358979323846 / (c->T * c->T);
}

typedef struct {
  double T, q, albedo;
} medium_point;

typedef struct {
  double ratio[BINS];         /* profile / Monte Carlo per bin */
  double shape_ratio[BINS];   /* the same after normalising both to their first bin */
  double rel_sigma[BINS];     /* Monte Carlo standard error / value */
  double mc[BINS], model[BINS], series[BINS];
  double mc_fluence, model_fluence; /* scattered fluence relative to the vacuum fluence I0 / R^2 */
  double net_flux;
} comparison;

static int compare(medium_point pt, int bounded, long photons, comparison *c)
{
  sl_error err = {0};
  sl_ref_point_options o;
  sl_ref_point_options_defaults(&o);
  o.optical_distance = pt.T, o.albedo = pt.albedo, o.g = pt.q, o.bins = BINS, o.photons = photons;
  o.bounded = bounded;
  sl_ref_point_result r;
  if (sl_ref_point_source(&o, &r, &err)) return CHECK_MSG(0, err.message), 1;
  const sl_apsf_medium m = {pt.albedo, pt.q, NULL, 0};
  sl_apsf_profile prof;
  if (sl_apsf_profile_build(&prof, &m, pt.T, 1e-6, 3.14159265358979323846, 8192, &err)) {
    sl_ref_point_result_free(&r);
    return CHECK_MSG(0, err.message), 1;
  }
  sl_apsf_series s;
  const int have_series = pt.T > 1.0 && sl_apsf_series_init(&s, &m, pt.T, 1e-6, 0, &err) == SL_OK;
  profile_ctx pc = {&prof, pt.T};
  c->mc_fluence = c->model_fluence = 0.0;
  for (int b = 0; b < BINS; ++b) {
    const double lo = b * 180.0 / BINS * DEG, hi = (b + 1) * 180.0 / BINS * DEG;
    const double dOmega = 2.0 * 3.14159265358979323846 * (cos(lo) - cos(hi));
    c->mc[b] = r.apsf[b];
    c->rel_sigma[b] = r.apsf[b] > 0.0 ? r.se_apsf[b] / r.apsf[b] : 1.0;
    c->model[b] = bin_average(profile_at, &pc, lo, hi);
    c->series[b] = have_series ? bin_average(series_at, &s, lo, hi) : 0.0;
    c->ratio[b] = r.apsf[b] > 0.0 ? c->model[b] / r.apsf[b] : 0.0;
    c->mc_fluence += r.apsf[b] * dOmega * pt.T * pt.T / (4.0 * 3.14159265358979323846);
    c->model_fluence += c->model[b] * dOmega * pt.T * pt.T / (4.0 * 3.14159265358979323846);
  }
  for (int b = 0; b < BINS; ++b)
    c->shape_ratio[b] = c->mc[b] > 0.0 ? (c->model[b] / c->model[0]) / (c->mc[b] / c->mc[0]) : 0.0;
  c->net_flux = r.net_flux;
  if (have_series) sl_apsf_series_free(&s);
  sl_apsf_profile_free(&prof);
  sl_ref_point_result_free(&r);
  return 0;
}

/* Best fit of the series' peak-normalised shape family to the Monte Carlo over 0-60 degrees with
 * free (T_eff, q_eff): the paper's milk fits chose their parameters this way. Returns the worst
 * relative error of the best fit. */
static double fit_shape(const comparison *c, double albedo, double *T_eff, double *q_eff)
{
  const int nb = BINS / 3;
  double best = 1e300;
  for (double Te = 1.02; Te < 40.0; Te *= 1.04)
    for (double qe = 0.0; qe < 0.995; qe += 0.01) {
      const sl_apsf_medium m = {albedo, qe, NULL, 0};
      sl_apsf_series s;
      sl_error err;
      if (sl_apsf_series_init(&s, &m, Te, 1e-4, 0, &err)) continue;
      double p[BINS], sxy = 0.0, sxx = 0.0;
      for (int b = 0; b < nb; ++b) {
        p[b] = bin_average(series_at, &s, b * 5.0 * DEG, (b + 1) * 5.0 * DEG);
        sxy += p[b] / c->mc[b], sxx += p[b] * p[b] / (c->mc[b] * c->mc[b]);
      }
      sl_apsf_series_free(&s);
      const double k = sxy / sxx; /* least squares in relative error */
      double worst = 0.0;
      for (int b = 0; b < nb; ++b) worst = fmax(worst, fabs(k * p[b] / c->mc[b] - 1.0));
      if (worst < best) best = worst, *T_eff = Te, *q_eff = qe;
    }
  return best;
}

static void regular(void)
{
  comparison c;
  /* 1. Single-scattering regime, low albedo: the profile is single scattering; the reference adds
   *    orders >= 2, of relative size about W0 (and more at large theta, where single scattering of a
   *    forward phase function is small). */
  const medium_point ss = {1.0, 0.5, 0.02};
  if (!compare(ss, 0, 200000, &c))
    for (int b = 0; b < 18; ++b) { /* the forward hemisphere */
      const double tol = 4.0 * c.rel_sigma[b] + 2.0 * ss.albedo;
      if (!CHECK_MSG(fabs(c.ratio[b] - 1.0) <= tol, "single-scattering profile vs Monte Carlo, T = 1, W0 = 0.02"))
        printf("  bin %d: profile %.5g, Monte Carlo %.5g (ratio %.4f, tolerance %.4f)\n", b, c.model[b], c.mc[b],
               c.ratio[b], tol);
    }

  /* 2. The measured model error at T = 4, q = 0.8, W0 = 0.9 (docs/ACCURACY.md's table, 10^6
   *    photons): profile / Monte Carlo at 2.5, 12.5, 32.5, 62.5, 92.5, 152.5 degrees. */
  const medium_point pt = {4.0, 0.8, 0.9};
  static const double stated[N_REPORT] = {0.0184, 0.0663, 0.236, 0.635, 0.848, 0.236};
  comparison inf, bnd;
  if (compare(pt, 0, 200000, &inf) || compare(pt, 1, 200000, &bnd)) return;
  for (int k = 0; k < N_REPORT; ++k) {
    const int b = report_bins[k];
    const double tol = 4.0 * inf.rel_sigma[b] + 0.03; /* MC noise here + the table's own noise */
    if (!CHECK_MSG(fabs(inf.ratio[b] / stated[k] - 1.0) <= tol, "model error at T 4, q 0.8, W0 0.9 as stated"))
      printf("  theta %.1f: profile / Monte Carlo %.4f, stated %.4f (tolerance %.3f)\n", (b + 0.5) * 5.0, inf.ratio[b],
             stated[k], tol);
  }
  /* Not the geometry: the bounded sphere (the paper's bowl) changes the forward bins by < 2 %,
   * while the model is 50x below there. */
  for (int b = 0; b < 3; ++b) CHECK(fabs(bnd.mc[b] / inf.mc[b] - 1.0) < 0.02 + 4.0 * inf.rel_sigma[b]);
  CHECK(inf.ratio[0] < 0.05);
  /* Not the normalisation: normalising both to their forward bin (the paper's "maximum = 1")
   * leaves the shapes a factor > 3 apart at 32.5 degrees. */
  CHECK(bnd.shape_ratio[6] > 3.0 && inf.shape_ratio[6] > 3.0);
  /* Not the angle variable or the solid-angle measure: the scattered fluence does not depend on
   * either. The model keeps 0.28 of the vacuum fluence I0/R^2 (e^{-3 (1 - W0) T} less the direct
   * beam's share), the reference 0.89: the model's absorption is too strong and its field too broad. */
  CHECK(inf.model_fluence < 0.5 * inf.mc_fluence);
}

static void table(void)
{
  static const medium_point pts[] = {{1.1, 0.8, 0.9}, {2.0, 0.85, 0.9}, {2.0, 0.5, 0.95}, {4.0, 0.5, 0.9},
                                     {4.0, 0.8, 0.9}, {4.0, 0.95, 0.9}, {8.0, 0.8, 0.95}, {16.0, 0.9, 0.99}};
  printf("| T | q | W0 | scattered fluence MC | model | profile / MC at 2.5° | 12.5° | 32.5° | 62.5° | 92.5° | "
         "152.5° | MC σ (max of these) | shape / MC at 32.5° (peak-normalised) | bowl: best (T_eff, q_eff) | "
         "its worst error 0–60° |\n|");
  for (int k = 0; k < 16; ++k) printf(" --- |");
  printf("\n");
  for (size_t i = 0; i < sizeof pts / sizeof pts[0]; ++i) {
    comparison inf, bnd;
    if (compare(pts[i], 0, 1000000, &inf) || compare(pts[i], 1, 1000000, &bnd)) continue;
    double Te = 0, qe = 0;
    const double fit = fit_shape(&bnd, pts[i].albedo, &Te, &qe);
    double sigma = 0.0;
    for (int k = 0; k < N_REPORT; ++k) sigma = fmax(sigma, inf.rel_sigma[report_bins[k]]);
    printf("| %g | %g | %g | %.3g | %.3g |", pts[i].T, pts[i].q, pts[i].albedo, inf.mc_fluence, inf.model_fluence);
    for (int k = 0; k < N_REPORT; ++k) printf(" %.3g |", inf.ratio[report_bins[k]]);
    printf(" %.1f %% | %.3g | (%.2f, %.2f) | %.1f %% |\n", 100.0 * sigma, inf.shape_ratio[6], Te, qe, 100.0 * fit);
    fflush(stdout);
    /* The model is everywhere broader than the field (forward too low) except at T = 1.1, where
     * render/apsf's profile is mostly single scattering. */
    CHECK(inf.ratio[0] < 0.9);
  }
}

int main(int argc, char **argv)
{
  if (argc > 1 && strcmp(argv[1], "--table") == 0)
    table();
  else
    regular();
  return sl_test_finish("test_apsf_montecarlo");
}
