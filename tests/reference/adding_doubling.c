/* Adding-doubling for a homogeneous slab over a black surface (see adding_doubling.h).
 *
 * Radiances are kept at the Gauss nodes mu_i of each hemisphere. A layer is described by
 * matrices acting on radiance vectors: R (downward radiance at the top -> upward radiance at the
 * top) and T (downward at the top -> downward at the bottom, the unscattered part on the
 * diagonal), the same from below for a homogeneous layer; and by the diffuse radiance a unit
 * collimated irradiance produces: r0 (up at the top) and t0 (down at the bottom). A thin layer
 * of optical thickness delta starts the doubling by single scattering (the "infinitesimal
 * generator", van de Hulst 1980 sec. 4.3; error O(delta)), and
 *     R' = R + T (1 - R R)^-1 R T,  T' = T (1 - R R)^-1 T
 * doubles it; the beam terms follow from the interface equations D = t0 + e R r0 + R U,
 * U = R D + e r0 (e: the beam's transmission through one layer). */
#include "adding_doubling.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAXN 128
#define PI 3.14159265358979323846

/* Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n). */
static void gauss01(int n, double *x, double *w)
{
  for (int i = 0; i < n; ++i) {
    double z = cos(PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (fabs(dz) < 1e-15) break;
    }
    x[i] = 0.5 * (1.0 - z);
    w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
  }
}

/* Azimuth average of the phase function (1/sr) between directions of cosines a and b:
 * sum_l (2l+1)/(4 pi) chi_l P_l(a) P_l(b) (the m = 0 term of the addition theorem). */
static double phase_m0(const ad_slab *s, double a, double b)
{
  const int L = s->chi ? s->n_chi : 2000;
  double pa0 = 1.0, pa1 = a, pb0 = 1.0, pb1 = b;
  double sum = 1.0 / (4.0 * PI);
  double chi = 1.0;
  for (int l = 1; l < L; ++l) {
    chi = s->chi ? s->chi[l] : chi * s->g;
    if (!s->chi && fabs(chi) < 1e-15) break;
    sum += (2.0 * l + 1.0) / (4.0 * PI) * chi * pa1 * pb1;
    const double na = ((2.0 * l + 1.0) * a * pa1 - l * pa0) / (l + 1.0);
    const double nb = ((2.0 * l + 1.0) * b * pb1 - l * pb0) / (l + 1.0);
    pa0 = pa1, pa1 = na, pb0 = pb1, pb1 = nb;
  }
  return sum;
}

static void matmul(int n, const double *a, const double *b, double *c)
{
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double s = 0.0;
      for (int k = 0; k < n; ++k) s += a[i * n + k] * b[k * n + j];
      c[i * n + j] = s;
    }
}

static void matvec(int n, const double *a, const double *v, double *out)
{
  for (int i = 0; i < n; ++i) {
    double s = 0.0;
    for (int k = 0; k < n; ++k) s += a[i * n + k] * v[k];
    out[i] = s;
  }
}

/* inv = a^-1 by Gauss-Jordan with partial pivoting; returns 1 when singular. */
static int invert(int n, const double *a, double *inv)
{
  double m[MAXN * 2 * MAXN];
  const int w = 2 * n;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < w; ++j) m[i * w + j] = j < n ? a[i * n + j] : (j - n == i ? 1.0 : 0.0);
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (fabs(m[r * w + c]) > fabs(m[p * w + c])) p = r;
    if (fabs(m[p * w + c]) < 1e-300) return 1;
    if (p != c)
      for (int j = 0; j < w; ++j) {
        const double t = m[c * w + j];
        m[c * w + j] = m[p * w + j];
        m[p * w + j] = t;
      }
    const double piv = 1.0 / m[c * w + c];
    for (int j = 0; j < w; ++j) m[c * w + j] *= piv;
    for (int r = 0; r < n; ++r) {
      if (r == c) continue;
      const double f = m[r * w + c];
      if (f == 0.0) continue;
      for (int j = 0; j < w; ++j) m[r * w + j] -= f * m[c * w + j];
    }
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) inv[i * n + j] = m[i * w + n + j];
  return 0;
}

int ad_slab_fluxes(const ad_slab *s, ad_fluxes *out)
{
  if (s->n_quad < 2 || s->n_quad >= MAXN || !(s->tau > 0.0) || !(s->mu0 > 0.0 && s->mu0 <= 1.0)) return 1;
  double mu[MAXN], wq[MAXN];
  gauss01(s->n_quad, mu, wq);
  /* An extra direction of zero weight: it takes part in no integral, but its radiance is
   * computed like every other's, giving R and T at any mu. */
  const int extra = s->mu_extra > 0.0 && s->mu_extra <= 1.0;
  const int n = s->n_quad + extra;
  if (extra) mu[n - 1] = s->mu_extra, wq[n - 1] = 0.0;
  const size_t nn = (size_t)n * n;
  double *R = calloc(nn, sizeof(double)), *T = calloc(nn, sizeof(double));
  double *A = calloc(nn, sizeof(double)), *B = calloc(nn, sizeof(double)), *M = calloc(nn, sizeof(double));
  double *C = calloc(nn, sizeof(double));
  if (!R || !T || !A || !B || !M || !C) {
    free(R), free(T), free(A), free(B), free(M), free(C);
    return 1;
  }
  double r0[MAXN], t0[MAXN];

  /* Start: delta = tau / 2^k below 1e-9. */
  int k = 0;
  double delta = s->tau;
  while (delta > 1e-7) delta *= 0.5, ++k;
  const double om = s->albedo;
  for (int j = 0; j < n; ++j) {
    /* Quadrature renormalisation: the discrete phase function conserves energy exactly, so an
     * albedo-1 slab keeps R + T = 1 to rounding. */
    double norm = 0.0;
    for (int i = 0; i < n; ++i) norm += 2.0 * PI * wq[i] * (phase_m0(s, mu[i], -mu[j]) + phase_m0(s, -mu[i], -mu[j]));
    for (int i = 0; i < n; ++i) {
      R[i * n + j] = om * phase_m0(s, mu[i], -mu[j]) / norm * 2.0 * PI * wq[j] * delta / mu[i];
      T[i * n + j] = om * phase_m0(s, -mu[i], -mu[j]) / norm * 2.0 * PI * wq[j] * delta / mu[i];
    }
    T[j * n + j] += exp(-delta / mu[j]);
  }
  {
    double norm = 0.0;
    for (int i = 0; i < n; ++i)
      norm += 2.0 * PI * wq[i] * (phase_m0(s, mu[i], -s->mu0) + phase_m0(s, -mu[i], -s->mu0));
    for (int i = 0; i < n; ++i) {
      r0[i] = om * phase_m0(s, mu[i], -s->mu0) / norm * delta / (s->mu0 * mu[i]);
      t0[i] = om * phase_m0(s, -mu[i], -s->mu0) / norm * delta / (s->mu0 * mu[i]);
    }
  }
  double e = exp(-delta / s->mu0);

  for (int step = 0; step < k; ++step) {
    /* M = (1 - R R)^-1 */
    matmul(n, R, R, A);
    for (size_t i = 0; i < nn; ++i) A[i] = -A[i];
    for (int i = 0; i < n; ++i) A[i * n + i] += 1.0;
    if (invert(n, A, M)) {
      free(R), free(T), free(A), free(B), free(M), free(C);
      return 1;
    }
    /* Beam: D = M (t0 + e R r0), U = R D + e r0. */
    double v[MAXN], D[MAXN], U[MAXN], tmp[MAXN];
    matvec(n, R, r0, v);
    for (int i = 0; i < n; ++i) v[i] = t0[i] + e * v[i];
    matvec(n, M, v, D);
    matvec(n, R, D, U);
    for (int i = 0; i < n; ++i) U[i] += e * r0[i];
    matvec(n, T, U, tmp);
    for (int i = 0; i < n; ++i) r0[i] += tmp[i];
    matvec(n, T, D, tmp);
    for (int i = 0; i < n; ++i) t0[i] = tmp[i] + e * t0[i];
    /* R' = R + T M R T, T' = T M T. */
    matmul(n, T, M, A);  /* A = T M */
    matmul(n, A, R, B);  /* B = T M R */
    matmul(n, B, T, C);  /* C = T M R T */
    matmul(n, A, T, B);  /* B = T M T */
    for (size_t i = 0; i < nn; ++i) {
      R[i] += C[i];
      T[i] = B[i];
    }
    e *= e;
  }
  double refl = 0.0, trans = 0.0;
  for (int i = 0; i < n; ++i) {
    refl += 2.0 * PI * wq[i] * mu[i] * r0[i];
    trans += 2.0 * PI * wq[i] * mu[i] * t0[i];
  }
  out->reflectance = refl;
  out->reflection_function = extra ? PI * r0[n - 1] : 0.0;
  out->transmission_function = extra ? PI * t0[n - 1] : 0.0;
  out->direct_transmittance = exp(-s->tau / s->mu0);
  out->transmittance = trans + out->direct_transmittance;
  free(R), free(T), free(A), free(B), free(M), free(C);
  return 0;
}
