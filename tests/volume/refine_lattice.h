/* The lattices adaptive pixels march (render/volume/pixel_refine.h), counted from the blocks' rule:
 * blocks of SL__REFINE_TOP from the first pixel, and, where the last pixel is off that lattice, a
 * last one ending on it. Shared by the refinement's tests. */
#ifndef SL_TEST_REFINE_LATTICE_H
#define SL_TEST_REFINE_LATTICE_H

#include <stddef.h>

#include "pixel_refine.h"

/* Whether pixel p of an axis of `length` pixels lies on the lattice of `step` pixels of a block
 * holding it (every pixel where the axis is shorter than a block). */
static inline int refine_on_lattice(int p, int length, int step)
{
  const int top = SL__REFINE_TOP, regular_end = (length - 1) / top * top, last = length - 1 - top;
  if (length - 1 < top) return 1;
  return (p <= regular_end && p % step == 0) || (regular_end < length - 1 && p >= last && (p - last) % step == 0);
}

/* Pixels of a w x h image on the lattice of `step` along both axes. */
static inline size_t refine_lattice_count(int w, int h, int step)
{
  size_t nx = 0, ny = 0;
  for (int x = 0; x < w; ++x) nx += (size_t)refine_on_lattice(x, w, step);
  for (int y = 0; y < h; ++y) ny += (size_t)refine_on_lattice(y, h, step);
  return w - 1 < SL__REFINE_TOP || h - 1 < SL__REFINE_TOP ? (size_t)w * h : nx * ny;
}

#endif
