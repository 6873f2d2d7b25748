/* The table cache: a second build loads what the first stored, a corrupted or stale file is
 * rejected and rebuilt, and the loaded tables equal the built ones. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sl_optics.h"
#include "sl_testing.h"

static int tables_equal(const sl_optics_tables *a, const sl_optics_tables *b, sl_particle p)
{
  for (int w = 0; w < sl_optics_wavelength_count(a); ++w) {
    const sl_phase_table *x = sl_optics_table(a, p, w), *y = sl_optics_table(b, p, w);
    if (!x || !y || x->max_order != y->max_order || x->n_angles != y->n_angles || x->sigma_ext != y->sigma_ext)
      return 0;
    if (memcmp(x->ams, y->ams, sizeof(float) * (size_t)(x->max_order + 1) * (size_t)x->n_angles) != 0) return 0;
    if (memcmp(x->forward, y->forward, sizeof(double) * (size_t)(x->max_order + 1)) != 0) return 0;
  }
  return 1;
}

int main(void)
{
  char dir[] = "/tmp/sl-optics-cache-XXXXXX";
  CHECK(mkdtemp(dir) != NULL);
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.particles = (1u << SL_SNOW) | (1u << SL_ICE);
  req.angle_step_deg = 1.0;
  req.ice_rays = 20000;
  req.cache_dir = dir;
  sl_error err = {0};
  sl_optics_stats s;

  sl_optics_tables *a = sl_optics_build(&req, &err);
  CHECK_MSG(a != NULL, err.message);
  sl_optics_get_stats(a, &s);
  CHECK(s.tables_built == 2 && s.tables_loaded == 0);

  sl_optics_tables *b = sl_optics_build(&req, &err);
  sl_optics_get_stats(b, &s);
  CHECK(s.tables_built == 0 && s.tables_loaded == 2 && s.cache_rejected == 0);
  CHECK(tables_equal(a, b, SL_SNOW) && tables_equal(a, b, SL_ICE));
  sl_optics_free(b);

  /* Flip one byte in the middle of every cache file: both must be rejected and rebuilt. */
  char cmd[600];
  snprintf(cmd, sizeof cmd,
           "for f in %s/optics-*.bin; do printf '\\377' | dd of=\"$f\" bs=1 seek=3000 conv=notrunc 2>/dev/null; done",
           dir);
  CHECK(system(cmd) == 0);
  b = sl_optics_build(&req, &err);
  sl_optics_get_stats(b, &s);
  CHECK(s.tables_built == 2 && s.cache_rejected == 2);
  CHECK(tables_equal(a, b, SL_SNOW) && tables_equal(a, b, SL_ICE));
  sl_optics_free(b);

  /* A different request (another seed) is another file, never a stale hit. */
  req.seed += 1;
  b = sl_optics_build(&req, &err);
  sl_optics_get_stats(b, &s);
  CHECK(s.tables_loaded == 1 && s.tables_built == 1); /* snow does not depend on the seed */
  sl_optics_free(b);

  /* A truncated file is rejected too. */
  snprintf(cmd, sizeof cmd, "for f in %s/optics-snow-*.bin; do truncate -s 100 \"$f\"; done", dir);
  CHECK(system(cmd) == 0);
  req.seed -= 1;
  b = sl_optics_build(&req, &err);
  sl_optics_get_stats(b, &s);
  CHECK(s.cache_rejected >= 1);
  CHECK(tables_equal(a, b, SL_SNOW));
  sl_optics_free(b);
  sl_optics_free(a);

  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  CHECK(system(cmd) == 0);
  return sl_test_finish("test_optics_cache");
}
