/* Verifies the derivation of Narasimhan et al. numerically instead of trusting the print:
 *  - the four projected terms of eq. 15 (eqs. 19-22) by quadrature, with P^(0) from the
 *    azimuthal integral of eq. 3 (not from eq. 13), give back alpha_m and beta_m of eq. 25;
 *  - each g_m of the code solves eq. 23 (numerical derivative);
 *  - the superposed series (eq. 27) against the projected transfer equation (eq. 9) for every
 *    projection n: the printed claim that I(T, mu) satisfies it is measured (docs/APSF.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "apsf_reference.h"
#include "sl_apsf.h"
#include "sl_testing.h"

#define NMU 48
#define NMU2 160
#define NPHI 512

static double mu_x[NMU], mu_w[NMU], mu2_x[NMU2], mu2_w[NMU2];

/* P^(0)(mu_i, mu'_j) of eq. 3 by the trapezoid rule in azimuth (spectrally accurate for a
 * periodic integrand), for HG with albedo 1. */
static void azimuthal_phase(double q, double *p0)
{
  for (int i = 0; i < NMU; ++i)
    for (int j = 0; j < NMU2; ++j) {
      const double a = mu_x[i], b = mu2_x[j], s = sqrt((1 - a * a) * (1 - b * b));
      double sum = 0.0;
      for (int k = 0; k < NPHI; ++k) sum += ref_hg(q, a * b + s * cos(2 * REF_PI * k / NPHI)); /* eq. 2 */
      p0[i * NMU2 + j] = sum / NPHI;
    }
}

/* f_m(mu) = L_{m-1} + L_m (eq. 16) and Q_n = L_n' / (n (n+1)) (eq. 5). */
static double f_m(int m, double x)
{
  double a, b, d;
  ref_legendre(m - 1, x, &a, &d);
  ref_legendre(m, x, &b, &d);
  return a + b;
}
static double Q_n(int n, double x)
{
  double p, dp;
  ref_legendre(n, x, &p, &dp);
  return dp / (n * (n + 1.0));
}

/* Projection n of eq. 9 for an angular function F sampled at mu2 nodes (and at mu nodes):
 * the coefficients A = int mu Q_n F, B = int L_n F, C = int Q_n F, D = 1/2 int Q_n int P0 F. */
typedef struct {
  double A, B, C, D;
} proj;
static proj project(int n, const double *F_mu, const double *F_mu2, const double *p0, double W0)
{
  proj r = {0, 0, 0, 0};
  for (int i = 0; i < NMU; ++i) {
    const double x = mu_x[i], q = Q_n(n, x);
    double p, dp;
    ref_legendre(n, x, &p, &dp);
    r.A += mu_w[i] * x * q * F_mu[i];
    r.B += mu_w[i] * p * F_mu[i];
    r.C += mu_w[i] * q * F_mu[i];
    double inner = 0.0;
    for (int j = 0; j < NMU2; ++j) inner += mu2_w[j] * W0 * p0[i * NMU2 + j] * F_mu2[j];
    r.D += 0.5 * mu_w[i] * q * inner;
  }
  return r;
}

int main(void)
{
  ref_gauss(NMU, mu_x, mu_w);
  ref_gauss(NMU2, mu2_x, mu2_w);
  double *p0 = malloc(sizeof(double) * NMU * NMU2);
  const double qs[3] = {0.0, 0.5, 0.8};
  const int ms[5] = {1, 2, 3, 5, 8};
  double F_mu[NMU], F_mu2[NMU2];
  for (int iq = 0; iq < 3; ++iq) {
    azimuthal_phase(qs[iq], p0);
    for (int iw = 0; iw < 2; ++iw) {
      const double W0 = iw ? 0.7 : 1.0;
      const sl_apsf_medium med = {W0, qs[iq], NULL, 0};
      for (int k = 0; k < 5; ++k) {
        const int m = ms[k];
        for (int i = 0; i < NMU; ++i) F_mu[i] = f_m(m, mu_x[i]);
        for (int j = 0; j < NMU2; ++j) F_mu2[j] = f_m(m, mu2_x[j]);
        const proj r = project(m, F_mu, F_mu2, p0, W0);
        /* Eq. 15 reads g' A + g (B / T + C - D) = 0, so g = e^{-beta T} T^{-alpha} with
         * alpha = B / A and beta = (C - D) / A. */
        char what[128];
        snprintf(what, sizeof what, "alpha_%d by quadrature (q %g W0 %g)", m, qs[iq], W0);
        CHECK_MSG(fabs(r.B / r.A - sl_apsf_alpha(m)) < 1e-9, what);
        snprintf(what, sizeof what, "beta_%d by quadrature (q %g W0 %g): %.12f vs %.12f", m, qs[iq], W0,
                 (r.C - r.D) / r.A, sl_apsf_beta(&med, m));
        CHECK_MSG(fabs((r.C - r.D) / r.A - sl_apsf_beta(&med, m)) < 1e-7, what);
        /* Eqs. 19-22 as printed. */
        CHECK_CLOSE(r.A, 2.0 / ((m + 1.0) * (2.0 * m + 1.0)), 1e-10, 0);
        CHECK_CLOSE(r.B, 2.0 / (2.0 * m + 1.0), 1e-10, 0);
        CHECK_CLOSE(r.C, 2.0 / (m * (m + 1.0)), 1e-10, 0);
        CHECK_CLOSE(r.D, 2.0 / (m * (m + 1.0)) * W0 * (2 * m - 1) * pow(qs[iq], m - 1) / (2 * m - 1.0), 1e-7, 1e-12);
        /* Eq. 23 for the code's g_m, by a central difference in T. */
        for (double T = 1.2; T < 20; T *= 2.3) {
          /* Richardson-extrapolated central differences: error O(h^4). */
          const double h = 1e-3 * T, g = exp(sl_apsf_log_g(&med, m, T));
#define CD(hh) ((exp(sl_apsf_log_g(&med, m, T + (hh))) - exp(sl_apsf_log_g(&med, m, T - (hh)))) / (2 * (hh)))
          const double dg = (4.0 * CD(0.5 * h) - CD(h)) / 3.0;
#undef CD
          const double res = dg + g * sl_apsf_alpha(m) / T + g * sl_apsf_beta(&med, m);
          const double scale = fabs(dg) + fabs(g * sl_apsf_alpha(m) / T) + fabs(g * sl_apsf_beta(&med, m));
          snprintf(what, sizeof what, "eq. 23 residual m %d T %g q %g W0 %g: %.3g", m, T, qs[iq], W0, res / scale);
          CHECK_MSG(fabs(res) <= 1e-8 * scale, what);
        }
      }
    }
    /* The superposition: projection n of eq. 9 applied to the whole of eq. 27. Each term g_m f_m
     * was built to satisfy projection m only; the others see the neighbours' terms. */
    for (int iT = 0; iT < 3; ++iT) {
      const double T = iT == 0 ? 1.5 : (iT == 1 ? 3.0 : 8.0), W0 = 1.0;
      const sl_apsf_medium med = {W0, qs[iq], NULL, 0};
      sl_apsf_series s0, sm, sp, s2m, s2p;
      const double h = 1e-3 * T;
      sl_error err = {0};
      if (sl_apsf_series_init(&s0, &med, T, 1e-12, 0, &err) || sl_apsf_series_init(&sm, &med, T - h, 1e-12, 0, &err) ||
          sl_apsf_series_init(&sp, &med, T + h, 1e-12, 0, &err) ||
          sl_apsf_series_init(&s2m, &med, T - 2 * h, 1e-12, 0, &err) ||
          sl_apsf_series_init(&s2p, &med, T + 2 * h, 1e-12, 0, &err)) {
        CHECK_MSG(0, err.message);
        continue;
      }
      double dF_mu[NMU], dF_mu2[NMU2];
      for (int i = 0; i < NMU; ++i) {
        F_mu[i] = sl_apsf_series_eval(&s0, mu_x[i]);
        /* Richardson: (4 D(h) - D(2h)) / 3. */
        const double d1 = (sl_apsf_series_eval(&sp, mu_x[i]) - sl_apsf_series_eval(&sm, mu_x[i])) / (2 * h);
        const double d2 = (sl_apsf_series_eval(&s2p, mu_x[i]) - sl_apsf_series_eval(&s2m, mu_x[i])) / (4 * h);
        dF_mu[i] = (4.0 * d1 - d2) / 3.0;
      }
      for (int j = 0; j < NMU2; ++j) {
        F_mu2[j] = sl_apsf_series_eval(&s0, mu2_x[j]);
        dF_mu2[j] = 0.0;
      }
      for (int n = 1; n <= 4; ++n) {
        const proj r = project(n, F_mu, F_mu2, p0, W0), rd = project(n, dF_mu, dF_mu2, p0, W0);
        const double res = rd.A + r.B / T + r.C - r.D;
        const double scale = fabs(rd.A) + fabs(r.B / T) + fabs(r.C) + fabs(r.D);
        /* The doubly-projected residual from the neighbour m = n + 1 alone (docs/APSF.md):
         * -2 g_{n+1} (beta_{n+1} + 1/T) / ((n+1)(2n+1)), plus the lower neighbours'. */
        printf("eq. 9, projection %d, q %.1f, T %.1f: residual %.4g of scale %.4g (relative %.3g)\n", n, qs[iq], T, res,
               scale, res / scale);
        if (n == 1) {
          /* n = 1: only m = 2 couples in (A, B, C and D vanish for m >= 3 by orthogonality;
           * Q_1 = 1/2), so the residual is exactly the m = 2 cross term, for any q. */
          const double g2 = exp(sl_apsf_log_g(&med, 2, T));
          const double want = -2.0 * g2 * (sl_apsf_beta(&med, 2) + 1.0 / T) / (2.0 * 3.0);
          CHECK_CLOSE(res, want, 1e-5, 1e-9 * scale);
        }
      }
      sl_apsf_series_free(&s0);
      sl_apsf_series_free(&sm);
      sl_apsf_series_free(&sp);
      sl_apsf_series_free(&s2m);
      sl_apsf_series_free(&s2p);
    }
  }
  free(p0);
  return sl_test_finish("test_apsf_derivation");
}
