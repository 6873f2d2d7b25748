/* The slicer's tile claims (tiles.h): in every slice each active tile goes to exactly one thread,
 * also when a thread arrives late (descheduled by another process), whose run the others then take
 * from its back; and the barrier between the passes (slice_barrier.h) holds every thread until the
 * last has arrived: no thread sees the next slice's counts before all have written this one's. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sl_testing.h"
#include "slice_barrier.h"
#include "tiles.h"

enum { W = 200, H = 120, SLICES = 40, THREADS = 4 };

int main(void)
{
  tile_ranges t = {0};
  CHECK(sl__tiles_init(&t, W, H, THREADS));
  const size_t n = (size_t)t.nx * t.ny;
  /* Tile i is active in slices [i % 7, SLICES - 1 - i % 5]; its cost grows with i, so that the
   * runs are uneven in length. */
  for (size_t i = 0; i < n; ++i) {
    t.k[2 * i] = (int)(i % 7), t.k[2 * i + 1] = SLICES - 1 - (int)(i % 5);
    t.work[i] = t.work[n + i] = 1 + (int)(i % 13);
  }
  int *taken = calloc((size_t)SLICES * n, sizeof *taken);
  int *by_late = calloc(SLICES, sizeof *by_late);
  int arrived[SLICES] = {0}, early_release = 0;
  slice_barrier b = SLICE_BARRIER_INIT;
  omp_set_num_threads(THREADS);
#pragma omp parallel
  {
#pragma omp single
    b.team = omp_get_num_threads();
    const int me = omp_get_thread_num();
    for (int k = 0; k < SLICES; ++k) {
      /* Thread 1 is late in every third slice: 2 ms, far longer than the others' work. */
      if (me == 1 && k % 3 == 0) {
        const struct timespec late = {0, 2000000};
        nanosleep(&late, NULL);
      }
      int count, pos;
      const int *list = tiles_active(&t, k, &count);
      while (tiles_take(&t, k, list, count, &pos)) {
        __atomic_add_fetch(&taken[(size_t)k * n + list[pos]], 1, __ATOMIC_RELAXED);
        if (me == 1 && k % 3 == 0) __atomic_add_fetch(&by_late[k], 1, __ATOMIC_RELAXED);
      }
      __atomic_add_fetch(&arrived[k], 1, __ATOMIC_RELAXED);
      slice_barrier_wait(&b);
      if (__atomic_load_n(&arrived[k], __ATOMIC_RELAXED) != b.team) __atomic_store_n(&early_release, 1, __ATOMIC_RELAXED);
      slice_barrier_wait(&b);
    }
  }
  int wrong = 0, late_took = 0, late_slices = 0;
  for (int k = 0; k < SLICES; ++k)
    for (size_t i = 0; i < n; ++i) {
      const int active = k >= t.k[2 * i] && k <= t.k[2 * i + 1];
      wrong += taken[(size_t)k * n + i] != active;
    }
  for (int k = 0; k < SLICES; k += 3) late_took += by_late[k], late_slices++;
  if (wrong) fprintf(stderr, "%d tiles taken other than once in their slices\n", wrong);
  CHECK_MSG(wrong == 0, "every active tile is taken exactly once per slice, no inactive one");
  CHECK_MSG(!early_release, "no thread leaves the barrier before every thread has arrived");
  /* Its run is a quarter of each slice's tiles (about 25 of 104); 2 ms late, the others have taken
   * it, all but what it finds left. */
  fprintf(stderr, "the late thread took %d tiles in %d slices of %zu tiles\n", late_took, late_slices, n);
  CHECK_MSG(late_took < late_slices * (int)n / 8, "the late thread's run went to the others");
  free(taken), free(by_late);
  sl__tiles_free(&t);
  return sl_test_finish("test_tiles_take");
}
