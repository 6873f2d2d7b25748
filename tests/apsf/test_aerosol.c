/* The haze aerosol (render/optics/aerosol.c) against values from outside its quadrature:
 *   1. an independent quadrature of the same distribution (Simpson in log10 r over +-6 sigma,
 *      3001 nodes per mode, sl_mie per radius) for <C_ext>, <C_sca>, g at 440-650 nm;
 *   2. the Rayleigh limit of a tiny-particle lognormal, in closed form through the lognormal's
 *      moments <r^n> = r_g^n exp(n^2 s^2 / 2) (s = sigma_log10 ln 10):
 *      <C_sca> = (8 pi / 3) k^4 |K|^2 <r^6>, <C_abs> = 4 pi k Im(K) <r^3>, K = (m^2 - 1)/(m^2 + 2),
 *      g -> 0 (Bohren & Huffman 1983, eqs. 5.8-5.9 with m_im >= 0 absorbing);
 *   3. the large-particle limit: Q_ext -> 2 (the extinction paradox), <C_ext> -> 2 pi <r^2>;
 *   4. Koschmieder: -ln(0.02) = 3.912023.
 * And it prints the rural model's optics per wavelength (docs/APSF.md, "Haze"). */
#include <complex.h>
#include <math.h>
#include <stdio.h>

#include "sl_aerosol.h"
#include "sl_mie.h"
#include "sl_testing.h"

#define PI 3.14159265358979323846

static void independent(const sl_aerosol_model *m, double wl_nm, double *ext, double *sca, double *g)
{
  const double k = 2.0 * PI / (wl_nm * 1e-9);
  double e = 0.0, s = 0.0, sg = 0.0, norm = 0.0;
  for (int i = 0; i < m->n_modes; ++i) {
    const sl_lognormal_mode *md = &m->modes[i];
    const int n = 3000; /* intervals, even */
    const double lo = log10(md->median_radius_m) - 6.0 * md->sigma_log10, h = 12.0 * md->sigma_log10 / n;
    for (int j = 0; j <= n; ++j) {
      const double u = lo + j * h, r = pow(10.0, u);
      const double z = (u - log10(md->median_radius_m)) / md->sigma_log10;
      const double simpson = (j == 0 || j == n) ? 1.0 : (j % 2 ? 4.0 : 2.0);
      const double w = md->number_fraction * simpson * h / 3.0 * exp(-0.5 * z * z) / (md->sigma_log10 * sqrt(2.0 * PI));
      sl_mie_efficiencies q;
      sl_error err;
      sl_mie(k * r, m->m_re, m->m_im, NULL, 0, &q, NULL, NULL, NULL, &err);
      e += w * PI * r * r * q.qext, s += w * PI * r * r * q.qsca, sg += w * PI * r * r * q.qsca * q.g;
      norm += w;
    }
  }
  *ext = e / norm, *sca = s / norm, *g = sg / s;
}

int main(void)
{
  sl_error err = {0};
  const sl_aerosol_model *rural = sl_aerosol_rural();
  const double wls[4] = {440.0, 515.0, 550.0, 650.0};
  printf("rural aerosol (%s)\n", rural->source);
  for (int i = 0; i < 4; ++i) {
    sl_aerosol_optics o;
    CHECK(sl_aerosol_optics_compute(rural, wls[i], 0, &o, &err) == SL_OK);
    double e, s, g;
    independent(rural, wls[i], &e, &s, &g);
    printf("  %3.0f nm: C_ext %.5e m^2 (independent %.5e), W0 %.4f (%.4f), g %.4f (%.4f)\n", wls[i], o.extinction_m2, e,
           o.albedo, s / e, o.asymmetry, g);
    CHECK_CLOSE(o.extinction_m2, e, 1e-3, 0.0);
    CHECK_CLOSE(o.albedo, s / e, 1e-3, 0.0);
    CHECK_CLOSE(o.asymmetry, g, 1e-3, 0.0);
    /* Physical ranges for a weakly absorbing accumulation-mode aerosol. */
    CHECK(o.albedo > 0.85 && o.albedo < 1.0 && o.asymmetry > 0.5 && o.asymmetry < 0.8);
  }
  /* Haze reddens: more extinction in blue (Angstrom exponent between 0.5 and 2 for continental
   * aerosol). */
  {
    sl_aerosol_optics b, r;
    sl_aerosol_optics_compute(rural, 440.0, 0, &b, &err);
    sl_aerosol_optics_compute(rural, 650.0, 0, &r, &err);
    const double angstrom = log(b.extinction_m2 / r.extinction_m2) / log(650.0 / 440.0);
    printf("  Angstrom exponent 440-650 nm: %.3f\n", angstrom);
    CHECK(angstrom > 0.5 && angstrom < 2.0);
  }

  /* Rayleigh limit: radius 1 nm, sigma_log10 0.1, at 550 nm (x ~ 0.011). */
  {
    const sl_aerosol_model tiny = {"tiny", "test", 1, {{1e-9, 0.1, 1.0}}, 1.53, 0.0066};
    sl_aerosol_optics o;
    CHECK(sl_aerosol_optics_compute(&tiny, 550.0, 0, &o, &err) == SL_OK);
    const double k = 2.0 * PI / 550e-9, s = 0.1 * log(10.0);
    const double complex m = 1.53 + 0.0066 * I, K = (m * m - 1.0) / (m * m + 2.0);
    const double r6 = pow(1e-9, 6) * exp(18.0 * s * s), r3 = pow(1e-9, 3) * exp(4.5 * s * s);
    const double csca = 8.0 * PI / 3.0 * pow(k, 4) * cabs(K) * cabs(K) * r6, cabs_ = 4.0 * PI * k * cimag(K) * r3;
    CHECK_CLOSE(o.scattering_m2, csca, 5e-3, 0.0);
    CHECK_CLOSE(o.extinction_m2 - o.scattering_m2, cabs_, 5e-3, 0.0);
    CHECK(fabs(o.asymmetry) < 1e-3);
  }
  /* Large particles: radius 200 um, narrow, weakly absorbing: <C_ext> = 2 pi <r^2> to a few 1e-3
   * (Q_ext - 2 falls as x^{-2/3}; x ~ 2300). */
  {
    const sl_aerosol_model big = {"big", "test", 1, {{200e-6, 0.02, 1.0}}, 1.33, 1e-8};
    sl_aerosol_optics o;
    CHECK(sl_aerosol_optics_compute(&big, 550.0, 64, &o, &err) == SL_OK);
    const double s = 0.02 * log(10.0), r2 = 200e-6 * 200e-6 * exp(2.0 * s * s);
    CHECK_CLOSE(o.extinction_m2, 2.0 * PI * r2, 1e-2, 0.0);
  }
  CHECK_CLOSE(sl_koschmieder_extinction(1000.0), 3.912023e-3, 1e-6, 0.0);
  CHECK(sl_aerosol_optics_compute(rural, -5.0, 0, &(sl_aerosol_optics){0}, &err) != SL_OK);
  return sl_test_finish("test_aerosol");
}
