/* Load + resample benchmark: a 500 x 500 x 40 WRF-like storm written by `stormlight synth`
 * (sl_synth_write, the same code), loaded onto the uniform grid by sl_storm_load. Prints time
 * and peak memory of the load, against three peers measured in the same run: reading the
 * variables the load needs whole into float arrays (the I/O floor and the memory a read-everything
 * reader holds), the same load with the remap in one block of all levels (the work arrays over the
 * whole grid), and the float size of the fields rendered (the target: peak at most 2x that).
 * Usage: bench_load [FILE.nc] [NX NY NZ]; without FILE it writes /tmp/sl_bench_load.nc. */
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "sl_storm.h"
#include "sl_synth.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* kB of a /proc/self/status line ("VmHWM", "VmRSS"). */
static long status_kb(const char *key)
{
  FILE *f = fopen("/proc/self/status", "r");
  char line[256];
  long kb = -1;
  while (f && fgets(line, sizeof line, f))
    if (strncmp(line, key, strlen(key)) == 0) sscanf(line + strlen(key) + 1, "%ld", &kb);
  if (f) fclose(f);
  return kb;
}

/* Runs one phase in a child with a fresh peak-RSS counter; returns seconds and the peak growth
 * over the child's starting RSS (bytes) and the float size of the fields it produced. */
typedef struct phase_result {
  double seconds, peak_bytes, field_bytes;
} phase_result;

static void read_whole(const char *path, phase_result *r)
{
  const char *vars[] = {"P", "PB", "T", "QVAPOR", "PH", "PHB", "HGT", "XLAT", "XLONG",
                        "QCLOUD", "QRAIN", "QICE", "QSNOW"};
  int nc;
  if (nc_open(path, NC_NOWRITE, &nc)) return;
  float *keep[13] = {0};
  for (int v = 0; v < 13; ++v) {
    int id, nd, dims[NC_MAX_VAR_DIMS];
    if (nc_inq_varid(nc, vars[v], &id)) continue;
    nc_inq_varndims(nc, id, &nd);
    nc_inq_vardimid(nc, id, dims);
    size_t start[4] = {0}, count[4] = {1, 1, 1, 1}, n = 1;
    for (int d = 1; d < nd; ++d) nc_inq_dimlen(nc, dims[d], &count[d]), n *= count[d];
    keep[v] = malloc(n * sizeof(float));
    nc_get_vara_float(nc, id, start, count, keep[v]);
  }
  nc_close(nc);
  for (int v = 0; v < 13; ++v) free(keep[v]);
  r->field_bytes = 0;
}

static void load_blocks(const char *path, int block_levels, phase_result *r)
{
  sl_load_options o = {.block_levels = block_levels};
  sl_storm_frame f;
  sl_error err = {0};
  if (sl_storm_load(path, &o, &f, &err)) {
    fprintf(stderr, "%s\n", err.message);
    return;
  }
  r->field_bytes = 0;
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
    if (f.volume.eta[p]) r->field_bytes += (double)sl_volume_count(&f.volume) * sizeof(float);
  printf("  uniform grid %d x %d x %d, %d fields; the reader's own estimate %.0f MB\n", f.volume.nx, f.volume.ny,
         f.volume.nz, (int)(r->field_bytes / (sl_volume_count(&f.volume) * sizeof(float)) + 0.5),
         f.memory_estimate / 1e6);
  sl_storm_frame_free(&f);
}

/* The default blocks (64 MB of work arrays, rounded to the file's chunks), and all levels in one. */
static void load(const char *path, phase_result *r) { load_blocks(path, 0, r); }
static void load_one_block(const char *path, phase_result *r) { load_blocks(path, 100000, r); }

static phase_result run_phase(const char *path, void (*fn)(const char *, phase_result *))
{
  int pipefd[2];
  phase_result r = {0};
  if (pipe(pipefd)) return r;
  fflush(stdout); /* the child must not inherit unwritten output */
  const pid_t pid = fork();
  if (pid == 0) {
    FILE *clear = fopen("/proc/self/clear_refs", "w");
    if (clear) fputs("5", clear), fclose(clear); /* resets VmHWM to the current RSS */
    const long base = status_kb("VmRSS:");
    const double t0 = now();
    fn(path, &r);
    r.seconds = now() - t0;
    r.peak_bytes = (status_kb("VmHWM:") - base) * 1024.0;
    fflush(stdout);
    if (write(pipefd[1], &r, sizeof r) != sizeof r) _exit(1);
    _exit(0);
  }
  if (read(pipefd[0], &r, sizeof r) != sizeof r) fprintf(stderr, "phase failed\n");
  waitpid(pid, NULL, 0);
  close(pipefd[0]), close(pipefd[1]);
  return r;
}

int main(int argc, char **argv)
{
  const char *path = argc > 1 ? argv[1] : "/tmp/sl_bench_load.nc";
  if (argc <= 1 || access(path, R_OK) != 0) {
    sl_synth_options o;
    sl_synth_defaults(SL_SYNTH_CUMULONIMBUS, &o);
    o.nx = argc > 2 ? atoi(argv[2]) : 500, o.ny = argc > 3 ? atoi(argv[3]) : 500, o.nz = argc > 4 ? atoi(argv[4]) : 40;
    o.ntimes = 1;
    sl_error err = {0};
    const double t0 = now();
    if (sl_synth_write(path, &o, &err)) {
      fprintf(stderr, "%s\n", err.message);
      return 1;
    }
    printf("wrote %s (%d x %d x %d, cumulonimbus) in %.1f s\n", path, o.nx, o.ny, o.nz, now() - t0);
  }
  printf("whole-variable read (peer):\n");
  const phase_result whole = run_phase(path, read_whole);
  printf("  %.3f s, peak +%.0f MB\n", whole.seconds, whole.peak_bytes / 1e6);
  printf("sl_storm_load, all levels in one block (peer):\n");
  const phase_result one = run_phase(path, load_one_block);
  printf("  %.3f s, peak +%.0f MB\n", one.seconds, one.peak_bytes / 1e6);
  printf("sl_storm_load (blocks of levels, remapped into the output grid):\n");
  const phase_result l = run_phase(path, load);
  printf("  %.3f s, peak +%.0f MB\n", l.seconds, l.peak_bytes / 1e6);
  printf("fields rendered: %.0f MB as float\n", l.field_bytes / 1e6);
  printf("ratios: load peak / rendered fields %.2f (target <= 2; one block %.2f); load time / whole read %.2f "
         "(one block %.2f); whole-read peak / rendered fields %.2f\n",
         l.peak_bytes / l.field_bytes, one.peak_bytes / l.field_bytes, l.seconds / whole.seconds,
         one.seconds / whole.seconds, whole.peak_bytes / l.field_bytes);
  return 0;
}
