/* From a phase function on a grid to a finished table: forward-peak truncation, Legendre
 * moments, Ams_n (Riley et al. 2004, eq. 20) and F_n (eq. 23). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "optics_internal.h"
#include "sl_legendre.h"

int optics_grid_init(optics_grid *g, double step_deg, sl_error *err)
{
  memset(g, 0, sizeof *g);
  const double intervals = 180.0 / step_deg;
  const long n_int = lround(intervals);
  if (!(step_deg > 0.0) || fabs(intervals - (double)n_int) > 1e-9 || n_int % 2 != 0 || n_int > 2000000)
    return sl_fail(err, SL_ERR_ARG, "optics: angle step %g degrees must divide 90", step_deg);
  g->n_angles = (int)n_int + 1;
  g->step_rad = SL_PI / (double)n_int;
  double *mem = calloc((size_t)g->n_angles * 4, sizeof(double));
  if (!mem) return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory for the angle grid");
  g->theta = mem;
  g->mu = mem + g->n_angles;
  g->weight = mem + 2 * g->n_angles;
  g->weight_forward = mem + 3 * g->n_angles;
  const int half = (g->n_angles - 1) / 2;
  for (int j = 0; j < g->n_angles; ++j) {
    g->theta[j] = j * g->step_rad;
    g->mu[j] = j == half ? 0.0 : cos(g->theta[j]);
  }
  g->mu[0] = 1.0;
  g->mu[g->n_angles - 1] = -1.0;
  /* Exact integrals of the hat functions of linear interpolation in theta against sin theta:
   * on [t0, t1] with h = t1 - t0, int (theta - t0)/h sin = (sin t1 - sin t0 - h cos t1) / h,
   * int (t1 - theta)/h sin = (h cos t0 - sin t1 + sin t0) / h. */
  for (int j = 0; j + 1 < g->n_angles; ++j) {
    const double t0 = g->theta[j], t1 = (j + 1 == g->n_angles - 1) ? SL_PI : g->theta[j + 1], h = t1 - t0;
    const double up = (sin(t1) - sin(t0) - h * cos(t1)) / h;
    const double down = (h * cos(t0) - sin(t1) + sin(t0)) / h;
    g->weight[j] += 2.0 * SL_PI * down;
    g->weight[j + 1] += 2.0 * SL_PI * up;
    if (j < half) {
      g->weight_forward[j] += 2.0 * SL_PI * down;
      g->weight_forward[j + 1] += 2.0 * SL_PI * up;
    }
  }
  return SL_OK;
}

void optics_grid_free(optics_grid *g)
{
  free(g->theta);
  memset(g, 0, sizeof *g);
}

double optics_grid_integral(const optics_grid *g, const double *v)
{
  double s = 0.0;
  for (int j = 0; j < g->n_angles; ++j) s += g->weight[j] * v[j];
  return s;
}

/* chi_l = 2 pi int P P_l dmu of the piecewise-linear-in-theta function v, by 8-point Gauss
 * quadrature in theta on every grid interval (exact to rounding while l * step < ~4). */
static void moments_of_grid_function(const optics_grid *g, const double *v, int n_moments, double *chi)
{
  enum { Q = 8 };
  double gx[Q], gw[Q];
  sl_gauss_legendre(Q, gx, gw);
  memset(chi, 0, sizeof(double) * (size_t)n_moments);
  const int n_int = g->n_angles - 1;
  /* Fixed chunks summed in a fixed order: the moments do not depend on the thread count. */
  enum { CHUNKS = 16 };
  double *acc = calloc((size_t)CHUNKS * (size_t)n_moments + 2 * (size_t)n_moments, sizeof(double));
  if (!acc) return;
  /* Bonnet's recurrence P_l = a_l x P_{l-1} - b_l P_{l-2}, coefficients precomputed so that the
   * inner loop has no division and runs over the Q quadrature points of a cell at once. */
  double *ra = acc + (size_t)CHUNKS * (size_t)n_moments, *rb = ra + n_moments;
  for (int l = 2; l < n_moments; ++l) {
    ra[l] = (2.0 * l - 1.0) / l;
    rb[l] = (l - 1.0) / l;
  }
#pragma omp parallel for schedule(dynamic, 1)
  for (int c = 0; c < CHUNKS; ++c) {
    double *a = acc + (size_t)c * (size_t)n_moments;
    for (int j = c * n_int / CHUNKS; j < (c + 1) * n_int / CHUNKS; ++j) {
      const double t0 = g->theta[j], h = g->step_rad;
      double x[Q], wv[Q], p0[Q], p1[Q];
      for (int q = 0; q < Q; ++q) {
        const double s = 0.5 * (gx[q] + 1.0), t = t0 + s * h;
        const double value = (1.0 - s) * v[j] + s * v[j + 1];
        wv[q] = 2.0 * SL_PI * 0.5 * h * gw[q] * sin(t) * value;
        x[q] = cos(t);
        p0[q] = 1.0;
        p1[q] = x[q];
      }
      double s0 = 0.0, s1 = 0.0;
      for (int q = 0; q < Q; ++q) {
        s0 += wv[q];
        s1 += wv[q] * x[q];
      }
      a[0] += s0;
      if (n_moments > 1) a[1] += s1;
      for (int l = 2; l < n_moments; ++l) {
        const double al = ra[l], bl = rb[l];
        double sum = 0.0;
        for (int q = 0; q < Q; ++q) {
          const double p2 = al * x[q] * p1[q] - bl * p0[q];
          p0[q] = p1[q];
          p1[q] = p2;
          sum += wv[q] * p2;
        }
        a[l] += sum;
      }
    }
  }
  for (int c = 0; c < CHUNKS; ++c)
    for (int l = 0; l < n_moments; ++l) chi[l] += acc[(size_t)c * (size_t)n_moments + l];
  free(acc);
}

static double pow_int(double x, int n)
{
  double r = 1.0;
  while (n > 0) {
    if (n & 1) r *= x;
    x *= x;
    n >>= 1;
  }
  return r;
}

/* Bound on max |4 pi Ams_n - 1| of the smooth part from its moments. */
static double anisotropy_bound(const double *chi_trunc, int n_moments, double f, int n)
{
  double s = 0.0;
  const double fn = pow_int(f, n);
  for (int l = 1; l < n_moments; ++l) s += (2.0 * l + 1.0) * fabs(pow_int(f + chi_trunc[l], n) - fn);
  return s;
}

/* The highest order N: the given one, or the first n whose smooth part is isotropic within the
 * tolerance and whose Dirac weight f^n is below it. */
static int table_order(const optics_table_params *params, const double *chi, int L, double f)
{
  int N = params->max_order;
  if (N <= 0) {
    N = SL_OPTICS_MAX_ORDER;
    for (int n = 1; n <= SL_OPTICS_MAX_ORDER; ++n)
      if (pow_int(f, n) < params->isotropy_tolerance && anisotropy_bound(chi, L, f, n) < params->isotropy_tolerance) {
        N = n;
        break;
      }
  }
  return N < 1 ? 1 : N;
}

/* Ams_n on the grid for n = 0..N into row[n J + j], and delta[n] = f^n:
 * Ams_n = (f delta + Pt)^(*n) = f^n delta + n f^(n-1) Pt + sum_{k>=2} C(n,k) f^(n-k) Pt^(*k):
 * the Dirac and the single-Pt term are exact on the grid (no Gibbs ringing at rainbows),
 * the rest is smooth and summed from its Legendre coefficients
 * q_l = (f + chit_l)^n - f^n - n f^(n-1) chit_l (Riley et al. 2004, eq. 20 in Legendre space). */
static int ams_rows(const optics_grid *g, double f, const double *chi, int L, const double *ptrunc, int N,
                    double *delta, double *row, sl_error *err)
{
  const int J = g->n_angles;
  const size_t rows = (size_t)N + 1;
  double *coef = malloc(sizeof(double) * rows * (size_t)L);
  int *lmax = malloc(sizeof(int) * rows);
  if (!coef || !lmax) {
    free(coef), free(lmax);
    return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory for %d orders", N);
  }
  for (size_t n = 0; n < rows; ++n) {
    delta[n] = pow_int(f, (int)n);
    lmax[n] = 0;
    for (int l = 0; l < L; ++l) {
      double q = 0.0;
      if (n >= 2) q = pow_int(f + chi[l], (int)n) - delta[n] - (double)n * pow_int(f, (int)n - 1) * chi[l];
      coef[n * L + l] = (2.0 * l + 1.0) / (4.0 * SL_PI) * q;
      if (fabs(coef[n * L + l]) > 1e-12) lmax[n] = l + 1;
    }
  }
  int lmax_all = 0;
  for (size_t n = 0; n < rows; ++n) lmax_all = lmax[n] > lmax_all ? lmax[n] : lmax_all;
  /* Coefficients transposed to [l][n] so that the inner loop over orders is contiguous. */
  double *coef_ln = malloc(sizeof(double) * rows * (size_t)(lmax_all > 0 ? lmax_all : 1));
  double *ra = malloc(sizeof(double) * (size_t)(lmax_all + 2)), *rb = malloc(sizeof(double) * (size_t)(lmax_all + 2));
  if (!coef_ln || !ra || !rb) {
    free(coef_ln), free(ra), free(rb), free(coef), free(lmax);
    return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory for %d orders", N);
  }
  for (int l = 0; l < lmax_all; ++l)
    for (size_t n = 0; n < rows; ++n) coef_ln[(size_t)l * rows + n] = l < lmax[n] ? coef[n * L + l] : 0.0;
  for (int l = 2; l < lmax_all; ++l) {
    ra[l] = (2.0 * l - 1.0) / l;
    rb[l] = (l - 1.0) / l;
  }
#pragma omp parallel for schedule(dynamic, 16)
  for (int j = 0; j < J; ++j) {
    const double x = g->mu[j];
    double p0 = 1.0, p1 = x;
    double acc[SL_OPTICS_MAX_ORDER + 1];
    for (size_t n = 0; n < rows; ++n) acc[n] = coef[n * L];
    for (int l = 1; l < lmax_all; ++l) {
      double pl = x;
      if (l >= 2) {
        pl = ra[l] * x * p1 - rb[l] * p0;
        p0 = p1;
        p1 = pl;
      }
      const double *c = coef_ln + (size_t)l * rows;
      for (size_t n = 2; n < rows; ++n) acc[n] += c[n] * pl;
    }
    row[j] = 0.0;
    row[J + j] = ptrunc[j];
    for (size_t n = 2; n < rows; ++n) row[n * J + j] = acc[n] + (double)n * pow_int(f, (int)n - 1) * ptrunc[j];
  }
  free(coef), free(lmax), free(coef_ln), free(ra), free(rb);
  return SL_OK;
}

int optics_table_from_raw(const optics_grid *g, const optics_raw_phase *raw, const optics_table_params *params,
                          double wavelength_nm, sl_phase_table *out, sl_error *err)
{
  memset(out, 0, sizeof *out);
  const int J = g->n_angles, L = params->n_moments;
  for (int j = 0; j < J; ++j)
    if (!isfinite(raw->p[j]) || raw->p[j] < 0.0)
      return sl_fail(err, SL_ERR_DATA, "optics: phase function is %g at %g degrees (%g nm)", raw->p[j],
                     g->theta[j] * 180.0 / SL_PI, wavelength_nm);

  /* Truncation: inside the cone, P is replaced by its value at the cone's edge; what that
   * removes becomes the forward Dirac f (docs/OPTICS.md: the delta-M idea done in angle
   * space, as Potter 1970 did, so that the tabulated P is the model's P everywhere outside). */
  double *ptrunc = malloc(sizeof(double) * (size_t)J);
  double *chi = malloc(sizeof(double) * (size_t)L);
  if (!ptrunc || !chi) {
    free(ptrunc);
    free(chi);
    return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory");
  }
  int jc = (int)lround(params->truncation_rad / g->step_rad);
  if (jc < 1) jc = 1;
  if (jc > J / 4) jc = J / 4;
  for (int j = 0; j < J; ++j) ptrunc[j] = raw->p[j < jc ? jc : j];
  double kept = optics_grid_integral(g, ptrunc);
  double f = 1.0 - kept;
  if (f < 1e-6) {
    /* No resolved peak (a smooth phase function), or the grid integral of a smooth model is
     * off by its quadrature error: no Dirac, renormalise instead. */
    for (int j = 0; j < J; ++j) ptrunc[j] /= kept;
    f = 0.0;
  }
  moments_of_grid_function(g, ptrunc, L, chi);
  const int N = table_order(params, chi, L, f);
  const size_t rows = (size_t)N + 1;
  char *mem = optics_table_alloc(out, N, J, L);
  double *row = malloc(sizeof(double) * rows * (size_t)J);
  int rc = !mem || !row ? sl_fail(err, SL_ERR_NOMEM, "optics: out of memory for %d orders", N) : SL_OK;
  double *delta = mem ? (double *)out->delta : NULL;
  if (!rc) rc = ams_rows(g, f, chi, L, ptrunc, N, delta, row, err);
  if (rc) {
    free(mem), memset(out, 0, sizeof *out), free(row), free(ptrunc), free(chi);
    return rc;
  }
  double *forward = (double *)out->forward, *moments = (double *)out->moments;
  float *ams = (float *)out->ams;
  /* Ringing of the truncated series can dip below zero where a distribution is nearly empty:
   * clamp, then renormalise every row to exactly 1 - f^n under the grid's quadrature. */
  for (size_t n = 1; n < rows; ++n) {
    double *r = row + n * J;
    for (int j = 0; j < J; ++j)
      if (r[j] < 0.0) r[j] = 0.0;
    const double target = 1.0 - delta[n], have = optics_grid_integral(g, r);
    const double scale = have > 0.0 ? target / have : 0.0;
    double fwd = 0.0;
    for (int j = 0; j < J; ++j) {
      ams[n * J + j] = (float)(r[j] * scale);
      fwd += g->weight_forward[j] * (double)ams[n * J + j];
    }
    forward[n] = delta[n] + fwd;
  }
  forward[0] = 1.0;
  for (int l = 0; l < L; ++l) moments[l] = f + chi[l];
  moments[0] = 1.0;

  out->wavelength_nm = wavelength_nm;
  out->sigma_ext = raw->sigma_ext;
  out->albedo = raw->albedo;
  out->asymmetry = L > 1 ? moments[1] : 0.0;
  out->truncated_fraction = f;
  out->step_rad = g->step_rad;
  out->inv_step_rad = 1.0 / g->step_rad;
  free(row), free(ptrunc), free(chi);
  return SL_OK;
}

void *optics_table_alloc(sl_phase_table *t, int max_order, int n_angles, int n_moments)
{
  const size_t rows = (size_t)max_order + 1;
  const size_t bytes = sizeof(double) * (rows * 2 + (size_t)n_moments) + sizeof(float) * rows * (size_t)n_angles;
  char *mem = calloc(1, bytes);
  if (!mem) return NULL;
  double *delta = (double *)mem;
  t->delta = delta;
  t->forward = delta + rows;
  t->moments = delta + 2 * rows;
  t->ams = (const float *)(delta + 2 * rows + n_moments);
  t->max_order = max_order;
  t->n_angles = n_angles;
  t->n_moments = n_moments;
  return mem;
}

void optics_table_release(sl_phase_table *t)
{
  free((void *)t->delta);
  memset(t, 0, sizeof *t);
}

int sl_phase_table_isotropic_order(const sl_phase_table *t, double tol)
{
  for (int n = 0; n <= t->max_order; ++n) {
    if (t->delta[n] >= tol) continue;
    const float *r = t->ams + (size_t)n * (size_t)t->n_angles;
    double worst = 0.0;
    for (int j = 0; j < t->n_angles; ++j) worst = fmax(worst, fabs(4.0 * SL_PI * r[j] - 1.0));
    if (worst < tol) return n;
  }
  return -1;
}
