/* The Narasimhan–Ramamoorthi–Nayar series, its single-scattering companion for T <= 1 and the
 * blended angular profile. Derivation checks and the printed-equation errata: docs/APSF.md. */
#include "sl_apsf.h"
#include "sl_guards.h"

#include <math.h>
#include <stdlib.h>

#include "sl_legendre.h"

double sl_apsf_chi(const sl_apsf_medium *m, int k)
{
  if (k < 0) return 0.0;
  if (m->chi) return k < m->n_chi ? m->chi[k] : 0.0;
  return k == 0 ? 1.0 : pow(m->q, (double)k);
}

double sl_apsf_phase(const sl_apsf_medium *m, double cos_scatter)
{
  if (!m->chi) return 4.0 * SL_PI * sl_hg_phase(m->q, cos_scatter); /* Narasimhan et al., eq. 11 */
  /* A truncated Legendre sum rings where the phase function is steep; negative lobes are not
   * light, so they are clipped. */
  const double p = 4.0 * SL_PI * sl_legendre_series(m->chi, m->n_chi, cos_scatter);
  return p > 0.0 ? p : 0.0;
}

double sl_apsf_alpha(int order) { return order + 1.0; }

double sl_apsf_beta(const sl_apsf_medium *m, int order)
{
  /* Narasimhan et al., eq. 25, with W_{m-1} / (2m - 1) = W0 chi_{m-1} (eq. 12 generalised). */
  const double mm = (double)order;
  return (2.0 * mm + 1.0) / mm * (1.0 - m->albedo * sl_apsf_chi(m, order - 1));
}

double sl_apsf_log_g(const sl_apsf_medium *m, int order, double T)
{
  /* Narasimhan et al., eq. 24 (I0 = 1), kept as a logarithm: T^{-(m+1)} under- or overflows
   * long before the product does. */
  return -sl_apsf_beta(m, order) * T - sl_apsf_alpha(order) * log(T);
}

/* Upper bound of |chi_k| over k >= k0: beta_m >= 2 (1 - W0 bound) for every m > k0. */
static double chi_tail_bound(const sl_apsf_medium *m, int k0)
{
  if (!m->chi) return k0 <= 0 ? 1.0 : pow(fabs(m->q), (double)k0);
  double b = 0.0;
  for (int k = k0 < 0 ? 0 : k0; k < m->n_chi; ++k)
    if (fabs(m->chi[k]) > b) b = fabs(m->chi[k]);
  return b > 1.0 ? 1.0 : b;
}

int sl_apsf_terms_needed(const sl_apsf_medium *m, double T, double tolerance)
{
  if (!(T > 1.0) || !(tolerance > 0.0)) return SL_APSF_MAX_TERMS + 1;
  /* All in logarithms: at large T with absorption the orders differ by e^{10^4} and more, and
   * g_1 need not be the largest. The kept sum S_M = sum_{l<M} (g_l + g_{l+1}) is S(T, 1) minus a
   * positive tail, and S(T, 1) = sum of all the (positive) coefficients is the largest |S|, so
   * bounding the tail by tolerance * S_M bounds the error by tolerance * max |S|. The tail,
   * for every mu:
   *   |sum_{l>=M} (g_l + g_{l+1}) L_l| <= 2 sum_{m>=M} g_m <= 2 e^{-b T} T^{-(M+1)} / (1 - 1/T),
   * with b = 2 (1 - W0 sup_{k>=M-1} |chi_k|) <= beta_m for all m >= M. */
  const double lnT = log(T), geometric = -log1p(-1.0 / T), log_tol = log(tolerance);
  double log_kept = -INFINITY, log_prev = -INFINITY; /* ln g_0 = -inf */
  for (int M = 1; M <= SL_APSF_MAX_TERMS; ++M) {
    /* Adds a_{M-1} = g_{M-1} + g_M. */
    const double log_next = sl_apsf_log_g(m, M, T);
    const double hi = fmax(log_prev, log_next), lo = fmin(log_prev, log_next);
    const double log_a = hi + log1p(exp(lo - hi));
    const double khi = fmax(log_kept, log_a), klo = fmin(log_kept, log_a);
    log_kept = khi + log1p(exp(klo - khi));
    log_prev = log_next;
    const double b = 2.0 * (1.0 - m->albedo * chi_tail_bound(m, M - 1));
    const double log_tail = log(2.0) - b * T - (M + 1.0) * lnT + geometric;
    if (log_tail <= log_tol + log_kept) return M;
    if (m->chi && M > m->n_chi + 8) {
      /* Past the table every chi is 0 and the bound only shrinks geometrically: jump. */
      const double jump = ceil((log_tail - log_tol - log_kept) / lnT) + M;
      return jump > SL_APSF_MAX_TERMS ? SL_APSF_MAX_TERMS + 1 : (int)jump;
    }
  }
  return SL_APSF_MAX_TERMS + 1;
}

int sl_apsf_series_init(sl_apsf_series *s, const sl_apsf_medium *m, double T, double tolerance, int terms,
                        sl_error *err)
{
  s->chi = NULL;
  s->terms = 0;
  s->T = T;
  s->tolerance = tolerance;
  if (!(T > 1.0) || !isfinite(T))
    return sl_fail(err, SL_ERR_ARG, "apsf: the series needs an optical thickness T > 1 (got %g)", T);
  if (!(m->albedo > 0.0 && m->albedo <= 1.0))
    return sl_fail(err, SL_ERR_ARG, "apsf: albedo must be in (0, 1] (got %g)", m->albedo);
  if (!m->chi && !(m->q > -1.0 && m->q < 1.0))
    return sl_fail(err, SL_ERR_ARG, "apsf: Henyey-Greenstein q must be in (-1, 1) (got %g)", m->q);
  if (m->chi && (m->n_chi < 1 || m->chi[0] != 1.0))
    return sl_fail(err, SL_ERR_ARG, "apsf: phase moments must start with chi_0 = 1 (%d given)", m->n_chi);
  if (terms <= 0) {
    if (!(tolerance > 0.0 && tolerance < 1.0))
      return sl_fail(err, SL_ERR_ARG, "apsf: tolerance must be in (0, 1) (got %g)", tolerance);
    terms = sl_apsf_terms_needed(m, T, tolerance);
    if (terms > SL_APSF_MAX_TERMS)
      return sl_fail(err, SL_ERR_ARG, "apsf: T = %.9g is too close to 1 for tolerance %g (more than %d terms)", T,
                     tolerance, SL_APSF_MAX_TERMS);
  }
  s->chi = malloc(sizeof(double) * (size_t)terms);
  if (!s->chi) return sl_fail(err, SL_ERR_NOMEM, "apsf: out of memory for %d terms", terms);
  s->terms = terms;
  /* Coefficients relative to the largest one, from logarithms: e^{-beta T} T^{-(m+1)} leaves
   * double's range at T in the hundreds when the medium absorbs, long before the shape does. */
  double log_prev = -INFINITY; /* ln g_0 */
  s->log_scale = -INFINITY;
  for (int l = 0; l < terms; ++l) {
    const double log_next = sl_apsf_log_g(m, l + 1, T);
    /* Narasimhan et al., eq. 27: the coefficient of L_l is g_l + g_{l+1}. */
    const double hi = fmax(log_prev, log_next), lo = fmin(log_prev, log_next);
    s->chi[l] = hi + log1p(exp(lo - hi)); /* ln(g_l + g_{l+1}) for now */
    if (s->chi[l] > s->log_scale) s->log_scale = s->chi[l];
    log_prev = log_next;
  }
  /* sl_legendre_series sums (2l+1)/(4 pi) chi_l P_l, hence the factor. */
  for (int l = 0; l < terms; ++l) s->chi[l] = 4.0 * SL_PI / (2.0 * l + 1.0) * exp(s->chi[l] - s->log_scale);
  return SL_OK;
}

double sl_apsf_series_shape(const sl_apsf_series *s, double mu)
{
  const double c = sl_clamp_cosine(mu);
  return sl_legendre_series(s->chi, s->terms, c);
}

double sl_apsf_series_eval(const sl_apsf_series *s, double mu) { return exp(s->log_scale) * sl_apsf_series_shape(s, mu); }

double sl_apsf_series_back_fraction(const sl_apsf_series *s)
{
  /* The coefficients are in render/optics' convention, where chi_0 is the integral over the
   * sphere, so its forward-hemisphere sum applies as it is. */
  return 1.0 - sl_legendre_forward_fraction(s->chi, s->terms) / s->chi[0];
}

void sl_apsf_series_free(sl_apsf_series *s)
{
  free(s->chi);
  s->chi = NULL;
  s->terms = 0;
}

/* 8-point Gauss–Legendre on [-1, 1]. */
static const double GL8_X[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                                0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
static const double GL8_W[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                                0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

double sl_apsf_single_scatter(const sl_apsf_medium *m, double T, double gamma)
{
  /* W0 int_0^inf P(cos Theta) e^{-(tau + t)} / tau^2 dt along the view ray (t from the camera,
   * tau from the source). With h = T sin(gamma), the closest approach of the ray to the source,
   * substituting the scattering angle Theta (from gamma at the camera to pi at infinity) gives
   * dt / tau^2 = dTheta / h and tau + t = T cos(gamma) + h tan(Theta / 2):
   *   S_ss = W0 / h int_gamma^pi P(cos Theta) exp(-T cos(gamma) - h tan(Theta / 2)) dTheta,
   * smooth but for the phase function's forward peak at the lower end. */
  if (!(gamma > 0.0)) return INFINITY;
  if (gamma >= SL_PI) gamma = SL_PI * (1.0 - 1e-12);
  const double h = T * sin(gamma), base = -T * cos(gamma);
  /* Panels shrink geometrically toward both ends: toward gamma (the forward peak of P and the
   * 1/h scale) and toward pi, where the path to infinity cuts off within about 2 h. */
  enum { PANELS = 20 };
  double edge[2 * PANELS + 3];
  const double mid_angle = 0.5 * (gamma + SL_PI), u_min = 1e-3 * fmin(h, 1.0);
  for (int k = 0; k <= PANELS; ++k) {
    edge[k] = gamma * pow(mid_angle / gamma, (double)k / PANELS);
    edge[2 * PANELS + 1 - k] = SL_PI - u_min * pow((SL_PI - mid_angle) / u_min, (double)k / PANELS);
  }
  edge[2 * PANELS + 2] = SL_PI;
  double sum = 0.0;
  for (int k = 0; k < 2 * PANELS + 2; ++k) {
    const double half = 0.5 * (edge[k + 1] - edge[k]), mid = 0.5 * (edge[k + 1] + edge[k]);
    for (int i = 0; i < 8; ++i) {
      const double th = mid + half * GL8_X[i];
      const double e = base - h * tan(0.5 * th);
      if (e < -745.0) continue;
      sum += half * GL8_W[i] * sl_apsf_phase(m, cos(th)) * exp(e);
    }
  }
  return m->albedo * sum / h;
}

int sl_apsf_profile_build(sl_apsf_profile *p, const sl_apsf_medium *m, double T, double tolerance,
                          double gamma_max, int n_samples, sl_error *err)
{
  p->weight = NULL;
  p->n = 0;
  p->T = T;
  p->terms = 0;
  if (!(T > 0.0) || !isfinite(T)) return sl_fail(err, SL_ERR_ARG, "apsf: optical thickness must be > 0 (got %g)", T);
  if (!(gamma_max > 0.0 && gamma_max <= SL_PI))
    return sl_fail(err, SL_ERR_ARG, "apsf: profile angle range must be in (0, pi] (got %g)", gamma_max);
  if (n_samples < 16) return sl_fail(err, SL_ERR_ARG, "apsf: profile needs at least 16 samples (got %d)", n_samples);
  if (!(m->albedo > 0.0 && m->albedo <= 1.0))
    return sl_fail(err, SL_ERR_ARG, "apsf: albedo must be in (0, 1] (got %g)", m->albedo);
  if (!m->chi && !(m->q > -1.0 && m->q < 1.0))
    return sl_fail(err, SL_ERR_ARG, "apsf: Henyey-Greenstein q must be in (-1, 1) (got %g)", m->q);
  if (m->chi && (m->n_chi < 1 || m->chi[0] != 1.0))
    return sl_fail(err, SL_ERR_ARG, "apsf: phase moments must start with chi_0 = 1 (%d given)", m->n_chi);
  double x = (T - SL_APSF_BLEND_LO) / (SL_APSF_BLEND_HI - SL_APSF_BLEND_LO);
  x = x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x);
  const double w = x * x * (3.0 - 2.0 * x);
  p->blend = w;
  p->direct = exp(-T); /* Narasimhan et al., eq. 30: the attenuated Dirac */
  const double s_frac = 1.0 - exp((3.0 * (1.0 - m->albedo) - 1.0) * T);
  p->series_scale = s_frac > 0.0 ? s_frac : 0.0;
  p->gamma_max = gamma_max;
  p->weight = malloc(sizeof(double) * (size_t)n_samples);
  if (!p->weight) return sl_fail(err, SL_ERR_NOMEM, "apsf: out of memory for the profile");
  p->n = n_samples;
  sl_apsf_series s = {0};
  if (w > 0.0) {
    if (sl_apsf_series_init(&s, m, T, tolerance, 0, err)) {
      sl_apsf_profile_free(p);
      return err ? err->code : SL_ERR_ARG;
    }
    p->terms = s.terms;
  }
  for (int i = 0; i < n_samples; ++i) {
    const double u = (double)i / (n_samples - 1);
    double gamma = gamma_max * u * u;
    double S = 0.0;
    if (w > 0.0) S += w * p->series_scale * sl_apsf_series_eval(&s, cos(gamma));
    if (w < 1.0) {
      /* The single-scattering 1/gamma spike at the source is flattened below the first sample. */
      if (i == 0) gamma = 0.5 * gamma_max / ((double)(n_samples - 1) * (n_samples - 1));
      S += (1.0 - w) * sl_apsf_single_scatter(m, T, gamma);
    }
    /* Radiance is not negative; the series can be where absorption is strong and T large
     * (docs/APSF.md, stability). */
    p->weight[i] = S > 0.0 ? sl_apsf_fluence_weight(T, S) : 0.0;
  }
  sl_apsf_series_free(&s);
  return SL_OK;
}

double sl_apsf_profile_eval(const sl_apsf_profile *p, double gamma)
{
  if (!(gamma >= 0.0) || gamma > p->gamma_max) return 0.0;
  const double u = sqrt(gamma / p->gamma_max) * (p->n - 1);
  int i = (int)u;
  if (i > p->n - 2) i = p->n - 2;
  const double f = u - i;
  return p->weight[i] + f * (p->weight[i + 1] - p->weight[i]);
}

void sl_apsf_profile_free(sl_apsf_profile *p)
{
  free(p->weight);
  p->weight = NULL;
  p->n = 0;
}

double sl_apsf_mu_outside(double D, double R, double gamma)
{
  /* Narasimhan et al., eq. 28: the law of sines in the triangle camera, centre, exit point; the
   * ray leaves the sphere at its near intersection, where the outward radial and the ray toward
   * the camera make the acute angle. */
  const double s = D / R * sin(gamma);
  if (!(D > R) || fabs(s) > 1.0 || cos(gamma) <= 0.0) return -2.0;
  return sqrt(1.0 - s * s);
}
