#include "sl_legendre.h"

#include <math.h>

double sl_hg_phase(double g, double mu)
{
  /* Henyey & Greenstein 1941, ApJ 93, 70. */
  const double d = 1.0 + g * g - 2.0 * g * mu;
  return (1.0 - g * g) / (4.0 * SL_PI * d * sqrt(d));
}

double sl_legendre_series(const double *chi, int n_moments, double mu)
{
  /* Clenshaw recurrence for sum c_l P_l with P_{l+1} = ((2l+1) mu P_l - l P_{l-1}) / (l+1). */
  double b1 = 0.0, b2 = 0.0;
  for (int l = n_moments - 1; l >= 0; --l) {
    const double c = (2.0 * l + 1.0) / (4.0 * SL_PI) * chi[l];
    const double alpha = (2.0 * l + 1.0) / (l + 1.0) * mu;
    const double beta = (l + 1.0) / (l + 2.0);
    const double b0 = c + alpha * b1 - beta * b2;
    b2 = b1;
    b1 = b0;
  }
  return b1;
}

void sl_legendre_moments_gauss(const double *nodes, const double *weights, const double *values, int n_nodes,
                               int n_moments, double *chi)
{
  for (int l = 0; l < n_moments; ++l) chi[l] = 0.0;
  for (int i = 0; i < n_nodes; ++i) {
    const double x = nodes[i], wv = 2.0 * SL_PI * weights[i] * values[i];
    double p0 = 1.0, p1 = x;
    chi[0] += wv;
    if (n_moments > 1) chi[1] += wv * x;
    for (int l = 2; l < n_moments; ++l) {
      const double p2 = ((2.0 * l - 1.0) * x * p1 - (l - 1.0) * p0) / l;
      chi[l] += wv * p2;
      p0 = p1;
      p1 = p2;
    }
  }
}

double sl_legendre_forward_fraction(const double *chi, int n_moments)
{
  /* int_0^1 P_l dmu = (P_{l-1}(0) - P_{l+1}(0)) / (2l+1) for l >= 1 (from (2l+1) P_l =
   * P'_{l+1} - P'_{l-1}); P_k(0) vanishes for odd k, so only odd l contribute. */
  double sum = 0.5 * chi[0];
  double p_even = 1.0; /* P_{l-1}(0) for l = 1 */
  for (int l = 1; l < n_moments; l += 2) {
    const double p_next = -p_even * (double)l / (l + 1.0); /* P_{l+1}(0) = -l/(l+1) P_{l-1}(0) */
    sum += 0.5 * chi[l] * (p_even - p_next);
    p_even = p_next;
  }
  return sum;
}
