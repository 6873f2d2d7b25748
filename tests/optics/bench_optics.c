/* Benchmark (docs/PERFORMANCE.md): time to build the tables of all six particle types at 3 and at
 * 16 wavelengths, per type at 3, the size tables of the CM1 supercell at 70 minutes (cloud at 3.36,
 * 8 and 19 um, rain at 0.0987 and 1.33 mm), time to load them from the cache, and the cost of one
 * Ams_n lookup. Prints numbers; never fails on speed. Label: slow. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "sl_optics.h"
#include "sl_testing.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(void)
{
  char dir[] = "/tmp/sl-optics-bench-XXXXXX";
  CHECK(mkdtemp(dir) != NULL);
  const char *sets[2] = {"rgb", "spectral16"};
  sl_optics_tables *keep = NULL;
  for (int s = 0; s < 2; ++s) {
    sl_optics_request req;
    sl_optics_request_defaults(&req);
    req.cache_dir = dir;
    sl_error err = {0};
    CHECK(sl_optics_request_wavelengths(&req, sets[s], &err) == SL_OK);
    double t0 = now();
    sl_optics_tables *cold = sl_optics_build(&req, &err);
    const double t_cold = now() - t0;
    CHECK_MSG(cold != NULL, err.message);
    t0 = now();
    sl_optics_tables *warm = sl_optics_build(&req, &err);
    const double t_warm = now() - t0;
    sl_optics_stats st;
    sl_optics_get_stats(warm, &st);
    CHECK(st.tables_loaded == SL_PARTICLE_COUNT);
    printf("%-10s 6 particle types x %2d wavelengths: build %7.2f s, load from cache %6.3f s (ratio %.0f)\n", sets[s],
           req.n_wavelengths, t_cold, t_warm, t_cold / t_warm);
    sl_optics_free(cold);
    if (s == 0)
      keep = warm;
    else
      sl_optics_free(warm);
  }
  /* Per type, and the supercell's size tables, at 3 wavelengths without the cache. */
  for (int e = 0; e <= SL_PARTICLE_COUNT; ++e) {
    sl_optics_request req;
    sl_optics_request_defaults(&req);
    req.use_cache = 0;
    if (e < SL_PARTICLE_COUNT) {
      req.particles = 1u << e;
    } else {
      const sl_optics_size z[5] = {{SL_CLOUD, 3.36e-6}, {SL_CLOUD, 8e-6}, {SL_CLOUD, 19e-6}, {SL_RAIN, 0.0987e-3},
                                   {SL_RAIN, 1.33e-3}};
      req.particles = 0;
      req.n_sizes = 5;
      for (int i = 0; i < 5; ++i) req.sizes[i] = z[i];
    }
    sl_error err = {0};
    const double t0 = now();
    sl_optics_tables *T = sl_optics_build(&req, &err);
    CHECK_MSG(T != NULL, err.message);
    printf("%-44s build %7.2f s\n", e < SL_PARTICLE_COUNT ? sl_particle_name((sl_particle)e)
                                                       : "supercell sizes (cloud 3, rain 2)", now() - t0);
    sl_optics_free(T);
  }
  /* Lookup throughput: the renderer's per-sample call, random particle, order and angle. */
  if (keep) {
    const long count = 20000000;
    unsigned s = 12345u;
    double sum = 0.0;
    const double t0 = now();
    for (long i = 0; i < count; ++i) {
      s = s * 1664525u + 1013904223u;
      const double c = (double)(s >> 8) / 8388608.0 - 1.0;
      sum += sl_optics_ams(keep, (sl_particle)(s & 3u), (int)((s >> 2) % 3u), (int)((s >> 4) & 31u), c);
    }
    const double t = now() - t0;
    printf("sl_optics_ams: %.1f ns per lookup (%ld lookups, checksum %.6g)\n", 1e9 * t / count, count, sum);
    sl_optics_free(keep);
  }
  char cmd[300];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  CHECK(system(cmd) == 0);
  return sl_test_finish("bench_optics");
}
