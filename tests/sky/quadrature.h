/* Test-side reference for the sky: eq. 8 of Riley et al. 2004 integrated numerically, with its
 * ingredients (eqs. 10-12) written straight from the paper. Independent of render/sky's closed
 * forms: only the scalar parameters are shared. */
#ifndef SL_SKY_TEST_QUADRATURE_H
#define SL_SKY_TEST_QUADRATURE_H

#include <math.h>

typedef struct ref_sky {
  double beta_sl, gamma, z_eye, mu, airmass, phase;
} ref_sky;

/* Riley eq. 11 as printed (with expm1 so the reference itself stays accurate), eye to distance t. */
static inline double ref_transparency(const ref_sky *s, double t)
{
  double beta_eye = s->beta_sl * exp(-s->gamma * s->z_eye);
  double depth = s->mu == 0.0 ? beta_eye * t : beta_eye * -expm1(-s->gamma * s->mu * t) / (s->gamma * s->mu);
  return exp(-depth);
}

/* Integrand of eq. 8: T(eye, s') beta(s') P L(s'), with eq. 10 and eq. 12 (air mass m = 1/l_y). */
static inline double ref_integrand(const ref_sky *s, double t)
{
  double z = s->z_eye + s->mu * t;
  double beta = s->beta_sl * exp(-s->gamma * z);
  double sun = exp(-beta * s->airmass / s->gamma);
  return ref_transparency(s, t) * beta * s->phase * sun;
}

static const double kXk[8] = {0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                              0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                              0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                              0.207784955007898467600689403773245, 0.0};
static const double kWk[8] = {0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                              0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                              0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                              0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
static const double kWg[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                              0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

typedef double (*ref_fn)(const void *ctx, double t);

static inline double ref_gk15(ref_fn f, const void *ctx, double a, double b, double *err)
{
  double h = 0.5 * (b - a), c = 0.5 * (a + b);
  double fc = f(ctx, c), k = fc * kWk[7], g = fc * kWg[3];
  for (int j = 0; j < 7; ++j) {
    double v = f(ctx, c - h * kXk[j]) + f(ctx, c + h * kXk[j]);
    k += kWk[j] * v;
    if (j % 2 == 1) g += kWg[j / 2] * v;
  }
  *err = fabs((k - g) * h);
  return k * h;
}

/* Global adaptive bisection with a bounded number of panels (bounded work for every input). */
#define REF_MAX_PANELS 400
static inline double ref_adaptive(ref_fn f, const void *ctx, double lo, double hi, double tol)
{
  static double a[REF_MAX_PANELS], b[REF_MAX_PANELS], v[REF_MAX_PANELS], e[REF_MAX_PANELS];
  int n = 1;
  a[0] = lo, b[0] = hi;
  v[0] = ref_gk15(f, ctx, lo, hi, &e[0]);
  for (;;) {
    double total = 0.0, error = 0.0;
    int worst = 0;
    for (int i = 0; i < n; ++i) {
      total += v[i], error += e[i];
      if (e[i] > e[worst]) worst = i;
    }
    if (error <= tol || error <= 1e-15 * fabs(total) || n + 1 > REF_MAX_PANELS) return total;
    double mid = 0.5 * (a[worst] + b[worst]);
    a[n] = mid, b[n] = b[worst];
    v[n] = ref_gk15(f, ctx, mid, b[worst], &e[n]);
    b[worst] = mid;
    v[worst] = ref_gk15(f, ctx, a[worst], mid, &e[worst]);
    ++n;
  }
}

/* Integral of f over [0, end] (end may be infinite): decades as breakpoints, a coarse pass for
 * the scale, then adaptive Gauss-Kronrod to rel_tol of the total. */
static inline double ref_integrate(ref_fn f, const void *ctx, double end, double rel_tol)
{
  double cuts[40];
  int n = 0;
  cuts[n++] = 0.0;
  for (double d = 1e-3; d < end && n < 38; d *= 10.0) cuts[n++] = d;
  if (isinf(end)) end = cuts[n - 1] * 10.0;
  cuts[n++] = end;
  double scale = 0.0, err;
  for (int i = 0; i + 1 < n; ++i) scale += fabs(ref_gk15(f, ctx, cuts[i], cuts[i + 1], &err));
  double total = 0.0;
  for (int i = 0; i + 1 < n; ++i) total += ref_adaptive(f, ctx, cuts[i], cuts[i + 1], rel_tol * scale / (n - 1));
  return total;
}

static inline double ref_sky_fn(const void *ctx, double t) { return ref_integrand((const ref_sky *)ctx, t); }

/* The end of the integral: K itself, the ground for downward rays, and for an infinite upward ray
 * the height where the air (and everything it could add) has fallen by exp(-80). */
static inline double ref_sky_end(const ref_sky *s, double K)
{
  if (s->mu < 0.0) {
    double ground = s->z_eye > 0.0 ? s->z_eye / -s->mu : 0.0;
    return K < ground ? K : ground;
  }
  if (isinf(K) && s->mu > 0.0) {
    double beta_eye = s->beta_sl * exp(-s->gamma * s->z_eye);
    /* rise until beta * max(1, m / gamma) < exp(-80) * beta_eye * min(1, ...) */
    double extra = log(fmax(1.0, s->airmass / s->gamma * beta_eye));
    return (80.0 + extra) / (s->gamma * s->mu);
  }
  return K;
}

static inline double ref_sky_radiance(const ref_sky *s, double K, double rel_tol)
{
  double end = ref_sky_end(s, K);
  if (!(end > 0.0)) return 0.0;
  return ref_integrate(ref_sky_fn, s, end, rel_tol);
}

#endif
