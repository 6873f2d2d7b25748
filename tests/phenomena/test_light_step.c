/* The light step through one slab (sl_light_fraction: eq. 24 as the renderer evaluates it) with
 * the cloud's real tables, against what it claims to compute: the forward-kept fraction
 * averaged over the slab's random number of interactions. Oracles: the Poisson sum over that
 * number taken term by term from the tables (independent of the closed form), the thin limit
 * (a slab of optical depth tau loses tau (1 - albedo F_{n+1})), and composition (one slab keeps
 * what its two halves keep in turn). The printed form T + (1 - T) prod albedo F_i fails the
 * last two: its thin slabs lose only O(tau^2), so its light depends on how many slices cut the
 * cloud (printed here for the record). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "lighting.h"
#include "sl_optics.h"
#include "sl_testing.h"

/* ln prod_{i=n+1}^{n+k} albedo F_i for integer n and k, from the model's table. */
static double log_product(const sl_light_model *m, int c, int n, int k)
{
  return sl_log_forward_product(m, 0, c, (double)n, (double)k);
}

/* The printed eq. 24 over a slab of optical depth tau (one field, albedo_mean 1 up to 1e-6). */
static double printed(const sl_light_model *m, int c, double n, double tau)
{
  const double t = exp(-tau);
  return t + (1.0 - t) * exp(sl_log_forward_product(m, 0, c, n, m->albedo_mean[0] * tau));
}

static double fraction(const sl_light_model *m, int c, double n, double tau)
{
  const float beta[SL_MAX_FIELDS] = {(float)1e-2};
  double f[SL_MAX_WAVELENGTHS];
  sl_light_fraction(m, beta, n, tau / 1e-2, f);
  return f[c];
}

int main(void)
{
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.particles = 1u << SL_CLOUD;
  sl_error err = {0};
  sl_optics_tables *optics = sl_optics_build(&req, &err);
  if (!optics) {
    fprintf(stderr, "optics: %s\n", err.message);
    return 1;
  }
  float dummy = 1.0f;
  sl_volume volume = {0};
  volume.eta[SL_CLOUD] = &dummy;
  sl_scene scene = {.volume = &volume, .optics = optics, .lighting = SL_LIGHTING_MULTIPLE};
  sl_light_model m;
  CHECK(sl_light_model_init(&m, &scene, &err) == SL_OK && m.nf == 1);
  for (int c = 0; c < m.nwl; ++c) {
    /* 1. Thin limit: the first-order loss of the unscattered light minus the once-scattered
     * light kept forward, tau (1 - albedo F_{n+1}). */
    for (int n = 0; n <= 30; n += 10) {
      const double tau = 1e-5;
      const double kept_once = exp(log_product(&m, c, n, 1));
      const double loss = 1.0 - fraction(&m, c, n, tau);
      CHECK_CLOSE(loss, tau * (1.0 - kept_once), 2e-3, 0.0);
      if (c == 0 && n == 0)
        printf("thin slab tau 1e-5 at n 0: loss %.4g, tau (1 - albedo F_1) %.4g, printed eq. 24 %.4g\n", loss,
               tau * (1.0 - kept_once), 1.0 - printed(&m, c, n, tau));
    }
    /* 2. The Poisson sum over the slab's interactions, term by term from the tables: close where
     * the per-event factor is nearly constant over the slab's events (past the first orders);
     * within 5 % at the first orders, where the closed form's one geometric-mean factor stands
     * for factors that change from event to event. */
    const int ns[] = {0, 5, 30};
    const double taus[] = {0.1, 1.0, 5.0};
    for (size_t a = 0; a < sizeof ns / sizeof ns[0]; ++a)
      for (size_t b = 0; b < sizeof taus / sizeof taus[0]; ++b) {
        const int n = ns[a];
        const double tau = taus[b];
        double sum = 0.0, p = exp(-tau);
        for (int k = 0; k < 200; ++k) {
          sum += p * exp(log_product(&m, c, n, k));
          p *= tau / (k + 1);
        }
        const double got = fraction(&m, c, n, tau);
        if (c == 0) printf("n %2d tau %4.1f: closed form %.6f, Poisson sum %.6f, printed %.6f\n", n, tau, got, sum,
                           printed(&m, c, n, tau));
        CHECK_CLOSE(got, sum, n >= 30 ? 0.005 : 0.05, 0.0);
      }
    /* 3. One slab keeps what its two halves keep in turn (n advanced by the first half's events). */
    const double depths[] = {1e-3, 0.1, 1.0, 10.0};
    for (size_t b = 0; b < sizeof depths / sizeof depths[0]; ++b)
      for (int n = 0; n <= 20; n += 4) {
        const double tau = depths[b], half = 0.5 * tau * m.albedo_mean[0];
        const double whole = fraction(&m, c, n, tau);
        const double halves = fraction(&m, c, n, 0.5 * tau) * fraction(&m, c, n + half, 0.5 * tau);
        /* Exact while the per-event factor is constant over the slab, within 3 % over ten orders. */
        CHECK_CLOSE(log(whole), log(halves), tau < 5.0 ? 1e-3 : 0.03, 1e-12);
        if (c == 0 && n == 0)
          printf("tau %5.3f: loss in one slab %.5g, in two halves %.5g; printed %.5g and %.5g\n", tau, 1.0 - whole,
                 1.0 - halves, 1.0 - printed(&m, c, n, tau),
                 1.0 - printed(&m, c, n, 0.5 * tau) * printed(&m, c, n + half, 0.5 * tau));
      }
  }
  sl_light_model_free(&m);
  sl_optics_free(optics);
  return sl_test_finish("test_light_step");
}
