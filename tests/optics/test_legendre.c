/* Legendre machinery against closed forms: HG moments are g^l (Henyey & Greenstein 1941), the
 * convolution of HG(g1) and HG(g2) is HG(g1 g2), Rayleigh's moments are 1, 0, 1/10. */
#include <math.h>
#include <stdlib.h>

#include "sl_legendre.h"
#include "sl_air.h"
#include "sl_testing.h"

#define NODES 400
#define MOMENTS 120

int main(void)
{
  static double x[NODES], w[NODES], v[NODES], chi1[MOMENTS], chi2[MOMENTS], prod[MOMENTS];
  sl_gauss_legendre(NODES, x, w);
  double wsum = 0.0;
  for (int i = 0; i < NODES; ++i) wsum += w[i];
  CHECK_CLOSE(wsum, 2.0, 1e-13, 0.0);

  const double g1 = 0.6, g2 = 0.45;
  for (int i = 0; i < NODES; ++i) v[i] = sl_hg_phase(g1, x[i]);
  sl_legendre_moments_gauss(x, w, v, NODES, MOMENTS, chi1);
  for (int i = 0; i < NODES; ++i) v[i] = sl_hg_phase(g2, x[i]);
  sl_legendre_moments_gauss(x, w, v, NODES, MOMENTS, chi2);
  for (int l = 0; l < 40; ++l) {
    CHECK_CLOSE(chi1[l], pow(g1, l), 1e-10, 1e-13);
    CHECK_CLOSE(chi2[l], pow(g2, l), 1e-10, 1e-13);
  }
  /* HG(g1) * HG(g2) = HG(g1 g2): moments multiply (Funk–Hecke). */
  for (int l = 0; l < MOMENTS; ++l) prod[l] = chi1[l] * chi2[l];
  double worst = 0.0;
  for (int k = 0; k <= 180; ++k) {
    const double mu = cos(k * SL_PI / 180.0);
    const double got = sl_legendre_series(prod, MOMENTS, mu), want = sl_hg_phase(g1 * g2, mu);
    worst = fmax(worst, fabs(got - want) / want);
  }
  CHECK_MSG(worst < 1e-8, "HG(g1) convolved with HG(g2) equals HG(g1 g2) to 1e-8");

  /* Forward fraction of HG from its moments against the closed form
   * F = (1 + g) / (2 g) * (1 - (1 - g) / sqrt(1 + g^2)). */
  const double F_hg = (1.0 + g1) / (2.0 * g1) * (1.0 - (1.0 - g1) / sqrt(1.0 + g1 * g1));
  CHECK_CLOSE(sl_legendre_forward_fraction(chi1, MOMENTS), F_hg, 1e-9, 0.0);

  /* Rayleigh, Riley et al. 2004 eq. 1: normalised, chi_2 = 1/10, and the closed-form Ams_n. */
  for (int i = 0; i < NODES; ++i) v[i] = sl_rayleigh_phase(x[i]);
  sl_legendre_moments_gauss(x, w, v, NODES, 4, chi1);
  CHECK_CLOSE(chi1[0], 1.0, 1e-13, 0.0);
  CHECK_CLOSE(chi1[1], 0.0, 0.0, 1e-14);
  CHECK_CLOSE(chi1[2], 0.1, 1e-12, 0.0);
  for (int n = 1; n <= 5; ++n) {
    double s = 0.0;
    for (int i = 0; i < NODES; ++i) s += 2.0 * SL_PI * w[i] * sl_rayleigh_ams(n, x[i]);
    CHECK_CLOSE(s, 1.0, 1e-12, 0.0);
  }
  CHECK_CLOSE(sl_rayleigh_ams(1, 0.3), sl_rayleigh_phase(0.3), 1e-14, 0.0);
  return sl_test_finish("test_legendre");
}
