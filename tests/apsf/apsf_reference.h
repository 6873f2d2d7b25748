/* Independent references for the APSF tests: Legendre polynomials by upward recurrence, the
 * paper's printed coefficients, and a brute-force partial sum of eq. 27 in long double. None of
 * this calls render/apsf. */
#ifndef APSF_REFERENCE_H
#define APSF_REFERENCE_H

#include <math.h>

#ifndef REF_PI
#define REF_PI 3.14159265358979323846
#endif

/* P_n(x) and P_n'(x) by upward recurrence. */
static inline void ref_legendre(int n, double x, double *p, double *dp)
{
  double p0 = 1.0, p1 = x;
  if (n == 0) {
    *p = 1.0;
    *dp = 0.0;
    return;
  }
  for (int k = 2; k <= n; ++k) {
    const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
    p0 = p1;
    p1 = p2;
  }
  *p = p1;
  /* (1 - x^2) P_n' = n (P_{n-1} - x P_n); at |x| = 1, P_n'(±1) = (±1)^{n-1} n (n+1) / 2. */
  if (fabs(1.0 - x * x) < 1e-14) *dp = (x > 0 ? 1.0 : (n % 2 ? 1.0 : -1.0)) * n * (n + 1) / 2.0;
  else *dp = n * (p0 - x * p1) / (1.0 - x * x);
}

/* The paper as printed: W_k = W0 (2k+1) q^k (eq. 12 with the albedo of section 2.2.1),
 * beta_m = (2m+1)/m (1 - W_{m-1}/(2m-1)), alpha_m = m + 1 (eq. 25), g_m = e^{-beta T} T^{-alpha}. */
static inline long double ref_g(int m, double T, double q, double W0)
{
  if (m == 0) return 0.0L;
  const long double W = (long double)W0 * (2.0L * (m - 1) + 1.0L) * powl(q, m - 1);
  const long double beta = (2.0L * m + 1.0L) / m * (1.0L - W / (2.0L * m - 1.0L));
  return expl(-beta * T - (m + 1.0L) * logl(T));
}

/* Eq. 27 with `terms` Legendre terms, summed directly. */
static inline double ref_series(double T, double q, double W0, double mu, int terms)
{
  long double sum = 0.0L, p0 = 1.0L, p1 = mu;
  for (int l = 0; l < terms; ++l) {
    long double pl;
    if (l == 0) pl = 1.0L;
    else if (l == 1) pl = mu;
    else {
      pl = ((2.0L * l - 1.0L) * mu * p1 - (l - 1.0L) * p0) / l;
      p0 = p1;
      p1 = pl;
    }
    sum += (ref_g(l, T, q, W0) + ref_g(l + 1, T, q, W0)) * pl;
  }
  return (double)sum;
}

/* Gauss–Legendre nodes and weights on [-1, 1] (Golub–Welsch would do too; Newton is enough). */
static inline void ref_gauss(int n, double *x, double *w)
{
  for (int i = 0; i < n; ++i) {
    double z = cos(REF_PI * (i + 0.75) / (n + 0.5)), p, dp;
    for (int it = 0; it < 100; ++it) {
      ref_legendre(n, z, &p, &dp);
      const double dz = p / dp;
      z -= dz;
      if (fabs(dz) < 1e-15) break;
    }
    ref_legendre(n, z, &p, &dp);
    x[i] = z;
    w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

/* Henyey–Greenstein normalised to mean 1 over the sphere (eq. 11). */
static inline double ref_hg(double q, double c)
{
  const double d = 1.0 + q * q - 2.0 * q * c;
  return (1.0 - q * q) / (d * sqrt(d));
}

/* int g(u, v) du dv over [x0, x1] x [y0, y1]: Gauss-Legendre, panels x panels panels of 24 x 24
 * nodes (the 2D PSF over an image plane). */
static inline double ref_plane_integral(double (*g)(const void *, double, double), const void *user, double x0,
                                        double x1, double y0, double y1, int panels)
{
  double x[24], w[24];
  ref_gauss(24, x, w);
  const double sx = (x1 - x0) / panels, sy = (y1 - y0) / panels;
  double integral = 0.0;
  for (int pj = 0; pj < panels; ++pj)
    for (int pi = 0; pi < panels; ++pi)
      for (int j = 0; j < 24; ++j)
        for (int i = 0; i < 24; ++i)
          integral += 0.25 * sx * sy * w[i] * w[j] *
                      g(user, x0 + sx * (pi + 0.5 + 0.5 * x[i]), y0 + sy * (pj + 0.5 + 0.5 * x[j]));
  return integral;
}

#endif
