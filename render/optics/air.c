/* Air molecules: Rayleigh scattering (Riley et al. 2004, eq. 1, and Table 2's cross-sections). */
#include "sl_air.h"

#include <math.h>

#include "sl_legendre.h"

double sl_air_cross_section(double wavelength_nm)
{
  /* Bodhaine, Wood, Dutton & Slusser 1999, J. Atmos. Ocean. Tech. 16, 1854, eq. 29: Rayleigh
   * cross-section of dry air with 360 ppm CO2, in 1e-28 cm^2 with lambda in um. It gives
   * 2.28e-31 m^2 at 650 nm as Riley et al.'s Table 2 does, but 5.9e-31 at 515 nm and 1.13e-30
   * at 440 nm where Table 2 lists 5.33e-31 and 1.30e-30 (Table 2 is not a lambda^-4 law). */
  const double l = wavelength_nm / 1000.0, l2 = l * l;
  const double sigma_1e28_cm2 = (1.0455996 - 341.29061 / l2 - 0.90230850 * l2) / (1.0 + 0.0027059889 / l2 - 85.968563 * l2);
  return sigma_1e28_cm2 * 1e-28 * 1e-4;
}

double sl_rayleigh_phase(double cos_theta)
{
  /* Riley et al. 2004, eq. 1 */
  return 3.0 / (16.0 * SL_PI) * (1.0 + cos_theta * cos_theta);
}

double sl_rayleigh_ams(int n, double cos_theta)
{
  if (n <= 0) return 0.0;
  const double p2 = 0.5 * (3.0 * cos_theta * cos_theta - 1.0);
  return (1.0 + 5.0 * pow(0.1, n) * p2) / (4.0 * SL_PI);
}
