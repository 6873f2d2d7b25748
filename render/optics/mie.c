/* Lorenz–Mie series for a homogeneous sphere.
 * Bohren & Huffman 1983 (B&H), "Absorption and Scattering of Light by Small Particles",
 * eqs. 4.53 (a_n, b_n written with the logarithmic derivative D_n, sec. 4.8), 4.61-4.62
 * (Qext, Qsca), 4.74 (S1, S2), 4.46-4.47 (pi_n, tau_n recurrences); asymmetry from B&H
 * p. 120; backscatter from B&H eq. 4.82. Number of terms and the starting index of the downward
 * recurrence for D_n follow Wiscombe 1980 (Appl. Opt. 19, 1505), eqs. 21 and 18: the downward
 * recurrence is stable for any complex m, which the upward one is not when Im(m) x is large. */
#include "sl_mie.h"

#include <complex.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int sl_mie_series_terms(double x)
{
  /* Wiscombe 1980, eq. 21 (the x <= 8 branch also covers the Rayleigh limit, with at least
   * two terms so that the backscatter sum sees b_1 and a_2). */
  double n;
  if (x <= 8.0)
    n = x + 4.0 * cbrt(x) + 1.0;
  else if (x < 4200.0)
    n = x + 4.05 * cbrt(x) + 2.0;
  else
    n = x + 4.0 * cbrt(x) + 2.0;
  int terms = (int)n;
  return terms < 2 ? 2 : terms;
}

typedef struct mie_coefficients {
  double complex *a, *b; /* a[1..terms], b[1..terms] */
  double complex *d;     /* D_n scratch, 0..n_start */
  int terms;
} mie_coefficients;

static size_t coefficient_bytes(double x, double m_re, double m_im, int *terms, int *n_start)
{
  *terms = sl_mie_series_terms(x);
  const double mx = hypot(m_re, m_im) * x;
  /* Start the downward recurrence well above both N_stop and |m x|. B&H's BHMIE starts at
   * max(N_stop, |mx|) + 15, which is too close for weakly absorbing large spheres: for
   * m = 1.33 + 1e-5 i, x = 1e4 it gives Qsca 0.3% low against Wiscombe's test case 11, because
   * the start error only decays where n > |mx|. 1.1 |mx| + 50 reproduces the case to 1e-7 and
   * agrees with a start at 2 |mx| + 200 to the last digit. */
  *n_start = (int)(fmax((double)*terms, 1.1 * mx) + 50.0);
  return sizeof(double complex) * (size_t)(2 * (*terms + 2) + *n_start + 1);
}

static int check_args(double x, double m_re, double m_im, sl_error *err)
{
  if (!(x >= SL_MIE_X_MIN && x <= SL_MIE_X_MAX))
    return sl_fail(err, SL_ERR_ARG, "mie: size parameter %g outside [%g, %g]", x, SL_MIE_X_MIN, SL_MIE_X_MAX);
  if (!(m_re > 0.0 && isfinite(m_re) && m_im >= 0.0 && isfinite(m_im)))
    return sl_fail(err, SL_ERR_ARG, "mie: refractive index %g%+gi is not a physical medium (need re > 0, im >= 0)",
                   m_re, m_im);
  return SL_OK;
}

/* a_n and b_n, B&H eq. 4.88 with D_n from the downward recurrence B&H eq. 4.89. */
static void mie_series(double x, double m_re, double m_im, mie_coefficients *c, int n_start)
{
  const double complex m = m_re + I * m_im;
  const double complex mx = m * x;
  double complex *d = c->d;
  d[n_start] = 0.0;
  for (int n = n_start; n >= 1; --n) d[n - 1] = (double)n / mx - 1.0 / (d[n] + (double)n / mx);

  /* Riccati–Bessel psi_n = x j_n(x) and chi_n = -x y_n(x), upward from n = -1, 0. */
  double psi_prev = cos(x), psi = sin(x);
  double chi_prev = -sin(x), chi = cos(x);
  for (int n = 1; n <= c->terms; ++n) {
    const double f = (2.0 * n - 1.0) / x;
    const double psi_n = f * psi - psi_prev;
    const double chi_n = f * chi - chi_prev;
    const double complex xi_n = psi_n - I * chi_n, xi_prev = psi - I * chi;
    const double complex da = d[n] / m + n / x;
    const double complex db = m * d[n] + n / x;
    c->a[n] = (da * psi_n - psi) / (da * xi_n - xi_prev);
    c->b[n] = (db * psi_n - psi) / (db * xi_n - xi_prev);
    psi_prev = psi;
    psi = psi_n;
    chi_prev = chi;
    chi = chi_n;
  }
}

static void mie_efficiencies(double x, const mie_coefficients *c, sl_mie_efficiencies *out)
{
  double ext = 0.0, sca = 0.0, asym = 0.0;
  double complex back = 0.0;
  for (int n = 1; n <= c->terms; ++n) {
    const double complex a = c->a[n], b = c->b[n];
    const double w = 2.0 * n + 1.0;
    ext += w * creal(a + b);
    sca += w * (creal(a) * creal(a) + cimag(a) * cimag(a) + creal(b) * creal(b) + cimag(b) * cimag(b));
    back += w * ((n & 1) ? -1.0 : 1.0) * (a - b);
    asym += w / ((double)n * (n + 1.0)) * creal(a * conj(b));
    if (n < c->terms) {
      const double complex a1 = c->a[n + 1], b1 = c->b[n + 1];
      asym += (double)n * (n + 2.0) / (n + 1.0) * creal(a * conj(a1) + b * conj(b1));
    }
  }
  const double x2 = x * x;
  out->qext = 2.0 / x2 * ext;
  out->qsca = 2.0 / x2 * sca;
  out->qback = (creal(back) * creal(back) + cimag(back) * cimag(back)) / x2;
  out->g = out->qsca > 0.0 ? 4.0 / x2 * asym / out->qsca : 0.0;
  out->terms = c->terms;
}

static void *workspace_get(sl_mie_workspace *ws, size_t bytes, void **own)
{
  *own = NULL;
  if (!ws) return *own = malloc(bytes);
  if (ws->bytes < bytes) {
    void *p = realloc(ws->buffer, bytes);
    if (!p) return NULL;
    ws->buffer = p;
    ws->bytes = bytes;
  }
  return ws->buffer;
}

void sl_mie_workspace_free(sl_mie_workspace *ws)
{
  if (!ws) return;
  free(ws->buffer);
  ws->buffer = NULL;
  ws->bytes = 0;
}

static int coefficients_in(void *mem, double x, double m_re, double m_im, int terms, int n_start,
                           mie_coefficients *c)
{
  c->terms = terms;
  c->a = (double complex *)mem;
  c->b = c->a + terms + 2;
  c->d = c->b + terms + 2;
  mie_series(x, m_re, m_im, c, n_start);
  return SL_OK;
}

int sl_mie(double x, double m_re, double m_im, const double *mu, int n_angles, sl_mie_efficiencies *out,
           sl_amplitude *s1, sl_amplitude *s2, double *s11, sl_error *err)
{
  if (check_args(x, m_re, m_im, err)) return err ? err->code : SL_ERR_ARG;
  if (n_angles < 0 || (n_angles > 0 && !mu)) return sl_fail(err, SL_ERR_ARG, "mie: bad angle list");
  int terms, n_start;
  const size_t bytes = coefficient_bytes(x, m_re, m_im, &terms, &n_start);
  void *mem = malloc(bytes);
  if (!mem) return sl_fail(err, SL_ERR_NOMEM, "mie: out of memory for %d terms", terms);
  mie_coefficients c;
  coefficients_in(mem, x, m_re, m_im, terms, n_start, &c);
  sl_mie_efficiencies eff;
  mie_efficiencies(x, &c, &eff);
  if (out) *out = eff;
  for (int j = 0; j < n_angles; ++j) {
    const double u = mu[j];
    double pi_prev = 0.0, pi = 1.0;
    double complex S1 = 0.0, S2 = 0.0;
    for (int n = 1; n <= terms; ++n) {
      const double tau = n * u * pi - (n + 1.0) * pi_prev;
      const double f = (2.0 * n + 1.0) / ((double)n * (n + 1.0));
      S1 += f * (c.a[n] * pi + c.b[n] * tau);
      S2 += f * (c.a[n] * tau + c.b[n] * pi);
      const double pi_next = ((2.0 * n + 1.0) * u * pi - (n + 1.0) * pi_prev) / n;
      pi_prev = pi;
      pi = pi_next;
    }
    if (s1) s1[j] = (sl_amplitude){creal(S1), cimag(S1)};
    if (s2) s2[j] = (sl_amplitude){creal(S2), cimag(S2)};
    if (s11) s11[j] = 0.5 * (creal(S1) * creal(S1) + cimag(S1) * cimag(S1) + creal(S2) * creal(S2) +
                             cimag(S2) * cimag(S2));
  }
  free(mem);
  return SL_OK;
}

int sl_mie_s11_mirrored(double x, double m_re, double m_im, const double *mu_half, int n_half,
                        sl_mie_efficiencies *out, double *s11, sl_mie_workspace *ws, sl_error *err)
{
  if (check_args(x, m_re, m_im, err)) return err ? err->code : SL_ERR_ARG;
  if (n_half < 1 || !mu_half || !s11) return sl_fail(err, SL_ERR_ARG, "mie: bad mirrored angle list");
  int terms, n_start;
  const size_t coef_bytes = coefficient_bytes(x, m_re, m_im, &terms, &n_start);
  /* Per angle, in separate real arrays so that the loop over angles vectorises: pi_{n-1}, pi_n
   * and the real and imaginary parts of S1(+mu), S2(+mu), S1(-mu), S2(-mu). */
  enum { ARRAYS = 10 };
  const size_t angle_bytes = (size_t)n_half * ARRAYS * sizeof(double);
  void *own;
  void *mem = workspace_get(ws, coef_bytes + angle_bytes, &own);
  if (!mem) return sl_fail(err, SL_ERR_NOMEM, "mie: out of memory for %d terms", terms);
  mie_coefficients c;
  coefficients_in(mem, x, m_re, m_im, terms, n_start, &c);
  sl_mie_efficiencies eff;
  mie_efficiencies(x, &c, &eff);
  if (out) *out = eff;

  double *base = (double *)((char *)mem + coef_bytes);
  double *restrict pi_prev = base, *restrict pi = base + n_half;
  double *restrict s1p_re = base + 2 * n_half, *restrict s1p_im = base + 3 * n_half;
  double *restrict s2p_re = base + 4 * n_half, *restrict s2p_im = base + 5 * n_half;
  double *restrict s1m_re = base + 6 * n_half, *restrict s1m_im = base + 7 * n_half;
  double *restrict s2m_re = base + 8 * n_half, *restrict s2m_im = base + 9 * n_half;
  for (int j = 0; j < n_half; ++j) {
    pi_prev[j] = 0.0;
    pi[j] = 1.0;
    s1p_re[j] = s1p_im[j] = s2p_re[j] = s2p_im[j] = 0.0;
    s1m_re[j] = s1m_im[j] = s2m_re[j] = s2m_im[j] = 0.0;
  }
  for (int n = 1; n <= terms; ++n) {
    const double f = (2.0 * n + 1.0) / ((double)n * (n + 1.0));
    const double ar = f * creal(c.a[n]), ai = f * cimag(c.a[n]), br = f * creal(c.b[n]), bi = f * cimag(c.b[n]);
    const double parity = (n & 1) ? 1.0 : -1.0; /* (-1)^(n-1) */
    const double k1 = (2.0 * n + 1.0) / n, k2 = (n + 1.0) / n, dn = (double)n, dn1 = n + 1.0;
    for (int j = 0; j < n_half; ++j) {
      const double u = mu_half[j], p = pi[j];
      const double t = dn * u * p - dn1 * pi_prev[j];
      /* S1 = sum f (a pi + b tau), S2 = sum f (a tau + b pi); at -mu, pi picks up (-1)^(n-1)
       * and tau (-1)^n. */
      s1p_re[j] += ar * p + br * t;
      s1p_im[j] += ai * p + bi * t;
      s2p_re[j] += ar * t + br * p;
      s2p_im[j] += ai * t + bi * p;
      s1m_re[j] += parity * (ar * p - br * t);
      s1m_im[j] += parity * (ai * p - bi * t);
      s2m_re[j] += parity * (br * p - ar * t);
      s2m_im[j] += parity * (bi * p - ai * t);
      const double next = k1 * u * p - k2 * pi_prev[j];
      pi_prev[j] = p;
      pi[j] = next;
    }
  }
  for (int j = 0; j < n_half; ++j) {
    s11[j] = 0.5 * (s1p_re[j] * s1p_re[j] + s1p_im[j] * s1p_im[j] + s2p_re[j] * s2p_re[j] + s2p_im[j] * s2p_im[j]);
    s11[2 * n_half - 1 - j] =
        0.5 * (s1m_re[j] * s1m_re[j] + s1m_im[j] * s1m_im[j] + s2m_re[j] * s2m_re[j] + s2m_im[j] * s2m_im[j]);
  }
  free(own);
  return SL_OK;
}
