#include "sl_size_distribution.h"

#include <math.h>

double sl_gamma_shape(const sl_gamma_distribution *d, double number_m3)
{
  const double per_cm3 = number_m3 * 1e-6;
  switch (d->rule) {
  case SL_SHAPE_MARTIN1994: {
    /* Morrison, Curry & Khvorostyanov 2005 (J. Atmos. Sci. 62, 1665), after Martin, Johnson &
     * Spice 1994's relative dispersion eta = 0.0005714 N + 0.2714 (N in cm^-3) of maritime and
     * continental stratocumulus: mu = 1 / eta^2 - 1, bounded to [2, 10] as their code does. */
    const double eta = 0.0005714 * per_cm3 + 0.2714;
    const double mu = 1.0 / (eta * eta) - 1.0;
    return mu < 2.0 ? 2.0 : (mu > 10.0 ? 10.0 : mu);
  }
  case SL_SHAPE_THOMPSON2008: {
    /* Thompson et al. 2008 (Mon. Wea. Rev. 136, 5095) and Thompson & Eidhammer 2014: mu is the
     * nearest integer to 1000 / N (N in cm^-3) plus 2, at most 15. */
    const double mu = nearbyint(1000.0 / per_cm3) + 2.0;
    return mu > 15.0 ? 15.0 : mu;
  }
  case SL_SHAPE_FIXED:
  default: return d->mu;
  }
}

double sl_gamma_slope(const sl_gamma_distribution *d, double mass_kg_m3, double number_m3)
{
  const double mu = sl_gamma_shape(d, number_m3);
  /* Gamma(mu + 4) / Gamma(mu + 1) = (mu + 1)(mu + 2)(mu + 3), exact for any real mu > -1. */
  const double ratio = (mu + 1.0) * (mu + 2.0) * (mu + 3.0);
  return cbrt(d->density_kg_m3 * M_PI / 6.0 * number_m3 * ratio / mass_kg_m3);
}

double sl_gamma_effective_radius(const sl_gamma_distribution *d, double mass_kg_m3, double number_m3)
{
  return 0.5 * (sl_gamma_shape(d, number_m3) + 3.0) / sl_gamma_slope(d, mass_kg_m3, number_m3);
}

double sl_gamma_number_from_intercept(const sl_gamma_distribution *d, double mass_kg_m3)
{
  if (!(d->fixed_intercept_m4 > 0.0) || !(mass_kg_m3 > 0.0)) return 0.0;
  const double mu = d->rule == SL_SHAPE_FIXED ? d->mu : 0.0;
  const double lambda = pow(d->density_kg_m3 * M_PI / 6.0 * d->fixed_intercept_m4 * tgamma(mu + 4.0) / mass_kg_m3,
                            1.0 / (mu + 4.0));
  return d->fixed_intercept_m4 * tgamma(mu + 1.0) / pow(lambda, mu + 1.0);
}
