/* Internals shared by the two eye passes of render/volume: the half-angle slicer (slicer.c)
 * and the ray marcher over a cached light volume (light_volume.c). Not a public header. */
#ifndef SL_RENDERER_INTERNAL_H
#define SL_RENDERER_INTERNAL_H

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "ground_shadow.h"
#include "lighting.h"
#include "sky_light.h"
#include "sl_large_alloc.h"
#include "sl_renderer.h"
#include "sl_vec3.h"
#include "sun_table.h"


/* The slicer's light-buffer texels' rays (parallel, along the sunlight) through the content box
 * and the stretch of each that crosses occupied bricks, kept from the last frame: they depend on
 * the sun and the texel lattice, not on the camera, and their walks were about 9 ms of a 0.21 s
 * frame. A frame with the same sun and lattice (a camera path
 * at a fixed distance, the same view again) reads them; any other recomputes them. The key is
 * the lattice's exact numbers, so a kept frame is bitwise the frame it would have computed. */
/* The optical depth along a light texel's ray at which the medium counts as entered (u_entry
 * below). Before it ln I and n change by at most this much, which bounds what the kink model of
 * light_kink (light_kink.h) can misplace where the medium thickens gradually (haze). */
#define SL__ENTRY_DEPTH 0.01

typedef struct sl__texel_spans {
  int valid;             /* the arrays hold the spans of the key's lattice */
  double prop[3], a[3], b[3], amin, bmin, texel_a, texel_b;
  int w, h;              /* the arrays' lattice; their size is capacity texels */
  size_t capacity;
  float *u_in, *u_out;   /* each texel ray's interval in the content box (0, 0 when it misses) */
  double *first, *last;  /* its occupied stretch within that (first > last: none) */
  float *u_entry;        /* where along it the medium begins: the optical depth from the box reaches
                            SL__ENTRY_DEPTH there (NaN: never); the eye pass places the light's kink
                            at a cloud's surface between texels by it (light_kink.h) */
} sl__texel_spans;

struct sl_renderer {
  sl_scene scene;
  sl_volume shape;      /* the lattice of the volume, without fields */
  double beta_max;      /* the largest total extinction, m^-1 */
  float *fields;        /* extinction per present field, interleaved (model.nf per sample, one
                           of zeros without any), m^-1;
                           the total (eq. 3) is their sum, taken where it is read
                           (sl__total_extinction): a stored copy would be another field's size */
  sl_light_model model;
  /* Per field mask, the model restricted to those fields (sl_light_model_subset), for the
   * slicer's batches that hold only some; only in the multiple-scattering model with two or more
   * fields (has_subsets), kept in step with model.xi. */
  sl_light_model field_subsets[1 << SL_MAX_FIELDS];
  int has_subsets;
  double to_rgb[3 * SL_MAX_WAVELENGTHS]; /* spectral radiance -> linear sRGB (CIE); identity for RGB */
  int spectral;
  unsigned char *empty_radius; /* per 8^3 brick: 0 where it is occupied (non-zero extinction within
                                 it or one sample around it, the trilinear footprint), else its
                                 Chebyshev distance in bricks to the nearest occupied one (at most
                                 255): every brick less than that from it is empty, so a ray can
                                 jump the whole cube (sl__brick_empty_radius) */
  float *brick_beta_max;    /* per 8^3 brick: the largest total extinction any trilinear cell with
                               its lower corner in it reads (the largest of its corners') */
  int bricks[3];
  unsigned char *clear_blocks; /* per 2^3 block of lattice cells: its Chebyshev distance in blocks to
                                  the nearest block with a cell holding medium (0 there, at most 255);
                                  built with the first refined march (sl__clear_blocks_build) */
  int clear_blocks_n[3];
  float *light_volume;      /* cached light state (I per wavelength, n) per grid sample, or NULL */
  double light_volume_seconds;
  sl__sky_light sky;        /* the skylight's diffuse radiance (scene.skylight), for the current sun */
  sl__ground ground;        /* the ground's shadow map and light (scene.ground_albedo), for the current sun */
  int sky_built;            /* sky and ground hold the current sun's (sl_renderer_prepare_sky) */
  sl__texel_spans texel_spans; /* the slicer's light texels' rays, kept from frame to frame */
  sl_grid_view lattice;     /* the samples' lattice, the rule every trilinear look-up of the fields
                               follows; its data: the one field where there is at most one (so
                               the total), else NULL (the fields are interleaved) */
  double lo[3], hi[3];  /* the volume's box */
  double clo[3], chi[3];    /* the box around non-empty samples: nothing outside it scatters, so
                               slices, light buffer and rays are clipped to it (empty-space skipping
                               at the coarsest level) */
  double content_center[3]; /* its centre: the midplane's anchor */
  int any_extinction;
};

/* The larger and the smaller of two finite numbers, inline: without -ffinite-math-only GCC calls
 * libm's fmax and fmin (through the PLT), which the eye pass did five times per sample. A NaN
 * in a gives b, as fmax and fmin do. */
static inline double sl__max(double a, double b) { return a > b ? a : b; }
static inline double sl__min(double a, double b) { return a < b ? a : b; }

/* Distance from a point inside the box [lo, hi] along dir to the box's boundary, with the face
 * each axis leaves through and its reciprocal prepared once (the slicer's eye pass asks twice per
 * sample toward the sun; six divisions there were a tenth of its time). */
typedef struct sl__box_exit {
  double face[3], inv_dir[3];
  int axis_used[3];
} sl__box_exit;

/* An axis along which dir is below SL__BOX_EXIT_PARALLEL leaves by the other axes: a sun straight
 * down has components of 6e-17 in x or y, and a point a rounding error outside such a face (a
 * segment ending on the box's face) would otherwise be "outside" and get no path at all. */
#define SL__BOX_EXIT_PARALLEL 1e-9
static inline void sl__box_exit_init(sl__box_exit *b, const double lo[3], const double hi[3], const double dir[3])
{
  for (int i = 0; i < 3; ++i) {
    b->axis_used[i] = fabs(dir[i]) > SL__BOX_EXIT_PARALLEL;
    b->face[i] = dir[i] > 0.0 ? hi[i] : lo[i];
    b->inv_dir[i] = b->axis_used[i] ? 1.0 / dir[i] : 0.0;
  }
}

/* Branch-free (an unused axis is a selection), so that the eye pass's loop over a batch of
 * samples vectorises. */
static inline __attribute__((always_inline)) double sl__box_exit_distance(const sl__box_exit *b, const double x[3])
{
  double best = INFINITY;
  for (int i = 0; i < 3; ++i) {
    const double t = b->axis_used[i] ? (b->face[i] - x[i]) * b->inv_dir[i] : INFINITY;
    best = t < best ? t : best;
  }
  return best > 0.0 ? best : 0.0;
}

/* A lattice coordinate u along axis a clamped into the grid (the rule of sl_grid_sample). */
static inline __attribute__((always_inline)) double sl__lattice_clamp(const sl_grid_view *g, double u, int a)
{
  const double umax = (double)(g->n[a] - 1);
  return u < 0.0 ? 0.0 : u > umax ? umax : u;
}

/* x's coordinate along axis a in lattice units, clamped into the grid. */
static inline __attribute__((always_inline)) double sl__lattice_u(const sl_grid_view *g, const double x[3], int a)
{
  return sl__lattice_clamp(g, (x[a] - g->origin[a]) * g->inv_spacing[a], a);
}

/* The lattice cell at lattice coordinates u_in (clamped into the grid, sl__lattice_clamp): its
 * lower corner i0 and the fractions f within it. */
static inline __attribute__((always_inline)) void sl__lattice_cell_at_u(const sl_grid_view *g, const double u_in[3],
                                                                        int i0[3], double f[3])
{
  for (int a = 0; a < 3; ++a) {
    const double u = sl__lattice_clamp(g, u_in[a], a);
    int i = (int)u;
    if (i > g->n[a] - 2) i = g->n[a] - 2;
    if (i < 0) i = 0;
    i0[a] = i;
    f[a] = g->n[a] > 1 ? u - i : 0.0;
  }
}

/* The lattice cell holding x (sl__lattice_cell_at_u at x's lattice coordinates). */
static inline __attribute__((always_inline)) void sl__lattice_cell(const sl_grid_view *g, const double x[3], int i0[3],
                                                                   double f[3])
{
  const double u[3] = {(x[0] - g->origin[0]) * g->inv_spacing[0], (x[1] - g->origin[1]) * g->inv_spacing[1],
                       (x[2] - g->origin[2]) * g->inv_spacing[2]};
  sl__lattice_cell_at_u(g, u, i0, f);
}

/* The index of the 8^3 brick holding lattice cell i0 (in empty_radius, brick_beta_max). */
static inline size_t sl__brick_index(const sl_renderer *r, const int i0[3])
{
  return ((size_t)(i0[2] / 8) * r->bricks[1] + i0[1] / 8) * r->bricks[0] + i0[0] / 8;
}

/* The empty radius of the brick holding lattice cell i0 (0: occupied). */
static inline int sl__brick_radius(const sl_renderer *r, const int i0[3]) { return r->empty_radius[sl__brick_index(r, i0)]; }

static inline int sl__brick_occupied(const sl_renderer *r, const int i0[3]) { return sl__brick_radius(r, i0) == 0; }

/* The brick occupancy of the total extinction inside the content box and each empty brick's radius
 * (r->bricks, r->empty_radius; empty_space.c). */
int sl__bricks_build(sl_renderer *r, sl_error *err);

/* r->clear_blocks, for the adaptive refinement's clear blocks (clear_margin.h). */
int sl__clear_blocks_build(sl_renderer *r, sl_error *err);

/* The content bounds (r->clo, r->chi) from the box of samples that hold medium, medium_lo ..
 * medium_hi (medium_hi[0] < 0: none, the whole box): one cell of margin around it, within the grid's
 * bounds. */
void sl__content_bounds(const sl_renderer *r, const int medium_lo[3], const int medium_hi[3], double lo[3],
                        double hi[3]);

/* Chebyshev distance transform of a brick lattice, in place: on entry radius[b] is 0 for an
 * occupied brick and non-zero for an empty one; on return each empty brick holds its distance to
 * the nearest occupied brick, max over the axes of |b - o|, capped at 255 (255 also where no brick
 * is occupied). Index (z * n[1] + y) * n[0] + x. */
void sl__brick_empty_radius(const int n[3], unsigned char *radius);

/* The part [*first, *last] of the stretch [t0, t1] of the ray o + t d that crosses occupied
 * bricks; *first > *last when it crosses none (empty_space.c). */
void sl__occupied_span(const sl_renderer *r, const double o[3], const double d[3], double t0, double t1,
                       double *first, double *last);

/* The last 8^3 brick along axis a that a point can fall in: cells stop at n - 2 (the clamp of
 * sl__lattice_cell), so that brick also holds the points up to the box's face. */
static inline int sl__last_brick(const sl_grid_view *g, int a) { return g->n[a] > 1 ? (g->n[a] - 2) / 8 : 0; }

/* Runs BODY(f, nf, nwl) inside one OpenMP parallel region, with the model's field count nf and
 * wavelength count nwl as constants for the pairs the passes are compiled for (one to four
 * fields at three wavelengths and at sixteen), and as run-time values otherwise. The region is
 * opened here, around the always-inlined body: GCC outlines a region before it inlines, so a
 * region opened inside the body would see the counts as run-time values. */
#define SL_RUN_SPECIALISED(BODY, f, nf, nwl) \
  do { \
    const int sl_nf_ = (nf), sl_nwl_ = (nwl); \
    SL_SPECIALISE_CASE(BODY, f, 1, 3) SL_SPECIALISE_CASE(BODY, f, 2, 3) \
    SL_SPECIALISE_CASE(BODY, f, 3, 3) SL_SPECIALISE_CASE(BODY, f, 4, 3) \
    SL_SPECIALISE_CASE(BODY, f, 1, 16) SL_SPECIALISE_CASE(BODY, f, 2, 16) \
    SL_SPECIALISE_CASE(BODY, f, 3, 16) SL_SPECIALISE_CASE(BODY, f, 4, 16) \
    _Pragma("omp parallel") BODY(f, sl_nf_, sl_nwl_); \
  } while (0)
#define SL_SPECIALISE_CASE(BODY, f, NF, NWL) \
  if (sl_nf_ == NF && sl_nwl_ == NWL) { \
    _Pragma("omp parallel") BODY(f, NF, NWL); \
    break; \
  }

/* The passes are compiled twice: for baseline x86-64 and, beside it, for AVX-512 (eight doubles
 * per vector in the loops GCC vectorises across samples), chosen at run time by sl__wide_isa.
 * The wide copy is the same text: an always-inlined pass body may be inlined into a function of
 * a wider target, and OpenMP's outlined regions keep their parent's target. sl_volume builds
 * with -ffp-contract=off, so neither copy fuses a multiply and an add: both round alike, and
 * only libmvec's exp and log (each within 4 ulp) may differ in the last bits. */
/* Only in optimised builds: unoptimised (the sanitizer build), nothing is inlined, so the wide copy
 * would call baseline helpers (sl__load_v4f, ...) from AVX-512 code at every sample and pay the
 * switch between the two encodings each time (test_slicing: 20 min instead of 1 under ASan). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__OPTIMIZE__)
#define SL_WIDE_TARGET __attribute__((target("avx512f,avx512dq,avx512vl,avx512bw,avx2,avx,popcnt")))
static inline int sl__wide_isa(const sl_scene *sc)
{
  __builtin_cpu_init();
  return !sc->baseline_isa && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw");
}
#endif

/* Four floats as one value: four fields of a lattice sample (interleaved) are one 16-byte load,
 * and the seven lerps of a trilinear look-up run on all of them at once. */
typedef float sl__v4f __attribute__((vector_size(16)));

static inline sl__v4f sl__load_v4f(const float *p)
{
  sl__v4f v;
  memcpy(&v, p, sizeof v);
  return v;
}

/* Trilinear interpolation of four interleaved floats at the cell whose lower corner is c (the
 * neighbours sx, sy, sz floats apart; 0 along an axis of one sample), fractions fx, fy, fz. */
static inline __attribute__((always_inline)) sl__v4f sl__trilinear_v4f(const float *c, size_t sx, size_t sy, size_t sz,
                                                                     float fx, float fy, float fz)
{
  const sl__v4f c00 = sl__load_v4f(c) + fx * (sl__load_v4f(c + sx) - sl__load_v4f(c));
  const sl__v4f c10 = sl__load_v4f(c + sy) + fx * (sl__load_v4f(c + sy + sx) - sl__load_v4f(c + sy));
  const sl__v4f c01 = sl__load_v4f(c + sz) + fx * (sl__load_v4f(c + sz + sx) - sl__load_v4f(c + sz));
  const sl__v4f c11 = sl__load_v4f(c + sz + sy) + fx * (sl__load_v4f(c + sz + sy + sx) - sl__load_v4f(c + sz + sy));
  const sl__v4f c0 = c00 + fy * (c10 - c00), c1 = c01 + fy * (c11 - c01);
  return c0 + fz * (c1 - c0);
}

/* A field look-up in two steps, so that a pass can find a batch of samples' cells (and prefetch
 * them) before it loads any: the loads of a batch then overlap instead of each waiting on memory
 * in turn (at 256^3 the light pass waits on these loads). */
typedef struct sl__field_cell {
  const float *c; /* the cell's lowest corner in the interleaved field array */
  float f[3];     /* the fractions within it */
} sl__field_cell;

/* Whether x lies in the lattice's box (outside it every field is zero; false for NaN), as one
 * expression without branches, so that a loop over a batch of points vectorises. */
static inline __attribute__((always_inline)) int sl__in_lattice_box(const sl_grid_view *g, const double x[3])
{
  return (x[0] >= g->lo[0]) & (x[0] <= g->hi[0]) & (x[1] >= g->lo[1]) & (x[1] <= g->hi[1]) & (x[2] >= g->lo[2]) &
         (x[2] <= g->hi[2]);
}

/* The far end o + t d of an eye segment, clamped into the lattice's box: a segment that ends on
 * the box's face reads the medium there however the rounding puts its end (unclamped, a camera
 * moved by a micrometre put it in or out and changed the frame). */
static inline __attribute__((always_inline)) void sl__segment_far_end(const sl_grid_view *g, const double o[3],
                                                                      const double *d, double t, double x[3])
{
  for (int a = 0; a < 3; ++a) x[a] = sl__min(sl__max(o[a] + t * d[a], g->lo[a]), g->hi[a]);
}

/* The cell (i0, f) of a point in the box, whatever its brick. */
static inline __attribute__((always_inline)) void sl__field_cell_fill(const sl_renderer *r, const int nf,
                                                                      const int i0[3], const double f[3],
                                                                      sl__field_cell *cell)
{
  const sl_grid_view *g = &r->lattice;
  cell->c = r->fields + (((size_t)i0[2] * g->n[1] + i0[1]) * g->n[0] + i0[0]) * nf;
  for (int a = 0; a < 3; ++a) cell->f[a] = (float)f[a];
}

/* The second step of sl__field_cell_at, for a point in the box whose lattice cell (i0, f) is
 * known: 0 in an empty brick; else the cell, its four rows (its eight corners) prefetched when
 * asked. */
static inline __attribute__((always_inline)) int sl__field_cell_of(const sl_renderer *r, const int nf,
                                                                   const int i0[3], const double f[3],
                                                                   const int prefetch, sl__field_cell *cell)
{
  const sl_grid_view *g = &r->lattice;
  if (!sl__brick_occupied(r, i0)) return 0;
  sl__field_cell_fill(r, nf, i0, f, cell);
  if (prefetch) {
    const size_t sy = g->n[1] > 1 ? (size_t)g->n[0] * nf : 0;
    const size_t sz = g->n[2] > 1 ? (size_t)g->n[0] * g->n[1] * nf : 0;
    /* Each row's two corners are 2 nf floats from the cell's corner on: its first and last byte. */
    const float *rows[4] = {cell->c, cell->c + sy, cell->c + sz, cell->c + sy + sz};
    for (int k = 0; k < 4; ++k) {
      __builtin_prefetch(rows[k]);
      __builtin_prefetch(rows[k] + 2 * nf - 1);
    }
  }
  return 1;
}

/* The cell of x (the lattice rule of sl_grid_sample); 0 outside the box or in an empty brick,
 * where every field is zero. Prefetches the cell's four rows when asked. */
static inline __attribute__((always_inline)) int sl__field_cell_at(const sl_renderer *r, const int nf,
                                                                   const double x[3], const int prefetch,
                                                                   sl__field_cell *cell)
{
  const sl_grid_view *g = &r->lattice;
  int i0[3];
  double f[3];
  if (!sl__in_lattice_box(g, x)) return 0;
  sl__lattice_cell(g, x, i0, f);
  return sl__field_cell_of(r, nf, i0, f, prefetch, cell);
}

/* Floats sl__field_fetch writes: two four-float lerps cover the six particle types. */
#define SL__FIELD_LANES 8
/* The trilinear interpolation of every field in a cell found by sl__field_cell_at, into
 * out[0..nf-1] (lanes past nf hold junk). Fields 0-3 are one four-float lerp; a volume with more
 * than four (graupel or hail beside cloud, rain, ice and snow) pays a second one for 4-7. The
 * field array is padded by SL__FIELD_LANES floats, so the last sample's loads stay inside it. */
static inline __attribute__((always_inline)) void sl__field_fetch(const sl_renderer *r, const int nf,
                                                                  const sl__field_cell *cell, float *out)
{
  const sl_grid_view *g = &r->lattice;
  const size_t sx = g->n[0] > 1 ? (size_t)nf : 0;
  const size_t sy = g->n[1] > 1 ? (size_t)g->n[0] * nf : 0;
  const size_t sz = g->n[2] > 1 ? (size_t)g->n[0] * g->n[1] * nf : 0;
  const sl__v4f lo = sl__trilinear_v4f(cell->c, sx, sy, sz, cell->f[0], cell->f[1], cell->f[2]);
  memcpy(out, &lo, sizeof lo);
  if (nf > 4) {
    const sl__v4f hi = sl__trilinear_v4f(cell->c + 4, sx, sy, sz, cell->f[0], cell->f[1], cell->f[2]);
    memcpy(out + 4, &hi, sizeof hi);
  }
}

/* The total extinction in a cell found by sl__field_cell_at (sl__field_fetch's fields summed, in
 * double, field by field). */
static inline __attribute__((always_inline)) double sl__field_total(const sl_renderer *r, const int nf,
                                                                    const sl__field_cell *cell)
{
  float v[SL__FIELD_LANES];
  sl__field_fetch(r, nf, cell, v);
  double total = 0.0;
  for (int j = 0; j < nf; ++j) total += v[j];
  return total;
}

/* Trilinear sample of every field's extinction at x (the same lattice rule as sl_grid_sample, in
 * float); returns 0 and zeros outside the box or in an empty brick. nf is r->model.nf, passed
 * apart so that the specialised passes give it as a constant. */
static inline __attribute__((always_inline)) int sl__sample_fields_n(const sl_renderer *r, const int nf,
                                                                     const double x[3], float *out)
{
  sl__field_cell cell;
  if (!sl__field_cell_at(r, nf, x, 0, &cell)) {
    for (int j = 0; j < nf; ++j) out[j] = 0.0f;
    return 0;
  }
  float v[SL__FIELD_LANES];
  sl__field_fetch(r, nf, &cell, v);
  for (int j = 0; j < nf; ++j) out[j] = v[j];
  return 1;
}

/* The total extinction at a sample whose fields start at c (Riley et al. 2004, eq. 3): the sum of
 * the nf interleaved fields, in float, field by field. With one field it is that field. */
static inline __attribute__((always_inline)) float sl__sample_total(const float *c, const int nf)
{
  float s = c[0];
  for (int j = 1; j < nf; ++j) s += c[j];
  return s;
}

/* Trilinear sample of the total extinction at x; 0 outside the box. One field: sl_grid_sample on
 * it (r->lattice's data). More: every field's trilinear sample at once (sl__field_fetch), summed,
 * as the passes' own samples are; 0 in an empty brick, where every cell reads zeros. nf is
 * r->model.nf, passed apart so that the specialised passes give it as a constant. */
static inline __attribute__((always_inline)) double sl__total_extinction_n(const sl_renderer *r, const int nf,
                                                                         const double x[3])
{
  if (nf <= 1) return sl_grid_sample(&r->lattice, x);
  sl__field_cell cell;
  return sl__field_cell_at(r, nf, x, 0, &cell) ? sl__field_total(r, nf, &cell) : 0.0;
}

static inline double sl__total_extinction(const sl_renderer *r, const double x[3])
{
  return sl__total_extinction_n(r, r->model.nf, x);
}

/* Pieces a short segment's optical depth is summed in at most (sl__segment_optical_depth). */
#define SL__SEGMENT_PIECES 8
/* The optical depth of the segment a -> b (a few cells at most; nf is r->model.nf): between the
 * lattice's node planes the trilinear field is a cubic along a line, which the two-point
 * Gauss-Legendre rule integrates exactly, so the segment is cut where it crosses them and each
 * piece is taken by that rule (which reads no end point: a segment ending on the box's face, where
 * the medium stops, is not read there). Exact where the segment crosses fewer than
 * SL__SEGMENT_PIECES pieces, each piece's cell found once; past that, equal pieces. A cloud's
 * surface where its density ramps up from zero within a cell is then integrated wherever it lies
 * along the segment, as a single midpoint is not. */
static inline __attribute__((always_inline)) double sl__segment_optical_depth(const sl_renderer *r, const int nf,
                                                                              const double a_in[3],
                                                                              const double b_in[3])
{
  const sl_grid_view *g = &r->lattice;
  /* Both ends lie in the box up to a rounding error (an eye sample and its light path's start
   * toward the sun), so the segment does: each end is clamped into it. Where the sun runs along a
   * face and the segment lies in it, the rounding would otherwise put the whole segment in or out. */
  double a[3], b[3];
  for (int ax = 0; ax < 3; ++ax) {
    a[ax] = sl__min(sl__max(a_in[ax], g->lo[ax]), g->hi[ax]);
    b[ax] = sl__min(sl__max(b_in[ax], g->lo[ax]), g->hi[ax]);
  }
  double cut[3 * SL__SEGMENT_PIECES + 2];
  int n = 0;
  cut[n++] = 0.0;
  /* The ends in lattice coordinates, in which the pieces' cells and Gauss points are found. */
  double ua[3], du[3];
  for (int ax = 0; ax < 3; ++ax) {
    ua[ax] = (a[ax] - g->origin[ax]) * g->inv_spacing[ax];
    const double ub = (b[ax] - g->origin[ax]) * g->inv_spacing[ax];
    du[ax] = ub - ua[ax];
    if (g->n[ax] < 2 || ua[ax] == ub) continue;
    const double lo = sl__min(ua[ax], ub), hi = sl__max(ua[ax], ub);
    for (double k = floor(lo) + 1.0; k < hi && n < 3 * SL__SEGMENT_PIECES; k += 1.0) cut[n++] = (k - ua[ax]) / du[ax];
  }
  const int equal_pieces = n > SL__SEGMENT_PIECES;
  if (equal_pieces) {
    n = SL__SEGMENT_PIECES;
    for (int i = 0; i < n; ++i) cut[i] = (double)i / n;
  }
  /* Sorted by insertion (a few values). */
  for (int i = 1; i < n; ++i)
    for (int j = i; j > 0 && cut[j] < cut[j - 1]; --j) {
      const double t = cut[j];
      cut[j] = cut[j - 1], cut[j - 1] = t;
    }
  cut[n] = 1.0;
  const double len = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
  const double node = 0.5 / sqrt(3.0); /* the Gauss points at the piece's middle -+ node x its length */
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double l0 = cut[i], l1 = cut[i + 1];
    if (equal_pieces || nf <= 1) {
      for (int k = 0; k < 2; ++k) {
        const double l = 0.5 * (l0 + l1) + (k ? node : -node) * (l1 - l0);
        const double x[3] = {a[0] + l * (b[0] - a[0]), a[1] + l * (b[1] - a[1]), a[2] + l * (b[2] - a[2])};
        sum += 0.5 * (l1 - l0) * sl__total_extinction_n(r, nf, x);
      }
      continue;
    }
    /* A piece between node planes lies in one lattice cell: found once, at its middle (in the box,
     * as both ends are), its brick tested once, and each Gauss point's fractions taken in it, all
     * from the ends' lattice coordinates (linear along the segment) as sl__lattice_cell_at_u
     * takes them. */
    const double lm = 0.5 * (l0 + l1);
    const double um[3] = {ua[0] + lm * du[0], ua[1] + lm * du[1], ua[2] + lm * du[2]};
    int i0[3];
    double fm[3];
    sl__lattice_cell_at_u(g, um, i0, fm);
    sl__field_cell cell;
    if (!sl__field_cell_of(r, nf, i0, fm, 0, &cell)) continue;
    for (int k = 0; k < 2; ++k) {
      const double l = lm + (k ? node : -node) * (l1 - l0);
      for (int ax = 0; ax < 3; ++ax) {
        const double u = sl__lattice_clamp(g, ua[ax] + l * du[ax], ax);
        cell.f[ax] = g->n[ax] > 1 ? (float)(u - i0[ax]) : 0.0f;
      }
      sum += 0.5 * (l1 - l0) * sl__field_total(r, nf, &cell);
    }
  }
  return sum * len;
}

/* The fields that a batch of samples holds (a slicer batch lies in one tile of one slice, a march
 * batch along a few cells of one ray: in a storm mostly one or two of the four, cloud and rain
 * low, ice and snow high), packed to the front of each sample's array with *model set to the
 * model restricted to them (sl_light_model_subset: the same results, bitwise, without the absent
 * fields' table reads); returns their count, or nf (nothing changed) when the batch holds every
 * field or there are no subsets. */
static inline __attribute__((always_inline)) int sl__batch_fields(const sl_light_model *subsets, const int nf,
                                                              const int cnt, float (*fields)[SL_MAX_FIELDS],
                                                              const sl_light_model **model)
{
  if (!subsets || nf < 2) return nf;
  unsigned mask = 0;
  for (int i = 0; i < cnt; ++i)
    for (int j = 0; j < nf; ++j) mask |= (unsigned)(fields[i][j] > 0.0f) << j;
  const int held = __builtin_popcount(mask);
  if (held == 0 || held >= nf) return nf;
  int from[SL_MAX_FIELDS], k = 0;
  for (int j = 0; j < nf; ++j)
    if (mask >> j & 1u) from[k++] = j;
  for (int i = 0; i < cnt; ++i)
    for (int j = 0; j < held; ++j) fields[i][j] = fields[i][from[j]];
  *model = &subsets[mask];
  return held;
}

/* Calls CALL(model, mode, count) for a batch whose fields sl__batch_fields packed: with the
 * subset model and its field count (a constant up to 3) when the batch holds fewer than nf fields
 * (multiple mode only, where subsets exist), else with the whole model, and the mode as a
 * constant for the two common ones, so that each call's loops unroll and vectorise for it. */
#define SL_WITH_BATCH_MODEL(m, held_model, held, nf, CALL) \
  do { \
    if ((held) < (nf)) { \
      if ((held) == 1) CALL((held_model), SL_LIGHTING_MULTIPLE, 1); \
      else if ((nf) > 2 && (held) == 2) CALL((held_model), SL_LIGHTING_MULTIPLE, 2); \
      else if ((nf) > 3 && (held) == 3) CALL((held_model), SL_LIGHTING_MULTIPLE, 3); \
      else CALL((held_model), SL_LIGHTING_MULTIPLE, (held)); \
    } else if ((m)->mode == SL_LIGHTING_MULTIPLE) CALL((m), SL_LIGHTING_MULTIPLE, (nf)); \
    else if ((m)->mode == SL_LIGHTING_LOW_ALBEDO) CALL((m), SL_LIGHTING_LOW_ALBEDO, (nf)); \
    else CALL((m), (int)(m)->mode, (nf)); \
  } while (0)

/* Optical depth of the ray o + t d through the total extinction over [t0, t1] by the midpoint rule
 * in steps of `step`, stopping where it reaches `stop` (*t_stop there; +inf when it never does;
 * surface_sunlight.c). */
double sl__optical_depth(const sl_renderer *r, const double o[3], const double d[3], double t0, double t1,
                         double step, double stop, double *t_stop);

/* The light-volume march's samples per grid cell (sl_scene.march_samples, 0 meaning 1: with thick
 * steps in parts, one per cell is nearer 8 than two taken whole were, docs/ACCURACY.md). */
static inline int sl__march_samples(const sl_scene *sc) { return sc->march_samples > 0 ? sc->march_samples : 1; }

/* A frame of the half-angle slicer (slicer.c); fwd, right, up: the camera's basis. */
int sl__render_slicer(sl_renderer *r, const sl_camera *cam, const double fwd[3], const double right[3],
                      const double up[3], sl_image *img, sl_render_stats *stats, sl_error *err);

/* The eye pass of the cached light volume (light_volume.c). */
int sl__render_with_light_volume(sl_renderer *r, const sl_camera *cam, sl_image *img, sl_render_stats *stats,
                                 sl_error *err);

#endif
