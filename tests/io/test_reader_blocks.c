/* The loader remaps a block of model levels at a time (io/remap.c), so that a large storm's work
 * arrays hold a block rather than the whole grid. Each cell's deposit reads only its own level's
 * heights, air and value, so a load in blocks of 1, 2 or 5 levels must give the frame of the load
 * in one block: the same fields, stats and size tables, bit for bit. Bit for bit holds because no
 * two species of these files feed one particle type: each output cell then sums its deposits in
 * the same order whatever the blocks (two species sharing a type would interleave theirs).
 * Real files: the WRF Katrina (WSM3, chunks of 14 levels, cloud split into ice) and Tibet
 * (Thompson with numbers, contiguous) runs, the CM1 supercell (two-moment, numbers per kg) and a
 * BOMEX LES time (shallow cumulus). Level subsets (--levels) start the blocks off the file's
 * first level; column subsets (--stride, --region) and the earth's curvature come along. The frame's content box, which the passes over the fields keep to, is checked
 * against a scan of the fields. The CF pressure-level layouts, reversed and masked below the ground, are checked in
 * test_reader_pressure.c. The deposits and the air are shared among threads, columns by columns:
 * one thread and three (more than the machine's cores, so rows change hands) give the same frame,
 * and where several cells are refused the message names the first in the file's order. */
#include <math.h>
#include <netcdf.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sl_storm.h"
#include "sl_synth.h"
#include "sl_testing.h"

/* Field by field: a struct's padding need not compare. */
static int same_stats(const sl_field_stats *a, const sl_field_stats *b)
{
  return a->present == b->present && a->q_min == b->q_min && a->q_max == b->q_max && a->q_mean == b->q_mean &&
         a->negative_count == b->negative_count && a->r_eff_min == b->r_eff_min && a->r_eff_max == b->r_eff_max &&
         a->number_negative == b->number_negative && a->number_missing == b->number_missing;
}

/* 1 when frames a and b hold the same grid, fields, stats and size tables, bit for bit. */
static int same_frame(const sl_storm_frame *a, const sl_storm_frame *b, const char *what)
{
  int same = a->volume.nx == b->volume.nx && a->volume.ny == b->volume.ny && a->volume.nz == b->volume.nz &&
             memcmp(a->volume.content_lo, b->volume.content_lo, sizeof a->volume.content_lo) == 0 &&
             memcmp(a->volume.content_hi, b->volume.content_hi, sizeof a->volume.content_hi) == 0 &&
             memcmp(a->volume.origin, b->volume.origin, sizeof a->volume.origin) == 0 &&
             memcmp(a->volume.spacing, b->volume.spacing, sizeof a->volume.spacing) == 0;
  const size_t n = (size_t)a->volume.nx * a->volume.ny * a->volume.nz;
  for (int p = 0; same && p < SL_VOLUME_SLOTS; ++p) {
    if (!a->volume.eta[p] != !b->volume.eta[p]) same = 0;
    else if (a->volume.eta[p] && memcmp(a->volume.eta[p], b->volume.eta[p], n * sizeof(float)) != 0) same = 0;
    if (a->volume.effective_radius_m[p] != b->volume.effective_radius_m[p]) same = 0;
    if (!same) fprintf(stderr, "%s: field in slot %d differs\n", what, p);
  }
  for (int p = 0; same && p < SL_PARTICLE_COUNT; ++p)
    same = same_stats(&a->stats[p], &b->stats[p]);
  for (int i = 0; same && i < a->nspecies; ++i)
    same = same_stats(&a->species_stats[i], &b->species_stats[i]);
  for (int p = 0; same && p < SL_PARTICLE_COUNT; ++p) {
    same = a->sizes.count[p] == b->sizes.count[p] && a->sizes.range_lo_m[p] == b->sizes.range_lo_m[p] &&
           a->sizes.range_hi_m[p] == b->sizes.range_hi_m[p] && a->sizes.limited[p] == b->sizes.limited[p];
    for (int k = 0; same && k < SL_VOLUME_MAX_FIELDS; ++k) same = a->sizes.radius_m[p][k] == b->sizes.radius_m[p][k];
  }
  if (same) same = a->nspecies == b->nspecies;
  return same;
}

/* Sum of every field: a load that deposited nothing would compare equal to another such. */
static double total(const sl_storm_frame *f)
{
  const size_t n = (size_t)f->volume.nx * f->volume.ny * f->volume.nz;
  double sum = 0.0;
  for (int p = 0; p < SL_VOLUME_SLOTS; ++p)
    for (size_t i = 0; f->volume.eta[p] && i < n; ++i) sum += f->volume.eta[p][i];
  return sum;
}

/* The frame's content box (sl_volume.h) against a scan of every field: it holds every non-zero
 * sample, and each of its six faces touches one (the box is where the remap deposited); and no
 * field the frame keeps is empty. */
static int content_box_is_tight(const sl_storm_frame *f)
{
  const sl_volume *v = &f->volume;
  int lo[3] = {v->nx, v->ny, v->nz}, hi[3] = {-1, -1, -1}, empty_field = 0;
  for (int p = 0; p < SL_VOLUME_SLOTS; ++p) {
    int held = 0;
    for (int k = 0; v->eta[p] && k < v->nz; ++k)
      for (int j = 0; j < v->ny; ++j)
        for (int i = 0; i < v->nx; ++i) {
          if (v->eta[p][sl_volume_index(v, i, j, k)] == 0.0f) continue;
          held = 1;
          const int at[3] = {i, j, k};
          for (int a = 0; a < 3; ++a) {
            if (at[a] < lo[a]) lo[a] = at[a];
            if (at[a] > hi[a]) hi[a] = at[a];
          }
        }
    empty_field |= v->eta[p] && !held;
  }
  /* Every field kept holds medium (the load drops the empty ones, by what its deposits left). */
  if (empty_field) fprintf(stderr, "a field the frame keeps is empty\n");
  int tight = v->content_known && !empty_field;
  for (int a = 0; a < 3; ++a) tight &= v->content_lo[a] == lo[a] && v->content_hi[a] == hi[a];
  if (!tight)
    fprintf(stderr, "content box %d..%d, %d..%d, %d..%d; non-zero samples %d..%d, %d..%d, %d..%d\n", v->content_lo[0],
            v->content_hi[0], v->content_lo[1], v->content_hi[1], v->content_lo[2], v->content_hi[2], lo[0], hi[0], lo[1],
            hi[1], lo[2], hi[2]);
  return tight;
}

/* The load of `path` with options base (its block size aside) in blocks against one block. */
static void check_blocks_with(const char *path, sl_load_options base)
{
  sl_error err = {0};
  sl_load_options whole = base;
  whole.block_levels = 1000;
  const int level_first = base.level_first, level_count = base.level_count;
  sl_storm_frame one;
  if (!CHECK(sl_storm_load(path, &whole, &one, &err) == SL_OK)) {
    fprintf(stderr, "%s\n", err.message);
    return;
  }
  CHECK(total(&one) > 0.0);
  CHECK_MSG(content_box_is_tight(&one), path);
  const int blocks[] = {1, 2, 5};
  for (size_t b = 0; b < sizeof blocks / sizeof blocks[0]; ++b) {
    sl_load_options o = whole;
    o.block_levels = blocks[b];
    sl_storm_frame f;
    char what[4200];
    snprintf(what, sizeof what, "%s levels %d:%d in blocks of %d", path, level_first, level_count, blocks[b]);
    if (CHECK_MSG(sl_storm_load(path, &o, &f, &err) == SL_OK, what)) {
      CHECK_MSG(same_frame(&one, &f, what), what);
      sl_storm_frame_free(&f);
    } else {
      fprintf(stderr, "%s\n", err.message);
    }
  }
  /* One thread and three: the same frame. */
  const int threads[] = {1, 3};
  const int default_threads = omp_get_max_threads();
  for (size_t t = 0; t < sizeof threads / sizeof threads[0]; ++t) {
    omp_set_num_threads(threads[t]);
    sl_load_options o = whole;
    o.block_levels = 2;
    sl_storm_frame f;
    char what[4200];
    snprintf(what, sizeof what, "%s levels %d:%d on %d threads", path, level_first, level_count, threads[t]);
    if (CHECK_MSG(sl_storm_load(path, &o, &f, &err) == SL_OK, what)) {
      CHECK_MSG(same_frame(&one, &f, what), what);
      sl_storm_frame_free(&f);
    }
  }
  omp_set_num_threads(default_threads);
  /* The default blocks (64 MB of work arrays, rounded to the chunks) hold these small files
   * whole; the same frame again. */
  sl_load_options d = whole;
  d.block_levels = 0;
  sl_storm_frame f;
  if (CHECK(sl_storm_load(path, &d, &f, &err) == SL_OK)) {
    CHECK_MSG(same_frame(&one, &f, path), "default blocks");
    sl_storm_frame_free(&f);
  }
  sl_storm_frame_free(&one);
}

static void check_blocks(const char *path, int time_index, int level_first, int level_count)
{
  check_blocks_with(path, (sl_load_options){.time_index = time_index, .level_first = level_first,
                                            .level_count = level_count});
}

/* Two unphysical cloud-water values in a small synthetic storm, the later one (level 7) in the
 * first row of columns and the earlier (level 3) in the last: whatever the blocks and the threads,
 * the message names level 3, the first in the file's order. */
static void check_first_refused(void)
{
  char path[] = "/tmp/sl_test_reader_blocks_XXXXXX.nc";
  const int fd = mkstemps(path, 3);
  if (!CHECK(fd >= 0)) return;
  close(fd);
  sl_error err = {0};
  sl_synth_options o;
  sl_synth_defaults(SL_SYNTH_STRATOCUMULUS, &o);
  o.nx = 12, o.ny = 10, o.nz = 16, o.ntimes = 1;
  if (!CHECK(sl_synth_write(path, &o, &err) == SL_OK)) {
    unlink(path);
    return;
  }
  int nc, id;
  const size_t late[4] = {0, 7, 0, 0}, early[4] = {0, 3, 9, 11};
  const float late_value = 0.7f, early_value = 0.5f;
  CHECK(nc_open(path, NC_WRITE, &nc) == NC_NOERR && nc_inq_varid(nc, "QCLOUD", &id) == NC_NOERR &&
        nc_put_var1_float(nc, id, late, &late_value) == NC_NOERR &&
        nc_put_var1_float(nc, id, early, &early_value) == NC_NOERR && nc_close(nc) == NC_NOERR);
  const int default_threads = omp_get_max_threads();
  for (int threads = 1; threads <= 3; threads += 2)
    for (int blocks = 1; blocks <= 1000; blocks *= 10) {
      omp_set_num_threads(threads);
      sl_load_options lo = {.block_levels = blocks};
      sl_storm_frame f;
      const int rc = sl_storm_load(path, &lo, &f, &err);
      char what[640];
      snprintf(what, sizeof what, "blocks of %d, %d threads: %s", blocks, threads, rc ? err.message : "loaded");
      CHECK_MSG(rc == SL_ERR_DATA && strstr(err.message, "QCLOUD = 0.5 kg/kg at model level 3 "), what);
      if (rc == SL_OK) sl_storm_frame_free(&f);
    }
  omp_set_num_threads(default_threads);
  unlink(path);
}

int main(void)
{
  /* The thread counts asked for are the ones given (no dynamic adjustment), so that three threads
   * do share the rows. */
  omp_set_dynamic(0);
  int team = 0;
  omp_set_num_threads(3);
#pragma omp parallel
#pragma omp single
  team = omp_get_num_threads();
  CHECK_MSG(team == 3, "three threads asked for, three given (OMP_THREAD_LIMIT?)");
  omp_set_num_threads(omp_get_num_procs());
  check_first_refused();
  const char *shared = getenv("SL_SHARED_DIR");
  char path[4096];
  snprintf(path, sizeof path, "%s/data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc", shared ? shared : "../shared");
  check_blocks(path, 2, 0, 0);
  check_blocks(path, 2, 3, 8);
  /* Every other column, and the columns of a latitude-longitude box, with the earth's curvature:
   * the blocks change only which levels are read. */
  check_blocks_with(path, (sl_load_options){.time_index = 1, .stride = 2, .earth_curvature = 1});
  check_blocks_with(path, (sl_load_options){.time_index = 1, .has_region = 1, .region = {24.0, 27.0, -90.0, -86.0}});
  snprintf(path, sizeof path, "%s/data/wrf/wrf_tibet2005_d01_lambert_thompson_4t_tiny.nc",
           shared ? shared : "../shared");
  check_blocks(path, 3, 0, 0);
  snprintf(path, sizeof path, "%s/data/cm1/cm1_supercell_t060min.nc", shared ? shared : "../shared");
  check_blocks(path, 0, 0, 0);
  check_blocks(path, 0, 4, 21);
  snprintf(path, sizeof path, "%s/data/cm1/cm1_bomex_les50m_t060min.nc", shared ? shared : "../shared");
  check_blocks(path, 0, 0, 0);
  return sl_test_finish("test_reader_blocks");
}
