#include "sl_refractive.h"

#include <math.h>

#include "sl_legendre.h"

double sl_water_index_re(double wavelength_nm, double temperature_k, double density_kg_m3)
{
  /* Relative to vacuum. */
  /* IAPWS R9-97, "Release on the refractive index of ordinary water substance as a function of
   * wavelength, temperature and pressure" (Harvey, Gallagher & Levelt Sengers 1998,
   * J. Phys. Chem. Ref. Data 27, 761), eq. A1 with its table of coefficients. Valid
   * 0.2-1.1 um, 261-773 K. Checked in tests against the release's own test value. */
  static const double a[8] = {0.244257733,    9.74634476e-3, -3.73234996e-3, 2.68678472e-4,
                              1.58920570e-3,  2.45934259e-3, 0.900704920,    -1.66626219e-2};
  const double lambda_uv = 0.2292020, lambda_ir = 5.432937;
  const double rho = density_kg_m3 / 1000.0, t = temperature_k / 273.15;
  const double l = wavelength_nm / 589.0, l2 = l * l;
  const double A = rho * (a[0] + a[1] * rho + a[2] * t + a[3] * l2 * t + a[4] / l2 + a[5] / (l2 - lambda_uv * lambda_uv) +
                          a[6] / (l2 - lambda_ir * lambda_ir) + a[7] * rho * rho);
  return sqrt((2.0 * A + 1.0) / (1.0 - A));
}

double sl_water_index_im(double wavelength_nm)
{
  /* Hale & Querry 1973, Appl. Opt. 12, 555, Table I (25 C), 0.400-0.750 um every 25 nm;
   * log-linear interpolation, held constant outside. */
  static const double k[15] = {1.86e-9, 1.30e-9, 1.02e-9, 9.35e-10, 1.00e-9, 1.32e-9, 1.96e-9, 3.60e-9,
                               1.09e-8, 1.39e-8, 1.64e-8, 2.23e-8, 3.35e-8, 9.15e-8, 1.56e-7};
  const double u = (wavelength_nm - 400.0) / 25.0;
  if (u <= 0.0) return k[0];
  if (u >= 14.0) return k[14];
  const int i = (int)u;
  const double w = u - i;
  return exp((1.0 - w) * log(k[i]) + w * log(k[i + 1]));
}

void sl_water_index(double wavelength_nm, double *re, double *im)
{
  /* 10 C: a typical temperature of liquid cloud and rain; density of water at 10 C,
   * 999.70 kg/m3 (IAPWS-95). The temperature shifts n by ~1e-4 per 10 K. */
  /* IAPWS gives the index relative to vacuum; scattering in air needs it relative to air,
   * whose index is 1.00028 at sea level in the visible (Edlen 1966, Metrologia 2, 71). */
  *re = sl_water_index_re(wavelength_nm, 283.15, 999.70) / 1.00028;
  *im = sl_water_index_im(wavelength_nm);
}

void sl_ice_index(double wavelength_nm, double *re, double *im)
{
  /* Cauchy form n = A + B / lambda^2 (lambda in um), A = 1.3002, B = 0.00320 um^2, chosen to
   * follow the real index of ice Ih in Warren & Brandt 2008 (J. Geophys. Res. 113, D14220;
   * data at www.atmos.washington.edu/ice_optical_constants) across 400-700 nm, where it falls
   * from about 1.320 to 1.307 (1.3098 at the sodium D line). The coefficients were fitted to
   * values recalled from that table, not read from the file in this session: treat them as
   * good to about 1e-3 (see docs/OPTICS.md). Halo angles move by 0.1 degree per 0.001 in n.
   * Imaginary part: Warren & Brandt 2008 give ~1e-9 to 1e-8 in the visible; we use 2e-9, which
   * absorbs less than 1e-4 over a 1 mm path. */
  const double l = wavelength_nm / 1000.0;
  *re = 1.3002 + 0.00320 / (l * l);
  *im = 2e-9;
}

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
