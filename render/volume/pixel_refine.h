/* Adaptive refinement of an image's rays (after Levoy's "volume rendering by adaptive
 * refinement", in blocks): march the rays of every SL__REFINE_TOP/2-th pixel first, so that each
 * block of SL__REFINE_TOP pixels has its corners and the five points halfway between them. The
 * blocks tile the image from its first pixel; where its last column (row) is not on that lattice,
 * a last column (row) of blocks ends on it, overlapping the one before, so that the image's edges
 * are judged as its middle is. Where
 * those five agree with the bilinear interpolation of the corners within a tolerance, the block is
 * smooth: its pixels take their accumulators by bilinear interpolation of the nine (a quarter of
 * the error the test measured, where the image is smooth). Elsewhere the block splits in four,
 * their halfway points are marched and judged alike, and a block of 4 that splits has every pixel
 * marched. The radiances and the depth numerator are compared relative to the larger of their
 * own magnitude and the frame's scale: the mean over the first list's rays that met medium. A dim
 * stretch of cloud (a shadowed flank, a thin edge) is then held to the absolute error that the
 * tolerance allows the frame's typical cloud, not to a finer one: what an image's error measures
 * (docs/ACCURACY.md, "Adaptive pixels"). A block holding a clear ray still splits, so a cloud's
 * edge is marched at every pixel. A block whose nine rays met no medium splits too (nine clear
 * rays can straddle a small cloud), unless each ray kept far enough from any medium (clear_margin.h) that every ray between
 * them is clear as well. What is interpolated is the march's accumulator (radiance per wavelength,
 * transparency, depth numerator); each pixel's own ray still resolves it against the air in front
 * (sl__resolve_pixel), so the sky and the aerial perspective stay exact. Which rays are marched
 * depends only on marched values: the image does not depend on the thread count. */
#ifndef SL_PIXEL_REFINE_H
#define SL_PIXEL_REFINE_H

#include <stddef.h>

#define SL__REFINE_TOP 8    /* the coarsest block, in pixels */
#define SL__REFINE_LEVELS 2 /* blocks of 8 and 4 are judged */

/* The blocks of SL__REFINE_TOP pixels along one axis of the image: one every SL__REFINE_TOP pixels
 * from 0, and, where the image's last pixel is not on that lattice, one more ending on it, which
 * overlaps the one before. */
typedef struct sl__refine_axis {
  int n;         /* blocks along the axis (0: shorter than a block, marched whole) */
  int *origin;   /* n: each block's first pixel */
  int *block_of; /* per pixel: the block holding it (of two that overlap, the first) */
  unsigned char *on_first; /* per pixel: 1 on a block's corner or midpoint (the first list's) */
} sl__refine_axis;

typedef struct sl__refine {
  int width, height, channels;
  int transparency; /* the channel compared by absolute difference (the others relatively) */
  double tolerance;
  float *scale;                    /* per channel: the frame's scale (set after the first list) */
  sl__refine_axis x, y;            /* the blocks across and down */
  float *acc;                      /* width * height * channels: the accumulators */
  unsigned char *marched;          /* per pixel: 1 once its ray is in the list to march */
  unsigned char *hard;             /* per pixel, set by the caller: 1 where the ray meets an
                                      opaque surface (a block holding one never interpolates) */
  float *clear;                    /* per marched pixel, set by the caller: its ray's clearance
                                      ratio where it met no medium (clear_margin.h), else 0 */
  double clear_spread;             /* the clearance ratio that rays a pixel apart need */
  unsigned char *state[SL__REFINE_LEVELS]; /* per block of each size: refine_state */
  int *list;                       /* the pixels to march next */
  size_t count;
  int size;                        /* the block size judged next */
} sl__refine;

/* Room for a width x height image with `channels` floats per pixel; 0 when out of memory. A block
 * whose nine rays met no medium is smooth where every one's clearance ratio exceeds clear_spread
 * times their spacing in pixels: the rays between them then meet none either. */
int sl__refine_init(sl__refine *f, int width, int height, int channels, int transparency, double tolerance,
                    double clear_spread);
void sl__refine_free(sl__refine *f);
/* The first list: the corners, edge midpoints and centre of every block of SL__REFINE_TOP (every
 * pixel where the image is shorter than a block along an axis). Returns the list's length. */
size_t sl__refine_first(sl__refine *f);
/* After the last list's rays are in acc: judges the blocks of the current size whose larger block
 * split, and lists the halfway points of the halves of those that split too. Returns the list's
 * length, 0 when every pixel is marched or inside a smooth block. */
size_t sl__refine_next(sl__refine *f);
/* Fills every pixel that was not marched from the four marched pixels around it in its smooth
 * block (an orphaned `omp for`: called from inside a parallel region, the threads share the rows). */
void sl__refine_fill(sl__refine *f);

#endif
