/* Stability sweep: the series and the profile over T from 1.0005 to 1e5, q from -0.95 to 0.995,
 * albedo from 0.02 to 1, HG and a table of moments: never NaN or Inf, the boundary property
 * holds to the tolerance, the only refusal is "too close to T = 1", and the kernel's weights
 * are finite and non-negative. Prints the most negative value of the PSF found (relative to
 * its peak): the series is not positive by construction. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sl_apsf.h"
#include "sl_glow.h"
#include "sl_testing.h"

int main(void)
{
  const double W0s[4] = {0.02, 0.5, 0.9, 1.0};
  /* A "table" medium: HG moments of g = 0.85 damped beyond 60 (like a truncated phase table). */
  static double chi[120];
  for (int k = 0; k < 120; ++k) chi[k] = pow(0.85, k) * exp(-(k / 60.0) * (k / 60.0));
  long evaluations = 0, refusals = 0, failures = 0;
  double most_negative = 0.0, most_negative_scattering = 0.0;
  for (int it = 0; it <= 40; ++it) {
    const double T = 1.0 + 0.0005 * pow(2e8, it / 40.0); /* 1.0005 .. 1e5 */
    for (int iq = 0; iq <= 12; ++iq) {
      const double q = iq == 12 ? 0.995 : -0.95 + 1.9 * iq / 11.0;
      for (int iw = 0; iw < 4; ++iw) {
        for (int table = 0; table < 2; ++table) {
          if (table && iq > 0) continue;
          const sl_apsf_medium m = {W0s[iw], q, table ? chi : NULL, table ? 120 : 0};
          sl_apsf_series s;
          sl_error err = {0};
          const int rc = sl_apsf_series_init(&s, &m, T, 1e-6, 0, &err);
          if (rc) {
            refusals += rc == SL_ERR_ARG && strstr(err.message, "too close") != NULL;
            failures += !(rc == SL_ERR_ARG && strstr(err.message, "too close") != NULL);
            continue;
          }
          const double peak = sl_apsf_series_shape(&s, 1.0);
          int ok = isfinite(peak) && peak >= 0.0;
          for (int a = 0; a <= 64; ++a) {
            const double v = sl_apsf_series_shape(&s, cos(M_PI * a / 64.0));
            ++evaluations;
            ok &= isfinite(v);
            if (peak > 0 && v / peak < most_negative) most_negative = v / peak;
            if (peak > 0 && W0s[iw] == 1.0 && v / peak < most_negative_scattering) most_negative_scattering = v / peak;
          }
          ok &= fabs(sl_apsf_series_shape(&s, -1.0)) <= 1e-6 * peak;
          if (!ok) {
            char what[128];
            snprintf(what, sizeof what, "series T %.6g q %g W0 %g table %d", T, q, W0s[iw], table);
            CHECK_MSG(0, what);
          }
          sl_apsf_series_free(&s);
        }
      }
    }
  }
  /* With absorption, once some beta_m < beta_1 = 3 (1 - W0), order m overtakes g_1 at large T
   * and the PSF takes that order's sign changes (docs/APSF.md). Without absorption beta_1 = 0
   * is the smallest and the PSF stays non-negative. */
  printf("%ld series evaluations, %ld refusals near T = 1, most negative PSF value %.3g of the peak (W0 = 1: %.3g)\n",
         evaluations, refusals, most_negative, most_negative_scattering);
  CHECK(most_negative_scattering >= -1e-5);
  CHECK(failures == 0);
  CHECK(evaluations > 20000);
  /* Profiles and kernels in every regime, single scattering included. */
  for (double T = 0.01; T < 60.0; T *= 1.9) {
    for (double q = -0.5; q < 1.0; q += 0.45) {
      const sl_apsf_medium m = {0.95, q, NULL, 0};
      sl_glow_kernel k;
      sl_error err = {0};
      if (sl_glow_kernel_build(&k, &m, T, 40.0, 30, 20, SL_GLOW_FLUENCE, 1e-6, &err)) {
        CHECK_MSG(0, err.message);
        continue;
      }
      int ok = isfinite(k.sum);
      for (int i = 0; i < 61 * 41; ++i) ok &= isfinite(k.w[i]) && k.w[i] >= 0.0;
      if (!ok) {
        char what[96];
        snprintf(what, sizeof what, "kernel T %g q %g: non-finite or negative weight", T, q);
        CHECK_MSG(0, what);
      }
      sl_glow_kernel_free(&k);
    }
  }
  return sl_test_finish("test_apsf_stability");
}
