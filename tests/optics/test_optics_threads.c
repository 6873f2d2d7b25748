/* Tables do not depend on the number of threads (DESIGN.md: seeded, reproducible results):
 * the ice ray tracer works in fixed chunks with their own random streams, the Mie radii and
 * the Legendre moments are reduced in a fixed order. */
#include <omp.h>
#include <string.h>

#include "sl_optics.h"
#include "sl_testing.h"

static sl_optics_tables *build(int threads)
{
  omp_set_num_threads(threads);
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.use_cache = 0;
  req.particles = (1u << SL_ICE) | (1u << SL_CLOUD);
  req.angle_step_deg = 1.0;
  req.radius_samples = 6;
  req.ice_rays = 20000;
  sl_error err = {0};
  return sl_optics_build(&req, &err);
}

int main(void)
{
  sl_optics_tables *a = build(1), *b = build(3);
  CHECK(a && b);
  for (int p = 0; p < SL_PARTICLE_COUNT && a && b; ++p)
    for (int w = 0; w < 3; ++w) {
      const sl_phase_table *x = sl_optics_table(a, (sl_particle)p, w), *y = sl_optics_table(b, (sl_particle)p, w);
      if (!x) continue;
      CHECK(y && x->max_order == y->max_order);
      if (!y || x->max_order != y->max_order) continue;
      CHECK(memcmp(x->ams, y->ams, sizeof(float) * (size_t)(x->max_order + 1) * (size_t)x->n_angles) == 0);
      CHECK(memcmp(x->moments, y->moments, sizeof(double) * (size_t)x->n_moments) == 0);
      CHECK(x->sigma_ext == y->sigma_ext && x->albedo == y->albedo);
    }
  sl_optics_free(a);
  sl_optics_free(b);
  return sl_test_finish("test_optics_threads");
}
