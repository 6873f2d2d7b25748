/* The exponential Rayleigh atmosphere (Riley et al. 2004, eqs. 9-10, Table 3) and its
 * wavelength-dependent sea-level scattering coefficients. */
#include <math.h>
#include <string.h>

#include "sl_sky.h"

const double sl_sky_rgb_wavelengths_nm[SL_SKY_RGB_COUNT] = {650.0, 515.0, 440.0};

void sl_sky_spectral_wavelengths(double out_nm[SL_SKY_SPECTRAL_COUNT])
{
  for (int i = 0; i < SL_SKY_SPECTRAL_COUNT; ++i)
    out_nm[i] = 380.0 + (720.0 - 380.0) * i / (SL_SKY_SPECTRAL_COUNT - 1);
}

/* Standard air of Bodhaine et al. 1999: 288.15 K, 1013.25 hPa. */
static const double kStandardAirDensity = 2.546899e25; /* molecules m^-3 */
static const double kCO2 = 360e-6;                     /* volume mixing ratio */

/* Refractive index of standard air: Peck & Reeder 1972 for 300 ppm CO2, scaled to kCO2 as in
 * Bodhaine et al. 1999, eqs. 17-18. */
static double standard_air_refractivity(double wavelength_um)
{
  double s2 = 1.0 / (wavelength_um * wavelength_um);
  double n300 = 1e-8 * (8060.51 + 2480990.0 / (132.274 - s2) + 17455.7 / (39.32957 - s2));
  return n300 * (1.0 + 0.54 * (kCO2 - 0.0003));
}

/* King factor (6 + 3 rho) / (6 - 7 rho) of air: Bates 1984 per gas, weighted by volume as in
 * Bodhaine et al. 1999, eqs. 22-23. */
static double king_factor(double wavelength_um)
{
  double l2 = wavelength_um * wavelength_um;
  double f_n2 = 1.034 + 3.17e-4 / l2;
  double f_o2 = 1.096 + 1.385e-3 / l2 + 1.448e-4 / (l2 * l2);
  double f_ar = 1.00, f_co2 = 1.15;
  double c = kCO2 * 100.0; /* percent */
  return (78.084 * f_n2 + 20.946 * f_o2 + 0.934 * f_ar + c * f_co2) / (78.084 + 20.946 + 0.934 + c);
}

double sl_rayleigh_cross_section(double wavelength_nm)
{
  /* Bodhaine et al. 1999, eq. 2: sigma = 24 pi^3 (n^2-1)^2 / (lambda^4 N^2 (n^2+2)^2) F_air. */
  const double pi = 3.14159265358979323846;
  double um = wavelength_nm * 1e-3, lambda = wavelength_nm * 1e-9;
  double nm1 = standard_air_refractivity(um);
  double n2m1 = nm1 * (2.0 + nm1), n2p2 = 3.0 + n2m1;
  double ratio = n2m1 / n2p2;
  double l2 = lambda * lambda;
  return 24.0 * pi * pi * pi * ratio * ratio /
         (l2 * l2 * kStandardAirDensity * kStandardAirDensity) * king_factor(um);
}

double sl_rayleigh_beta_standard_air(double wavelength_nm)
{
  return kStandardAirDensity * sl_rayleigh_cross_section(wavelength_nm);
}

/* Riley et al. 2004, Table 3 (their wavelengths; see docs/SKY.md on Table 2's labels). */
static double riley_table3_beta(double wavelength_nm)
{
  static const double lam[3] = {440.0, 550.0, 680.0};
  static const double beta[3] = {3.31e-5, 1.35e-5, 5.8e-6};
  int i = wavelength_nm < lam[1] ? 0 : 1;
  double slope = log(beta[i + 1] / beta[i]) / log(lam[i + 1] / lam[i]);
  if (wavelength_nm < lam[0]) i = 0, slope = -4.0;
  if (wavelength_nm > lam[2]) i = 2, slope = -4.0;
  return beta[i] * pow(wavelength_nm / lam[i], slope);
}

int sl_atmosphere_init(sl_atmosphere *atm, const double *wavelength_nm, int count,
                       sl_earth_model earth, sl_rayleigh_source rayleigh, sl_error *err)
{
  if (!atm || !wavelength_nm) return sl_fail(err, SL_ERR_ARG, "sky: atmosphere or wavelengths is NULL");
  if (count < 1 || count > SL_SKY_MAX_WAVELENGTHS)
    return sl_fail(err, SL_ERR_ARG, "sky: %d wavelengths (1..%d allowed)", count, SL_SKY_MAX_WAVELENGTHS);
  if (earth != SL_EARTH_FLAT && earth != SL_EARTH_ROUND)
    return sl_fail(err, SL_ERR_ARG, "sky: unknown earth model %d", (int)earth);
  if (rayleigh != SL_RAYLEIGH_BODHAINE1999 && rayleigh != SL_RAYLEIGH_RILEY2004)
    return sl_fail(err, SL_ERR_ARG, "sky: unknown Rayleigh source %d", (int)rayleigh);
  memset(atm, 0, sizeof *atm);
  for (int i = 0; i < count; ++i) {
    double w = wavelength_nm[i];
    if (!(w >= 380.0 && w <= 1000.0))
      return sl_fail(err, SL_ERR_ARG, "sky: wavelength %g nm outside 380..1000 nm", w);
    atm->wavelength_nm[i] = w;
    atm->beta_sea_level[i] =
        rayleigh == SL_RAYLEIGH_RILEY2004 ? riley_table3_beta(w) : sl_rayleigh_beta_standard_air(w);
    atm->sun_irradiance[i] = 1.0;
  }
  atm->count = count;
  atm->scale_height = 8000.0;
  atm->earth_radius = 6371000.0;
  atm->ground_radius = 0.0;
  atm->earth = earth;
  atm->rayleigh = rayleigh;
  return SL_OK;
}
