/* Benchmark of issue 4 (docs/PERFORMANCE.md): time to build the tables of a four-field scene at
 * 3 and at 16 wavelengths, time to load them from the cache, and the cost of one Ams_n lookup.
 * Prints numbers; never fails on speed. Label: slow. */
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
    CHECK(st.tables_loaded == 4);
    printf("%-10s 4 particle types x %2d wavelengths: build %7.2f s, load from cache %6.3f s (ratio %.0f)\n", sets[s],
           req.n_wavelengths, t_cold, t_warm, t_cold / t_warm);
    sl_optics_free(cold);
    if (s == 0)
      keep = warm;
    else
      sl_optics_free(warm);
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
