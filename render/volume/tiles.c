/* The tile lattice's memory and each tile's range of slices (tiles.h). */
#include "tiles.h"

#include <stdlib.h>
#include <string.h>

int sl__tiles_init(tile_ranges *t, int w, int h, int threads)
{
  t->nx = (w + TILE - 1) / TILE, t->ny = (h + TILE - 1) / TILE;
  t->k = malloc((size_t)t->nx * t->ny * 2 * sizeof(int));
  t->active = malloc((size_t)t->nx * t->ny * threads * sizeof(int));
  t->work = malloc((size_t)t->nx * t->ny * 2 * sizeof(int));
  t->claim = aligned_alloc(64, (size_t)threads * TILES_CLAIM_STRIDE * sizeof *t->claim);
  if (t->claim) memset(t->claim, 0, (size_t)threads * TILES_CLAIM_STRIDE * sizeof *t->claim);
  return t->k != NULL && t->active != NULL && t->work != NULL && t->claim != NULL;
}

void sl__tiles_free(tile_ranges *t) { free(t->k), free(t->active), free(t->work), free(t->claim); }

void sl__tile_range_from(tile_ranges *t, size_t i, int w, int h, const int *k_lo, const int *k_hi, size_t stride)
{
  const int tx = (int)(i % t->nx), ty = (int)(i / t->nx);
  int lo = 1 << 30, hi = -(1 << 30);
  for (int y = ty * TILE; y < (ty + 1) * TILE && y < h; ++y)
    for (int x = tx * TILE; x < (tx + 1) * TILE && x < w; ++x) {
      const size_t e = (size_t)y * w + x;
      if (k_lo[e * stride] > k_hi[e * stride]) continue;
      if (k_lo[e * stride] < lo) lo = k_lo[e * stride];
      if (k_hi[e * stride] > hi) hi = k_hi[e * stride];
    }
  t->k[2 * i] = lo, t->k[2 * i + 1] = hi;
  t->work[i] = t->work[(size_t)t->nx * t->ny + i] = 1; /* until the tile has run: its cost is unknown */
}
