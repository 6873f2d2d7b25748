/* Tile scheduling for the slicer's passes: square tiles of the image (or light buffer), each with
 * the slices in which it has work, shared out per slice among the threads by measured cost. */
#ifndef SL_TILES_H
#define SL_TILES_H

#include <omp.h>
#include <stddef.h>
#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

/* Square tiles of a w x h lattice (image pixels or light texels), each with the range of slices in
 * which any of its elements is active: a pass over one slice visits only the tiles whose range
 * holds it, instead of testing every element of the lattice against its own range per slice
 * (256 slices x 512^2 pixels is 67M tests, most failing, for ~8M samples). */
#define TILE 16
typedef struct tile_ranges {
  int nx, ny;
  int *k;      /* per tile: first and last active slice (first > last: never active) */
  int *active; /* per thread, room for a list of every tile (tiles_active) */
  int *work;   /* two per tile: its cost in a slice it had work (tile_cost; tiles_run): slice k's
                  cuts read row k % 2 while its tiles write row (k + 1) % 2, so that no thread's
                  cut sees another's writes of the same slice */
  unsigned long long *claim; /* per thread, its run of the slice's tiles (tiles_take) */
} tile_ranges;

/* Room for a w x h lattice's tiles and one active list per thread; 0 when out of memory. */
int sl__tiles_init(tile_ranges *t, int w, int h, int threads);
void sl__tiles_free(tile_ranges *t);
/* Tile i's range from its elements' ranges (k_lo[e], k_hi[e] of element e = y * w + x, stride ints
 * apart), its cost unknown until it has run. */
void sl__tile_range_from(tile_ranges *t, size_t i, int w, int h, const int *k_lo, const int *k_hi, size_t stride);

/* The tiles whose range holds slice k, in order, in the calling thread's own list (returned).
 * Every thread builds the same list (no barrier), and shares it out with tiles_take. */
static inline int *tiles_active(const tile_ranges *t, int k, int *count)
{
  const size_t n = (size_t)t->nx * t->ny;
  int *list = t->active + (size_t)omp_get_thread_num() * n, c = 0;
  for (size_t i = 0; i < n; ++i) {
    list[c] = (int)i;
    c += k >= t->k[2 * i] && k <= __atomic_load_n(&t->k[2 * i + 1], __ATOMIC_RELAXED);
  }
  *count = c;
  return list;
}

/* A tile's cost as its share weight: the time it took (the cycle counter, a few cycles to read),
 * so that the cuts follow what the tiles really cost, parts, fields and all; its sample count
 * where there is no cycle counter. */
static inline unsigned long long tile_clock(void)
{
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#else
  return 0;
#endif
}

static inline int tile_cost(unsigned long long start, int samples)
{
#if defined(__x86_64__) || defined(__i386__)
  (void)samples;
  const unsigned long long cycles = (__rdtsc() - start) >> 6;
  return cycles < (1u << 24) ? (int)cycles + 1 : 1 << 24;
#else
  (void)start;
  return samples + 1;
#endif
}

/* Thread who's part [*first, *end) of a slice's active tiles: a contiguous run of the list, the
 * runs cut where the tiles' work in their last slice adds up to equal shares. Contiguous runs keep
 * a thread on the same part of the image (or light buffer) from slice to slice, its pixels and
 * texels in its own core's caches: with a dynamic schedule, tiles went to whichever thread asked,
 * and the two threads did a fifth more work than one (docs/PERFORMANCE.md, "Threads"). Every
 * thread computes every cut from the same list and counts, so the runs tile the list. */
static inline void tiles_run(const tile_ranges *t, int k, const int *list, int count, int who, int threads,
                             int *first, int *end)
{
  *first = 0, *end = count;
  if (threads == 1) return;
  const int *work = t->work + (size_t)(k & 1) * t->nx * t->ny;
  long total = 0;
  for (int i = 0; i < count; ++i) total += work[list[i]];
  /* Tile i goes to the thread whose share holds the middle of its work. */
  long before = 0;
  *first = *end = count;
  for (int i = 0; i < count; ++i) {
    const long w = work[list[i]];
    const int owner = (int)((2 * before + w) * threads / (2 * total + 1));
    before += w;
    if (owner == who && *first == count) *first = i;
    if (owner > who) {
      *end = i;
      break;
    }
  }
  if (*first > *end) *first = *end;
}

/* A thread's run as a claim word: the slice's tag in the top 16 bits (never 0, so that a fresh
 * claim is never this slice's), then the next and the end position in the list, 24 bits each.
 * Its owner takes tiles from the front; a thread done with its own run takes them from the back,
 * so that a descheduled thread (another process on its core) holds up the slice by at most the
 * tile it is in, where its whole run held up the barrier that ends the slice. */
#define TILES_CLAIM_STRIDE 8 /* words per claim: one 64-byte line each, no false sharing */
static inline unsigned long long tiles_claim_word(int k, int next, int end)
{
  return (unsigned long long)(0x8000u | (k & 0x7fff)) << 48 | (unsigned long long)next << 24 | (unsigned)end;
}

/* Thread who's claim for slice k, set from its run if it still holds an earlier slice's (every
 * earlier run is spent: the slice's barrier came between). */
static inline unsigned long long tiles_claim(const tile_ranges *t, int k, const int *list, int count, int who,
                                             int threads)
{
  unsigned long long *slot = t->claim + (size_t)who * TILES_CLAIM_STRIDE;
  unsigned long long c = __atomic_load_n(slot, __ATOMIC_ACQUIRE);
  if (c >> 48 == (0x8000u | (k & 0x7fff))) return c;
  int first, end;
  tiles_run(t, k, list, count, who, threads, &first, &end);
  const unsigned long long fresh = tiles_claim_word(k, first, end);
  /* Another thread may have set it first, and taken from it since: its word wins. */
  if (__atomic_compare_exchange_n(slot, &c, fresh, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)) return fresh;
  return c;
}

/* The next tile of slice k for the calling thread (its position in the list, in *pos): from the
 * front of its own run, else from the back of another's. 0 when the slice has none left. The
 * tiles a thread ran do not change the image: each tile's pixels or texels are its own. */
static inline int tiles_take(const tile_ranges *t, int k, const int *list, int count, int *pos)
{
  const int threads = omp_get_num_threads(), me = omp_get_thread_num();
  for (int step = 0; step < threads; ++step) {
    const int who = (me + step) % threads;
    unsigned long long *slot = t->claim + (size_t)who * TILES_CLAIM_STRIDE;
    unsigned long long c = tiles_claim(t, k, list, count, who, threads);
    for (;;) {
      const int next = (int)(c >> 24 & 0xffffff), end = (int)(c & 0xffffff);
      if (next >= end) break;
      const int own = step == 0;
      const unsigned long long taken = own ? tiles_claim_word(k, next + 1, end) : tiles_claim_word(k, next, end - 1);
      if (__atomic_compare_exchange_n(slot, &c, taken, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)) {
        *pos = own ? next : end - 1;
        return 1;
      }
    }
  }
  return 0;
}

#endif
