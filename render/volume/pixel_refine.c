/* Adaptive refinement of an image's rays in blocks (pixel_refine.h). */
#include "pixel_refine.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum refine_state { BLOCK_INACTIVE = 0, BLOCK_SMOOTH, BLOCK_SPLITS };

/* The blocks along an axis of `length` pixels (pixel_refine.h); 0 when out of memory. */
static int axis_init(sl__refine_axis *ax, int length)
{
  const int top = SL__REFINE_TOP, regular = (length - 1) / top;
  ax->n = regular ? regular + ((length - 1) % top != 0) : 0;
  ax->origin = malloc((size_t)(ax->n ? ax->n : 1) * sizeof *ax->origin);
  ax->block_of = malloc((size_t)length * sizeof *ax->block_of);
  ax->on_first = calloc((size_t)length, 1);
  if (!ax->origin || !ax->block_of || !ax->on_first) return 0;
  for (int j = 0; j < ax->n; ++j) {
    ax->origin[j] = j < regular ? j * top : length - 1 - top;
    for (int k = 0; k <= top; k += top / 2) ax->on_first[ax->origin[j] + k] = 1;
  }
  for (int p = 0; p < length; ++p)
    ax->block_of[p] = !ax->n ? 0 : p <= regular * top ? (p / top < regular ? p / top : regular - 1) : ax->n - 1;
  return 1;
}

/* Blocks along an axis at `level` (each block of SL__REFINE_TOP holds 2^level of them). */
static int blocks_along(const sl__refine_axis *ax, int level) { return ax->n << level; }

/* The first pixel of block i at `level` along an axis. */
static int block_origin(const sl__refine_axis *ax, int level, int i)
{
  return ax->origin[i >> level] + (i & ((1 << level) - 1)) * (SL__REFINE_TOP >> level);
}

/* The block at `level` holding pixel p along an axis. */
static int block_holding(const sl__refine_axis *ax, int level, int p)
{
  const int j = ax->block_of[p], size = SL__REFINE_TOP >> level, last = (1 << level) - 1;
  const int sub = (p - ax->origin[j]) / size;
  return (j << level) + (sub < last ? sub : last);
}

int sl__refine_init(sl__refine *f, int width, int height, int channels, int transparency, double tolerance,
                    double clear_spread)
{
  memset(f, 0, sizeof *f);
  f->width = width, f->height = height, f->channels = channels;
  f->transparency = transparency, f->tolerance = tolerance, f->clear_spread = clear_spread;
  const size_t np = (size_t)width * height;
  f->acc = calloc(np * channels, sizeof *f->acc);
  f->marched = calloc(np, 1);
  f->hard = calloc(np, 1);
  f->clear = calloc(np, sizeof *f->clear);
  f->list = malloc(np * sizeof *f->list);
  f->scale = calloc((size_t)channels, sizeof *f->scale);
  int ok = f->acc && f->marched && f->hard && f->clear && f->list && f->scale;
  ok = ok && axis_init(&f->x, width) && axis_init(&f->y, height);
  /* An image shorter than a block along either axis is marched whole. */
  if (ok && (!f->x.n || !f->y.n)) f->x.n = f->y.n = 0;
  for (int l = 0; l < SL__REFINE_LEVELS && ok && f->x.n; ++l) {
    f->state[l] = calloc((size_t)blocks_along(&f->x, l) * blocks_along(&f->y, l), 1);
    ok = f->state[l] != NULL;
  }
  if (!ok) sl__refine_free(f);
  return ok;
}

void sl__refine_free(sl__refine *f)
{
  free(f->acc), free(f->marched), free(f->hard), free(f->clear), free(f->list), free(f->scale);
  free(f->x.origin), free(f->x.block_of), free(f->x.on_first);
  free(f->y.origin), free(f->y.block_of), free(f->y.on_first);
  for (int l = 0; l < SL__REFINE_LEVELS; ++l) free(f->state[l]);
  memset(f, 0, sizeof *f);
}

static void list_pixel(sl__refine *f, int x, int y)
{
  const size_t q = (size_t)y * f->width + x;
  if (f->marched[q]) return;
  f->marched[q] = 1;
  f->list[f->count++] = (int)q;
}

size_t sl__refine_first(sl__refine *f)
{
  f->count = 0;
  f->size = f->x.n ? SL__REFINE_TOP : 0;
  memset(f->marched, 0, (size_t)f->width * f->height);
  for (int y = 0; y < f->height; ++y)
    for (int x = 0; x < f->width; ++x)
      if (!f->x.n || (f->x.on_first[x] && f->y.on_first[y])) list_pixel(f, x, y);
  return f->count;
}

static const float *acc_at(const sl__refine *f, int x, int y)
{
  return f->acc + ((size_t)y * f->width + x) * f->channels;
}

/* One channel of a marched point against its prediction from the corners: the transparency by
 * absolute difference, the others relative to the largest of their magnitudes and the frame's
 * scale. NaN never agrees. */
static int point_agrees(const sl__refine *f, int k, float marched, float predicted)
{
  const float tol = (float)f->tolerance, diff = fabsf(marched - predicted);
  if (k == f->transparency) return marched < 1.0f && diff <= tol;
  return diff <= tol * fmaxf(fmaxf(fabsf(marched), fabsf(predicted)), f->scale[k]);
}

/* The frame's scale per channel from the first list's marched rays: the mean magnitude over those
 * that met medium (transparency below 1), summed in the list's order, so that it does not depend
 * on the thread count. A NaN among them makes the scale NaN, which fmaxf passes over: that
 * channel is then compared as without a scale. */
static void frame_scale(sl__refine *f)
{
  const int nc = f->channels;
  for (int k = 0; k < nc; ++k) {
    size_t held = 0;
    double sum = 0.0;
    for (size_t i = 0; i < f->count; ++i) {
      const float *a = f->acc + (size_t)f->list[i] * nc;
      if (a[f->transparency] < 1.0f) held++, sum += fabsf(a[k]);
    }
    f->scale[k] = held && k != f->transparency ? (float)(sum / (double)held) : 0.0f;
  }
}

/* Every one of the nine rays of the block of `size` at (x0, y0) met no medium and kept far enough
 * from any that the rays between them meet none either (pixel_refine.h): each pixel of the block
 * would march clear, as its nine did. */
static int block_clear(const sl__refine *f, int x0, int y0, int size)
{
  const int h = size / 2;
  const double need = f->clear_spread * h;
  for (int y = y0; y <= y0 + size; y += h)
    for (int x = x0; x <= x0 + size; x += h)
      if (!(f->clear[(size_t)y * f->width + x] > need)) return 0;
  return 1;
}

/* The block of `size` at (x0, y0) is smooth: no opaque surface cuts a ray in it, and either its
 * rays all march clear (block_clear) or its four edge midpoints and its centre agree with the
 * bilinear interpolation of its corners and every one of the nine met some medium (nine clear rays
 * can straddle a small cloud). */
static int block_smooth(const sl__refine *f, int x0, int y0, int size)
{
  const int h = size / 2;
  for (int y = y0; y <= y0 + size; ++y)
    for (int x = x0; x <= x0 + size; ++x)
      if (f->hard[(size_t)y * f->width + x]) return 0;
  if (block_clear(f, x0, y0, size)) return 1;
  const float *c00 = acc_at(f, x0, y0), *c10 = acc_at(f, x0 + size, y0);
  const float *c01 = acc_at(f, x0, y0 + size), *c11 = acc_at(f, x0 + size, y0 + size);
  const float *mid[5] = {acc_at(f, x0 + h, y0), acc_at(f, x0, y0 + h), acc_at(f, x0 + h, y0 + h),
                         acc_at(f, x0 + size, y0 + h), acc_at(f, x0 + h, y0 + size)};
  for (int k = 0; k < f->channels; ++k) {
    const float predicted[5] = {0.5f * (c00[k] + c10[k]), 0.5f * (c00[k] + c01[k]),
                                0.25f * (c00[k] + c10[k] + c01[k] + c11[k]), 0.5f * (c10[k] + c11[k]),
                                0.5f * (c01[k] + c11[k])};
    for (int i = 0; i < 5; ++i)
      if (!point_agrees(f, k, mid[i][k], predicted[i])) return 0;
    if (k == f->transparency && !(c00[k] < 1.0f && c10[k] < 1.0f && c01[k] < 1.0f && c11[k] < 1.0f)) return 0;
  }
  return 1;
}

size_t sl__refine_next(sl__refine *f)
{
  if (f->size == SL__REFINE_TOP) frame_scale(f);
  f->count = 0;
  if (f->size < SL__REFINE_TOP >> (SL__REFINE_LEVELS - 1)) return 0;
  int level = 0;
  while ((SL__REFINE_TOP >> level) > f->size) level++;
  const int size = f->size, step = size / 4;
  const int bw = blocks_along(&f->x, level), bh = blocks_along(&f->y, level);
  unsigned char *state = f->state[level];
  const unsigned char *parent = level ? f->state[level - 1] : NULL;
  const int parent_bw = level ? blocks_along(&f->x, level - 1) : 0;
  for (int j = 0; j < bh; ++j)
    for (int i = 0; i < bw; ++i) {
      unsigned char *s = &state[(size_t)j * bw + i];
      if (parent && parent[(size_t)(j / 2) * parent_bw + i / 2] != BLOCK_SPLITS) {
        *s = BLOCK_INACTIVE;
        continue;
      }
      const int x0 = block_origin(&f->x, level, i), y0 = block_origin(&f->y, level, j);
      *s = block_smooth(f, x0, y0, size) ? BLOCK_SMOOTH : BLOCK_SPLITS;
      if (*s == BLOCK_SPLITS)
        for (int y = y0; y <= y0 + size; y += step)
          for (int x = x0; x <= x0 + size; x += step) list_pixel(f, x, y);
    }
  f->size = size / 2;
  return f->count;
}

void sl__refine_fill(sl__refine *f)
{
  const int nc = f->channels;
  if (!f->x.n) return;
#pragma omp for schedule(static)
  for (int y = 0; y < f->height; ++y)
    for (int x = 0; x < f->width; ++x) {
      const size_t q = (size_t)y * f->width + x;
      if (f->marched[q]) continue;
      /* The pixel lies in a smooth block of some size, whose halfway lattice is marched: a block
       * of 8 that splits lists its halves' halfway points, and one of 4 every pixel. */
      for (int level = 0; level < SL__REFINE_LEVELS; ++level) {
        const int size = SL__REFINE_TOP >> level, half = size / 2;
        const int i = block_holding(&f->x, level, x), j = block_holding(&f->y, level, y);
        if (f->state[level][(size_t)j * blocks_along(&f->x, level) + i] != BLOCK_SMOOTH) continue;
        /* The quarter of the block holding the pixel (its last row and column in the last). */
        const int bx = block_origin(&f->x, level, i), by = block_origin(&f->y, level, j);
        int x0 = bx + (x - bx) / half * half, y0 = by + (y - by) / half * half;
        if (x0 == bx + size) x0 -= half;
        if (y0 == by + size) y0 -= half;
        const float u = (float)(x - x0) / half, v = (float)(y - y0) / half;
        const float *a00 = acc_at(f, x0, y0), *a10 = acc_at(f, x0 + half, y0);
        const float *a01 = acc_at(f, x0, y0 + half), *a11 = acc_at(f, x0 + half, y0 + half);
        float *out = f->acc + q * nc;
        for (int k = 0; k < nc; ++k) {
          const float bottom = a00[k] + u * (a10[k] - a00[k]), top = a01[k] + u * (a11[k] - a01[k]);
          out[k] = bottom + v * (top - bottom);
        }
        break;
      }
    }
}
