/* Stability sweep of issue 4: no NaN or Inf for size parameters 1e-3..2e4, imaginary index
 * 0..10, orders up to 200. */
#include <math.h>
#include <stdio.h>

#include "sl_mie.h"
#include "sl_optics.h"
#include "sl_testing.h"

int main(void)
{
  const double m_re[] = {1.0001, 1.33, 1.55, 2.5};
  const double m_im[] = {0.0, 1e-9, 1e-4, 0.1, 1.0, 10.0};
  const double mu[5] = {1.0, 0.5, 0.0, -0.5, -1.0};
  sl_error err = {0};
  int bad = 0, calls = 0;
  for (int i = 0; i <= 28; ++i) {
    const double x = 1e-3 * pow(2e7, i / 28.0); /* 1e-3 .. 2e4 */
    for (size_t a = 0; a < sizeof m_re / sizeof m_re[0]; ++a)
      for (size_t b = 0; b < sizeof m_im / sizeof m_im[0]; ++b) {
        sl_mie_efficiencies e;
        double s11[5];
        ++calls;
        if (sl_mie(x, m_re[a], m_im[b], mu, 5, &e, NULL, NULL, s11, &err) != SL_OK) {
          ++bad;
          continue;
        }
        int ok = isfinite(e.qext) && isfinite(e.qsca) && isfinite(e.qback) && isfinite(e.g) && e.qsca >= 0.0 &&
                 e.qext >= e.qsca * (1.0 - 1e-9) && fabs(e.g) <= 1.0 + 1e-9;
        for (int j = 0; j < 5; ++j) ok = ok && isfinite(s11[j]) && s11[j] >= 0.0;
        if (!ok) {
          ++bad;
          fprintf(stderr, "x %g m %g+%gi: qext %g qsca %g g %g\n", x, m_re[a], m_im[b], e.qext, e.qsca, e.g);
        }
      }
  }
  printf("%d Mie evaluations, %d bad\n", calls, bad);
  CHECK(bad == 0);

  /* Orders up to 200: every value of every Ams_n finite and non-negative. */
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.use_cache = 0;
  req.particles = (1u << SL_SNOW) | (1u << SL_CLOUD);
  req.angle_step_deg = 1.0;
  req.radius_samples = 4;
  req.max_order = 200;
  sl_optics_tables *T = sl_optics_build(&req, &err);
  CHECK_MSG(T != NULL, err.message);
  int finite = 1;
  for (int p = 0; p < SL_PARTICLE_COUNT && T; ++p)
    for (int w = 0; w < 3; ++w) {
      const sl_phase_table *t = sl_optics_table(T, (sl_particle)p, w);
      if (!t) continue;
      CHECK(t->max_order == 200);
      for (size_t k = 0; k < (size_t)(t->max_order + 1) * (size_t)t->n_angles; ++k)
        finite = finite && isfinite(t->ams[k]) && t->ams[k] >= 0.0f;
      for (int n = 0; n <= t->max_order; ++n) finite = finite && isfinite(t->forward[n]) && isfinite(t->delta[n]);
    }
  CHECK(finite);
  sl_optics_free(T);
  return sl_test_finish("test_optics_stability");
}
