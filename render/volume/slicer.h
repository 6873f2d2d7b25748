/* The half-angle slicer's shared structures (Riley et al. 2004, sec. 4): the light buffer
 * perpendicular to the sunlight, a frame's set-up, and the per-row and per-texel steps its eye
 * and light passes share. slicing.c chooses the slices and the light buffer's lattice;
 * slicer.c runs the passes. */
#ifndef SL_SLICER_H
#define SL_SLICER_H

#include "renderer_internal.h"
#include "sl_sample_physics.h"
#include "slice_barrier.h"
#include "tiles.h"
#include "vector_math.h"

/* Doubles per pixel ray in the frame's ray array: direction xyz, t_in, t_out, h.d, 1 / h.d. */
#define RAY_STRIDE 7

/* One sample's stretch of a ray: the slab [c - half, c + half] clipped to [t0, t1], its middle and
 * length; 0 when nothing is left. Selections, no branch: the passes' set-up loops vectorise. */
static inline __attribute__((always_inline)) int clip_segment(double c, double half, double t0, double t1,
                                                              double *mid, double *len)
{
  const double a = c - half > t0 ? c - half : t0;
  const double b = c + half < t1 ? c + half : t1;
  *mid = 0.5 * (a + b);
  *len = b - a;
  return b > a;
}

typedef struct light_buffer {
  int w, h;
  double a[3], b[3];   /* texel axes, unit, perpendicular to the propagation direction */
  double amin, bmin, texel_a, texel_b, inv_texel_a, inv_texel_b; /* texel sizes along a and b */
  int stride;          /* nwl log intensities (relative to the sunlight above the volume) and n */
  float *state;        /* per texel: ln I per wavelength, then the expected scattering count n. ln I,
                          as in the light volume: a light step adds eq. 24's log kept fraction (no
                          exponential), the eye gather wants the log-linear slope, and bilinear
                          interpolation of ln I keeps an exponential fall-off exact */
  float *u_in, *u_out; /* each texel ray's interval in the box */
  const float *u_entry; /* where each texel ray enters the medium (sl__texel_spans; NaN: never) */
  double *h_origin;    /* h . (texel ray origin) */
  /* The kink at a cloud's surface (light_kink): per texel its entry as g = h_origin / hp + u_entry,
   * so that a texel's ray has run e = s / hp - g into the medium at the slice plane s (NaN: never);
   * per texel cell (the texel and its neighbours along +a and +b) the least and largest g of its
   * corners, NaN excluded; per texel the state (as state) where its ray entered. */
  double *entry_g, *cell_gmin, *cell_gmax;
  float *entry_state;
  int *k_lo, *k_hi;    /* slices a texel ray crosses */
} light_buffer;

/* One row of a tile in one slice, its samples found in two steps: first every lane's segment and
 * lattice cell in a loop without branches (vector code: row_lattice_set per lane), then per lane
 * that holds a sample its brick flag, cell and prefetch (row_cells). Found one at a time, the
 * light pass's cells were a fifth of its time. The light pass's lanes are a row's texels; the
 * eye pass's only the pixels whose span holds the slice (most of a row's do not, and all sixteen
 * as lanes made it 5-10 % slower). */
typedef struct row_lattice {
  int take[TILE];   /* the lane's ray or texel crosses this slice within its span */
  int inside[TILE]; /* its point lies in the lattice's box */
  int i0[3][TILE];
  double f[3][TILE];
} row_lattice;

static inline __attribute__((always_inline)) void row_lattice_set(row_lattice *rl, int i, const sl_grid_view *g,
                                                                  const double x[3])
{
  int cell[3];
  double frac[3];
  rl->inside[i] = sl__in_lattice_box(g, x);
  sl__lattice_cell(g, x, cell, frac);
  for (int a = 0; a < 3; ++a) rl->i0[a][i] = cell[a], rl->f[a][i] = frac[a];
}

/* The lanes 0..n-1 of a row that hold a sample, counted into *samples; of those, the ones whose
 * cell is in the box and in an occupied brick get their cell (prefetched) in cells[] and their
 * lane in lanes[], in order; so do those whose far end's cell (far, unless NULL) is in an occupied
 * brick, whose middle's empty cell reads no medium (the eye pass, where a cloud's surface may lie
 * in the far half of a segment whose middle is clear). With far, each such sample's far end's
 * cell goes to far_cells[] (prefetched; its c NULL where the far end reads no medium: outside the
 * box or in an empty brick). Returns how many did. */
static inline __attribute__((always_inline)) int row_cells(const sl_renderer *r, const int nf, const row_lattice *rl,
                                                           const row_lattice *far, int n, long *samples, int *lanes,
                                                           sl__field_cell *cells, sl__field_cell *far_cells)
{
  int cnt = 0;
  for (int i = 0; i < n; ++i) {
    if (!rl->take[i]) continue;
    ++*samples;
    const int cell[3] = {rl->i0[0][i], rl->i0[1][i], rl->i0[2][i]};
    const double frac[3] = {rl->f[0][i], rl->f[1][i], rl->f[2][i]};
    if (!rl->inside[i]) continue;
    int far_occupied = 0;
    if (far) {
      const int far_cell[3] = {far->i0[0][i], far->i0[1][i], far->i0[2][i]};
      const double far_frac[3] = {far->f[0][i], far->f[1][i], far->f[2][i]};
      far_occupied = far->inside[i] && sl__field_cell_of(r, nf, far_cell, far_frac, 1, &far_cells[cnt]);
      if (!far_occupied) far_cells[cnt].c = NULL;
    }
    if (!sl__field_cell_of(r, nf, cell, frac, 1, &cells[cnt])) {
      if (!far_occupied) continue;
      sl__field_cell_fill(r, nf, cell, frac, &cells[cnt]);
    }
    lanes[cnt++] = i;
  }
  return cnt;
}

/* Bilinear look-up of the light buffer's state (ln I per wavelength and n) at a point's projection,
 * in two steps for the eye pass's loops over a batch of samples: first per sample its texel and
 * weights (light_texel_lane, no branch: the buffer's one-texel axes are selections, so the batch
 * loop around it vectorises), then the lerps (light_bilinear_texel). The offsets are ints, which
 * the frame's buffer size bounds (sl__render_slicer refuses 2^31 values or more). */
static inline __attribute__((always_inline)) void light_texel_lane(const light_buffer *L, const double x[3],
                                                                   int *texel, double *u, double *v)
{
  double fa = (L->a[0] * x[0] + L->a[1] * x[1] + L->a[2] * x[2] - L->amin) * L->inv_texel_a - 0.5;
  double fb = (L->b[0] * x[0] + L->b[1] * x[1] + L->b[2] * x[2] - L->bmin) * L->inv_texel_b - 0.5;
  fa = sl__min(sl__max(fa, 0.0), (double)(L->w - 1));
  fb = sl__min(sl__max(fb, 0.0), (double)(L->h - 1));
  int i = (int)fa, j = (int)fb;
  const int top_i = L->w > 1 ? L->w - 2 : 0, top_j = L->h > 1 ? L->h - 2 : 0;
  i = i < top_i ? i : top_i;
  j = j < top_j ? j : top_j;
  *u = L->w > 1 ? fa - i : 0.0;
  *v = L->h > 1 ? fb - j : 0.0;
  *texel = (j * L->w + i) * L->stride;
}

/* The offsets of a texel's neighbours along a and b (di, dj), 0 along an axis of one texel. */
static inline void light_texel_steps(const light_buffer *L, ptrdiff_t *di, ptrdiff_t *dj)
{
  *di = L->w > 1 ? L->stride : 0;
  *dj = L->h > 1 ? (ptrdiff_t)L->w * L->stride : 0;
}

/* Floats past the last texel's channels that the buffer holds (zeros), so that
 * light_bilinear_texel's four-channel loads stay inside it. */
#define LIGHT_STATE_PAD 3

typedef double light_v4d __attribute__((vector_size(32)));

/* The light buffer's channels 0..channels-1 at texel t (its neighbours di, dj apart), weights u
 * and v, into out[] (rounded up to a multiple of four: the lanes past `channels` hold junk): a
 * texel's channels lie together, so four of them are one 16-byte load per corner and their lerps
 * one vector operation, against a loop per channel over the batch that gathers each float
 * (tests/bench/bench_light_lookup: this form 1.27 times faster at 16 wavelengths, the loop per
 * channel slightly faster at 3 where the gathers are instructions; docs/PERFORMANCE.md). Each
 * channel's value is bitwise that of the scalar lerps st[t] + u (st[t + di] - st[t]) in double,
 * the corners' difference in float. */
static inline __attribute__((always_inline)) void light_bilinear_texel(const float *st, int di, int dj, int t,
                                                                       double u, double v, const int channels,
                                                                       double *out)
{
  for (int c = 0; c < channels; c += 4) {
    const float *p = st + t + c;
    const sl__v4f c00 = sl__load_v4f(p), c10 = sl__load_v4f(p + di);
    const sl__v4f c01 = sl__load_v4f(p + dj), c11 = sl__load_v4f(p + dj + di);
    const light_v4d r0 = __builtin_convertvector(c00, light_v4d) + u * __builtin_convertvector(c10 - c00, light_v4d);
    const light_v4d r1 = __builtin_convertvector(c01, light_v4d) + u * __builtin_convertvector(c11 - c01, light_v4d);
    const light_v4d r = r0 + v * (r1 - r0);
    memcpy(out + c, &r, sizeof r);
  }
}

/* The light steps of one tile's samples in a slice, collected first so that the loop over them
 * vectorises: sample i is texel idx[i], chord seg[i], per-field extinction bj[i]. The texels of a
 * tile are distinct, so the iterations are independent (ivdep). */
static inline __attribute__((always_inline)) void light_steps(const sl_light_model *m, const int mode, const int nf,
                                                              const int nwl, const int cnt, const int *idx,
                                                              const double *seg, float (*bj)[SL_MAX_FIELDS],
                                                              float *state, const int stride)
{
#pragma GCC ivdep
  for (int i = 0; i < cnt; ++i) sl_log_light_step_at(m, mode, nf, nwl, bj[i], seg[i], state, idx[i] * stride);
}

/* Everything a frame of the slicer needs once its buffers are set up. */
typedef struct slicer_frame {
  sl_renderer *r;
  const sl_camera *cam;
  sl_image *img;
  const sl_sky_view *view;
  sun_table *suntab;
  light_buffer *L;
  tile_ranges *eye_tiles, *light_tiles;
  float *acc;
  double *ray;
  int *pk, *angle_index;
  float *angle_weight;
  const sl_phase_table *grid_table;
  const sl_light_model *subsets; /* per field mask, the model restricted to it (multiple mode), or NULL */
  double fwd[3], right[3], up[3], h[3], prop[3];
  sl__box_exit sun_exit;
  double tan_half, aspect, h_o, hp, inv_hp, smin, ds;
  double *texel_first, *texel_last; /* the texels' occupied stretches (sl__texel_spans) */
  float *texel_entry;               /* and where they enter the medium */
  double entry_step;                /* texel_entry's step: a grid cell along the sunlight */
  int kink;                         /* light_kink on (a low sun), with the arrays it needs */
  int spans_kept;                   /* 1: they and L's u_in, u_out hold this frame's (kept) */
  int nslices, back_to_front, wide_isa;
  long eye_samples, light_samples;
  double light_seconds, eye_seconds;
  slice_barrier barrier; /* between the passes of a slice */
} slicer_frame;

/* The light buffer's lattice for a frame: axes perpendicular to the sunlight's propagation prop,
 * covering the content box, with texels that resolve what the image can show (light_resolution 0)
 * or light_resolution square texels along the longer side. pixel_at_content: a pixel's size at
 * the content's centre; image_side: the image's longer side. Sets a, b, amin, bmin, the texel
 * sizes and w, h. */
void sl__light_buffer_lattice(const sl_renderer *r, const double prop[3], double pixel_at_content, int image_side,
                              light_buffer *L);
/* The extent [*smin, *smax] of the content box along the half vector h. */
void sl__slice_range(const sl_renderer *r, const double h[3], double *smin, double *smax);
/* Whether the kept texel spans are this frame's: the same sunlight and the same lattice. */
int sl__texel_spans_hold(const sl__texel_spans *c, const double prop[3], const light_buffer *L);
/* Makes room for L's texels and keys the spans to its lattice, not yet valid; 1 when out of
 * memory. */
int sl__texel_spans_prepare(sl__texel_spans *c, const double prop[3], const light_buffer *L);

#endif
