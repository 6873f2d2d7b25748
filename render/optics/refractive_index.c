#include "sl_refractive.h"

#include <complex.h>
#include <math.h>


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
  /* Ice Ih, Warren & Brandt 2008 (J. Geophys. Res. 113, D14220), their compiled table
   * (www.atmos.washington.edu/ice_optical_constants, as redistributed in CRREL-GOSRT's
   * Materials/ice_Ri.csv), 0.39-0.73 um every 10 nm; linear in lambda for the real part,
   * log-linear for the imaginary part, held constant outside. */
  static const double m_re[35] = {1.3203, 1.3194, 1.3185, 1.3177, 1.3170, 1.3163, 1.3157, 1.3151, 1.3145,
                                  1.3140, 1.3135, 1.3130, 1.3126, 1.3121, 1.3117, 1.3114, 1.3110, 1.3106,
                                  1.3103, 1.3100, 1.3097, 1.3094, 1.3091, 1.3088, 1.3085, 1.3083, 1.3080,
                                  1.3078, 1.3076, 1.3073, 1.3071, 1.3069, 1.3067, 1.3065, 1.3062};
  static const double m_im[35] = {2.00e-11, 2.37e-11, 2.67e-11, 3.14e-11, 4.14e-11, 6.27e-11, 9.24e-11,
                                  1.33e-10, 1.96e-10, 2.86e-10, 4.17e-10, 5.89e-10, 8.04e-10, 1.08e-9,
                                  1.41e-9,  1.81e-9,  2.29e-9,  2.84e-9,  3.46e-9,  4.16e-9,  4.93e-9,
                                  5.73e-9,  6.89e-9,  8.58e-9,  1.04e-8,  1.22e-8,  1.43e-8,  1.66e-8,
                                  1.89e-8,  2.09e-8,  2.40e-8,  2.90e-8,  3.44e-8,  4.03e-8,  4.30e-8};
  const double u = (wavelength_nm - 390.0) / 10.0;
  if (u <= 0.0) {
    *re = m_re[0];
    *im = m_im[0];
    return;
  }
  if (u >= 34.0) {
    *re = m_re[34];
    *im = m_im[34];
    return;
  }
  const int i = (int)u;
  const double w = u - i;
  *re = (1.0 - w) * m_re[i] + w * m_re[i + 1];
  *im = exp((1.0 - w) * log(m_im[i]) + w * log(m_im[i + 1]));
}

void sl_bruggeman_index(double f1, double re1, double im1, double re2, double im2, double *re, double *im)
{
  /* Multiplying out the two fractions gives a quadratic, -2 eps^2 + b eps + eps1 eps2 = 0 with
   * b = (3 f1 - 1) eps1 + (3 f2 - 1) eps2 and f2 = 1 - f1. Its two roots have a product
   * -eps1 eps2 / 2, so for non-absorbing components one is negative (unphysical); the other,
   * (b + sqrt(b^2 + 8 eps1 eps2)) / 4 with the square root in the right half-plane, is the
   * medium, and it tends to eps1 or eps2 as f1 goes to 1 or 0. */
  const double complex m1 = re1 + im1 * I, m2 = re2 + im2 * I;
  const double complex e1 = m1 * m1, e2 = m2 * m2;
  const double f2 = 1.0 - f1;
  const double complex b = (3.0 * f1 - 1.0) * e1 + (3.0 * f2 - 1.0) * e2;
  double complex root = csqrt(b * b + 8.0 * e1 * e2);
  if (creal(root) < 0.0) root = -root;
  const double complex eps = (b + root) / 4.0;
  double complex m = csqrt(eps);
  if (creal(m) < 0.0) m = -m;
  *re = creal(m);
  *im = fabs(cimag(m));
}

void sl_rimed_ice_index(double wavelength_nm, double density_kg_m3, double *re, double *im)
{
  double ice_re, ice_im;
  sl_ice_index(wavelength_nm, &ice_re, &ice_im);
  const double f = density_kg_m3 >= SL_SOLID_ICE_DENSITY ? 1.0 : density_kg_m3 / SL_SOLID_ICE_DENSITY;
  sl_bruggeman_index(f, ice_re, ice_im, 1.0, 0.0, re, im);
}
