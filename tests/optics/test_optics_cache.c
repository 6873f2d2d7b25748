/* The table cache: a second build loads what the first stored, a corrupted or stale file is
 * rejected and rebuilt, the loaded tables equal the built ones, and two processes that miss the
 * same entry at once build it once (the entry's lock). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
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

/* Reads n bytes (two children write 8 bytes each, in either order). */
static ssize_t read_all(int fd, void *buf, size_t n)
{
  size_t got = 0;
  while (got < n) {
    const ssize_t r = read(fd, (char *)buf + got, n - got);
    if (r <= 0) break;
    got += (size_t)r;
  }
  return (ssize_t)got;
}

/* The child of the concurrency check: builds rain's tables into dir, writes (built, loaded). */
static int build_rain(const char *dir)
{
  sl_optics_request rain;
  sl_optics_request_defaults(&rain);
  rain.particles = 1u << SL_RAIN;
  rain.angle_step_deg = 1.0;
  rain.radius_samples = 64;
  rain.cache_dir = dir;
  sl_error err = {0};
  sl_optics_tables *t = sl_optics_build(&rain, &err);
  if (!t) return 1;
  sl_optics_stats s;
  sl_optics_get_stats(t, &s);
  const int counts[2] = {s.tables_built, s.tables_loaded};
  sl_optics_free(t);
  return write(STDOUT_FILENO, counts, sizeof counts) == (ssize_t)sizeof counts ? 0 : 1;
}

int main(int argc, char **argv)
{
  if (argc == 3 && strcmp(argv[1], "--build-rain") == 0) return build_rain(argv[2]);
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

  /* Two processes building the same rain tables into an empty cache at once (each build takes
   * a few tenths of a second, far longer than starting a process): one builds, the other waits
   * on the entry's lock and loads what the first stored. Without the lock both built. The two
   * are this program started afresh (fork and exec: a forked child of a process whose OpenMP
   * threads have run may hang in its first parallel region). */
  char rain_dir[700];
  snprintf(rain_dir, sizeof rain_dir, "%s/concurrent", dir);
  int fds[2];
  CHECK(pipe(fds) == 0);
  pid_t kids[2];
  for (int k = 0; k < 2; ++k) {
    kids[k] = fork();
    CHECK(kids[k] >= 0);
    if (kids[k] == 0) {
      dup2(fds[1], STDOUT_FILENO);
      close(fds[0]);
      execl("/proc/self/exe", "test_optics_cache", "--build-rain", rain_dir, (char *)NULL);
      _exit(127);
    }
  }
  close(fds[1]);
  int counts[4] = {-1, -1, -1, -1};
  CHECK(read_all(fds[0], counts, sizeof counts) == (ssize_t)sizeof counts);
  close(fds[0]);
  for (int k = 0; k < 2; ++k) {
    int status = 0;
    CHECK(waitpid(kids[k], &status, 0) == kids[k] && WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  printf("concurrent rain builds: built %d and %d, loaded %d and %d\n", counts[0], counts[2], counts[1], counts[3]);
  CHECK(counts[0] + counts[2] == 1 && counts[1] + counts[3] == 1);

  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  CHECK(system(cmd) == 0);
  return sl_test_finish("test_optics_cache");
}
