/* The series against values from outside the code: the boundary property I(T, -1) = 0, the
 * large-T limit of eq. 33, q = 0 and W0 < 1 (section 2.2.1), the fluence of the normalisation,
 * the term counts of section 2.2.5, the code's own term choice against a brute-force sum, the
 * single-scattering regime against an independent quadrature, eq. 28 against ray-sphere
 * geometry, and the blend across T = 1. */
#include <math.h>
#include <stdio.h>

#include "apsf_reference.h"
#include "sl_apsf.h"
#include "sl_testing.h"

static double series(double T, double q, double W0, double mu, double tol)
{
  const sl_apsf_medium m = {W0, q, NULL, 0};
  sl_apsf_series s;
  sl_error err = {0};
  if (sl_apsf_series_init(&s, &m, T, tol, 0, &err)) {
    CHECK_MSG(0, err.message);
    return NAN;
  }
  const double v = sl_apsf_series_eval(&s, mu);
  sl_apsf_series_free(&s);
  return v;
}

static void test_boundary(void)
{
  /* Telescoping: sum (g_m + g_{m+1}) (-1)^m = g_0 = 0. */
  const double Ts[5] = {1.1, 1.5, 2.0, 4.0, 10.0}, qs[4] = {0.0, 0.5, 0.9, 0.95};
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j) {
      const double back = series(Ts[i], qs[j], 1.0, -1.0, 1e-8), peak = series(Ts[i], qs[j], 1.0, 1.0, 1e-8);
      char what[96];
      snprintf(what, sizeof what, "I(T=%g, -1) = %.3g with peak %.3g (q %g)", Ts[i], back, peak, qs[j]);
      CHECK_MSG(fabs(back) <= 1e-8 * peak, what);
    }
}

static void test_eq33_limit(void)
{
  /* Eq. 33: T^2 e^{3(1-W0)T} I -> 1 + mu when g_1 dominates, with the next term g_2 / g_1 =
   * e^{-(beta_2 - beta_1) T} / T as the error (beta from eq. 25 in the reference). */
  const double W0s[2] = {1.0, 0.99};
  for (int w = 0; w < 2; ++w)
    for (double T = 25.0; T <= 400.0; T *= 4.0) {
      const double q = 0.9, W0 = W0s[w];
      const double b1 = 3.0 * (1.0 - W0), b2 = 2.5 * (1.0 - W0 * q);
      const double next = exp(-(b2 - b1) * T) / T;
      for (double mu = -0.9; mu <= 1.0; mu += 0.3) {
        const double v = series(T, q, W0, mu, 1e-12) * T * T * exp(b1 * T);
        CHECK_CLOSE(v, 1.0 + mu, 0, 2.5 * next + 1e-9);
      }
      /* The back hemisphere of 1 + mu holds 1/4 of it. */
      const sl_apsf_medium m = {W0, q, NULL, 0};
      sl_apsf_series s;
      sl_error err = {0};
      sl_apsf_series_init(&s, &m, T, 1e-12, 0, &err);
      CHECK_CLOSE(sl_apsf_series_back_fraction(&s), 0.25, 0, 2.0 * next + 1e-9);
      sl_apsf_series_free(&s);
    }
}

static void test_isotropic_and_albedo(void)
{
  /* q = 0 (section 2.2.1): every W_k, k >= 1, vanishes, so beta_1 = 3 (1 - W0) and
   * beta_m = (2m + 1)/m for m >= 2: the brute-force sum of those. */
  for (double T = 1.2; T < 30; T *= 1.9)
    for (double mu = -1.0; mu <= 1.0; mu += 0.25) {
      long double sum = 0.0L;
      double p0 = 1.0, p1 = mu;
      for (int l = 0; l < 400; ++l) {
        double pl = l == 0 ? 1.0 : (l == 1 ? mu : 0.0);
        if (l >= 2) {
          pl = ((2.0 * l - 1.0) * mu * p1 - (l - 1.0) * p0) / l;
          p0 = p1;
          p1 = pl;
        }
        long double g[2];
        for (int k = 0; k < 2; ++k) {
          const int m = l + k;
          const double beta = m == 1 ? 3.0 * (1.0 - 0.8) : (2.0 * m + 1.0) / m;
          g[k] = m == 0 ? 0.0L : expl(-beta * T - (m + 1.0) * log(T));
        }
        sum += (g[0] + g[1]) * pl;
      }
      CHECK_CLOSE(series(T, 0.0, 0.8, mu, 1e-13), (double)sum, 1e-10, 1e-13 * series(T, 0.0, 0.8, 1.0, 1e-13));
    }
  /* Absorption lowers the forward value; g_1 falls by e^{-3 (1 - W0) T} (eq. 32). */
  for (double T = 1.1; T < 20; T *= 1.7)
    for (double q = 0.0; q < 0.96; q += 0.3) {
      const double full = series(T, q, 1.0, 1.0, 1e-10), half = series(T, q, 0.5, 1.0, 1e-10);
      CHECK(half < full);
      const sl_apsf_medium a = {0.5, q, NULL, 0}, b = {1.0, q, NULL, 0};
      CHECK_CLOSE(exp(sl_apsf_log_g(&a, 1, T) - sl_apsf_log_g(&b, 1, T)), exp(-1.5 * T), 1e-12, 0);
    }
}

static void test_fluence(void)
{
  /* The normalisation (docs/APSF.md): 2 pi int S dmu = 4 pi g_1 = 4 pi e^{-3(1-W0)T} / T^2,
   * by Gauss–Legendre quadrature of the code's S. */
  static double x[400], w[400];
  ref_gauss(400, x, w);
  const double Ts[4] = {1.3, 2.0, 5.0, 12.0}, qs[3] = {0.0, 0.7, 0.9}, W0s[2] = {1.0, 0.6};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 2; ++k) {
        const sl_apsf_medium m = {W0s[k], qs[j], NULL, 0};
        sl_apsf_series s;
        sl_error err = {0};
        if (sl_apsf_series_init(&s, &m, Ts[i], 1e-12, 0, &err)) continue;
        double sum = 0.0;
        for (int n = 0; n < 400; ++n) sum += w[n] * sl_apsf_series_eval(&s, x[n]);
        double back = 0.0; /* mu in [-1, 0]: Gauss-Legendre mapped to the half interval */
        for (int n = 0; n < 400; ++n) back += 0.5 * w[n] * sl_apsf_series_eval(&s, 0.5 * (x[n] - 1.0));
        CHECK_CLOSE(sl_apsf_series_back_fraction(&s), back / sum, 1e-9, 0);
        const double want = 4.0 * REF_PI * exp(-3.0 * (1.0 - W0s[k]) * Ts[i]);
        CHECK_CLOSE(Ts[i] * Ts[i] * 2.0 * REF_PI * sum, want, 1e-9, 0);
        sl_apsf_series_free(&s);
      }
}

/* Paper's criterion (section 2.2.5): the smallest number of terms whose sum is within 0.1 %
 * of the 500-term sum, the deviation taken as a fraction of the 500-term peak, over angles. */
static int paper_term_count(double T, double q)
{
  enum { NA = 181, NT = 500 };
  static double partial[NA][NT + 1];
  double peak = 0.0;
  for (int a = 0; a < NA; ++a) {
    const double mu = cos(a * REF_PI / (NA - 1));
    long double sum = 0.0L, p0 = 1.0L, p1 = mu;
    partial[a][0] = 0.0;
    for (int l = 0; l < NT; ++l) {
      long double pl = l == 0 ? 1.0L : (l == 1 ? (long double)mu : 0.0L);
      if (l >= 2) {
        pl = ((2.0L * l - 1.0L) * mu * p1 - (l - 1.0L) * p0) / l;
        p0 = p1;
        p1 = pl;
      }
      sum += (ref_g(l, T, q, 1.0) + ref_g(l + 1, T, q, 1.0)) * pl;
      partial[a][l + 1] = (double)sum;
    }
    if (fabs(partial[a][NT]) > peak) peak = fabs(partial[a][NT]);
  }
  for (int M = 1; M <= NT; ++M) {
    double worst = 0.0;
    for (int a = 0; a < NA; ++a) worst = fmax(worst, fabs(partial[a][M] - partial[a][NT]));
    if (worst <= 1e-3 * peak) return M;
  }
  return NT + 1;
}

static void test_term_counts(void)
{
  const double qs[3] = {0.5, 0.8, 0.9};
  for (int j = 0; j < 3; ++j)
    for (double T = 2.01; T < 12; T *= 1.6) {
      const int n = paper_term_count(T, qs[j]);
      char what[96];
      snprintf(what, sizeof what, "T %.3g q %.1f: %d terms for 0.1 %% of the 500-term sum (paper: < 10)", T, qs[j], n);
      CHECK_MSG(n < 10, what);
      printf("%s\n", what);
    }
  const int n = paper_term_count(1.02, 0.9);
  printf("T 1.02 q 0.9: %d terms for 0.1 %% of the 500-term sum (paper: about 200)\n", n);
  CHECK(n >= 100 && n <= 500);
  const sl_apsf_medium m = {1.0, 0.9, NULL, 0};
  printf("T 1.02 q 0.9: the code's bound needs %d terms for 1e-3, %d for 1e-6\n", sl_apsf_terms_needed(&m, 1.02, 1e-3),
         sl_apsf_terms_needed(&m, 1.02, 1e-6));
}

static void test_term_choice(void)
{
  /* The code's choice meets its tolerance against a brute-force sum with many more terms. */
  const double Ts[6] = {1.05, 1.1, 1.5, 2.0, 4.0, 10.0}, qs[5] = {0.0, 0.5, 0.8, 0.9, 0.95}, tols[2] = {1e-3, 1e-6};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 2; ++k) {
        const sl_apsf_medium m = {1.0, qs[j], NULL, 0};
        sl_apsf_series s;
        sl_error err = {0};
        if (sl_apsf_series_init(&s, &m, Ts[i], tols[k], 0, &err)) {
          CHECK_MSG(0, err.message);
          continue;
        }
        const int many = (int)(40.0 / log(Ts[i])) + 20;
        const double peak = ref_series(Ts[i], qs[j], 1.0, 1.0, many);
        double worst = 0.0;
        for (int a = 0; a <= 90; ++a) {
          const double mu = cos(a * REF_PI / 90.0);
          const double d = fabs(sl_apsf_series_eval(&s, mu) - ref_series(Ts[i], qs[j], 1.0, mu, many));
          if (d > worst) worst = d;
        }
        char what[128];
        snprintf(what, sizeof what, "T %g q %g tol %g: %d terms, error %.3g of the peak", Ts[i], qs[j], tols[k], s.terms,
                 worst / peak);
        CHECK_MSG(worst <= tols[k] * peak, what);
        sl_apsf_series_free(&s);
      }
}

/* Single scattering by a different substitution: t - t_c = h sinh(s) around the closest
 * approach t_c = T cos(gamma), so dt / tau^2 = ds / (h cosh s) and cos(Theta) = -tanh(s). */
static double ref_single(double T, double q, double W0, double gamma)
{
  const double h = T * sin(gamma), tc = T * cos(gamma);
  const double s0 = asinh(-tc / h), s1 = asinh((tc + 80.0) / h);
  const int n = 40000;
  const double ds = (s1 - s0) / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double s = s0 + i * ds, tau = h * cosh(s), t = tc + h * sinh(s);
    const double f = ref_hg(q, -tanh(s)) * exp(-(tau + t)) / (h * cosh(s));
    sum += f * (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0));
  }
  return W0 * sum * ds / 3.0;
}

static void test_single_scatter(void)
{
  const double Ts[3] = {0.3, 0.8, 1.2}, qs[3] = {0.0, 0.7, 0.9}, gs[4] = {0.01, 0.1, 0.7, 2.5};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 4; ++k) {
        const sl_apsf_medium m = {0.9, qs[j], NULL, 0};
        CHECK_CLOSE(sl_apsf_single_scatter(&m, Ts[i], gs[k]), ref_single(Ts[i], qs[j], 0.9, gs[k]), 2e-6, 0);
      }
}

static void test_outside_sphere(void)
{
  /* Eq. 28 against the near intersection of the ray with the sphere (camera at -D on z). */
  const double R = 1.0;
  for (double D = 1.5; D < 20; D *= 2.0)
    for (double g = 0.0; g < asin(R / D); g += 0.05) {
      const double dir[3] = {sin(g), 0.0, cos(g)}, cam[3] = {0, 0, -D};
      const double b = cam[2] * dir[2], c = D * D - R * R;
      const double t = -b - sqrt(b * b - c);
      const double p[3] = {cam[0] + t * dir[0], 0.0, cam[2] + t * dir[2]};
      const double mu = -(p[0] * dir[0] + p[2] * dir[2]) / R; /* outward normal . toward the camera */
      CHECK_CLOSE(sl_apsf_mu_outside(D, R, g), mu, 1e-12, 1e-12);
    }
  CHECK(sl_apsf_mu_outside(3.0, 1.0, 0.5) == -2.0); /* misses: sin(0.5) > 1/3 */
}

/* Largest relative change of the profile at four angles over steps dT across T in [0.95, 1.6]. */
static double blend_rate(double dT)
{
  const sl_apsf_medium m = {1.0, 0.8, NULL, 0};
  const double gammas[4] = {0.02, 0.1, 0.3, 1.0};
  double worst = 0.0;
  for (double T = 0.95; T < 1.6; T += 0.01) {
    sl_apsf_profile a, b;
    sl_error err = {0};
    if (sl_apsf_profile_build(&a, &m, T, 1e-6, 1.2, 1024, &err) ||
        sl_apsf_profile_build(&b, &m, T + dT, 1e-6, 1.2, 1024, &err)) {
      CHECK_MSG(0, err.message);
      return NAN;
    }
    for (int k = 0; k < 4; ++k) {
      const double u = sl_apsf_profile_eval(&a, gammas[k]), v = sl_apsf_profile_eval(&b, gammas[k]);
      worst = fmax(worst, fabs(v - u) / fmax(u, v));
    }
    worst = fmax(worst, fabs(a.direct - b.direct)); /* the Dirac's weight, a fraction of 1 */
    sl_apsf_profile_free(&a);
    sl_apsf_profile_free(&b);
  }
  return worst;
}

static void test_blend_continuity(void)
{
  /* Across the single-scattering / series blend the profile is continuous in T: halving the
   * step halves the largest change (a seam would not shrink). */
  const double r1 = blend_rate(2e-3), r2 = blend_rate(1e-3);
  printf("blend: largest relative change per dT = 0.002: %.4g, per dT = 0.001: %.4g\n", r1, r2);
  CHECK(r1 / r2 > 1.8 && r1 / r2 < 2.2);
}

int main(void)
{
  test_boundary();
  test_eq33_limit();
  test_isotropic_and_albedo();
  test_fluence();
  test_term_counts();
  test_term_choice();
  test_single_scatter();
  test_outside_sphere();
  test_blend_continuity();
  return sl_test_finish("test_apsf_series");
}
