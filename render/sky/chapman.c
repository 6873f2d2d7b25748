/* Air mass of the path to the sun: flat earth (Riley eq. 12) and round earth (Chapman function).
 *
 * Round earth, exponential atmosphere of scale height H, point at radius r0 = R + z, sun at
 * zenith angle chi <= 90 deg. With x = r0 / H and lengths in units of H, the optical depth to the
 * sun is beta(z) H Ch(x, chi) with
 *   Ch(x, chi) = integral_0^inf exp(x - sqrt(x^2 + 2 x s cos(chi) + s^2)) ds.
 * Substituting the height gained, h = r(s) - x, and then h = w^2 (which removes the 1/sqrt(h)
 * singularity of the horizontal case) gives the smooth, bounded integrand
 *   Ch = integral_0^inf exp(-w^2) 2 w (x + w^2) / sqrt((x cos chi)^2 + w^2 (2x + w^2)) dw,
 * integrated here by adaptive Gauss-Kronrod (7/15 points). docs/SKY.md compares it with the flat
 * air mass. */
#include <math.h>

#include "sl_sky.h"

static const double kKronrodNodes[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
static const double kKronrodWeights[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
static const double kGaussWeights[4] = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

typedef struct chapman_args {
  double x, a; /* a = x cos(chi) */
} chapman_args;

static double chapman_integrand(const chapman_args *p, double w)
{
  /* hypot: a^2 and w^2 underflow for a sun a hair above the horizon (cos chi ~ 1e-300). */
  double w2 = w * w;
  return exp(-w2) * 2.0 * w * (p->x + w2) / hypot(p->a, w * sqrt(2.0 * p->x + w2));
}

/* One 15-point Kronrod estimate on [lo, hi] and its difference from the embedded 7-point Gauss. */
static double gauss_kronrod(const chapman_args *p, double lo, double hi, double *error)
{
  double half = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
  double fc = chapman_integrand(p, mid);
  double kronrod = fc * kKronrodWeights[7], gauss = fc * kGaussWeights[3];
  for (int j = 0; j < 7; ++j) {
    double f = chapman_integrand(p, mid - half * kKronrodNodes[j]) +
               chapman_integrand(p, mid + half * kKronrodNodes[j]);
    kronrod += kKronrodWeights[j] * f;
    if (j % 2 == 1) gauss += kGaussWeights[j / 2] * f;
  }
  *error = fabs((kronrod - gauss) * half);
  return kronrod * half;
}

/* Global adaptive quadrature with a fixed budget: bisect the interval with the largest error
 * estimate until the total is below tol, the error is at round-off level, or the budget is spent.
 * Bounded work for every input, unlike recursion with a halving tolerance. */
#define CHAPMAN_MAX_PANELS 64
static double adaptive(const chapman_args *p, double lo, double hi, double tol)
{
  double a[CHAPMAN_MAX_PANELS], b[CHAPMAN_MAX_PANELS], v[CHAPMAN_MAX_PANELS], e[CHAPMAN_MAX_PANELS];
  int n = 1;
  a[0] = lo, b[0] = hi;
  v[0] = gauss_kronrod(p, lo, hi, &e[0]);
  for (;;) {
    double total = 0.0, error = 0.0;
    int worst = 0;
    for (int i = 0; i < n; ++i) {
      total += v[i], error += e[i];
      if (e[i] > e[worst]) worst = i;
    }
    if (error <= tol || error <= 1e-15 * fabs(total) || n + 1 > CHAPMAN_MAX_PANELS) return total;
    double mid = 0.5 * (a[worst] + b[worst]);
    a[n] = mid, b[n] = b[worst];
    v[n] = gauss_kronrod(p, mid, b[worst], &e[n]);
    b[worst] = mid;
    v[worst] = gauss_kronrod(p, a[worst], mid, &e[worst]);
    ++n;
  }
}

double sl_chapman(double x, double cos_zenith)
{
  if (!(cos_zenith > 0.0)) cos_zenith = 0.0;
  if (cos_zenith > 1.0) cos_zenith = 1.0;
  chapman_args p = {x, x * cos_zenith};
  /* exp(-w^2) < 1e-18 beyond w = 6.5 and the rest of the integrand is at most sqrt(2x + w^2). */
  const double top = 6.5;
  /* The integrand turns over at w ~ x cos(chi) / sqrt(2x); split there so both pieces are smooth
   * on their own scale. */
  double knee = p.a / sqrt(2.0 * x);
  double total;
  if (knee > 0.0 && knee < top)
    total = adaptive(&p, 0.0, knee, 1e-13) + adaptive(&p, knee, top, 1e-13);
  else
    total = adaptive(&p, 0.0, top, 1e-13);
  return total;
}

double sl_sky_airmass(const sl_atmosphere *atm, double z, double cos_zenith)
{
  if (!(cos_zenith > 0.0)) return INFINITY; /* night */
  if (atm->earth == SL_EARTH_ROUND)
    return sl_chapman((atm->earth_radius + z) / atm->scale_height, cos_zenith);
  return 1.0 / cos_zenith; /* Riley et al. 2004, eq. 12: 1 / l_y */
}
