/* The eye pass over the cached light volume (light_volume_sweep.c): a ray march with the same
 * per-sample gather as the slicer's eye pass, reading the light state at each step's ends. */
/* The march gathers the steps of a ray in batches (as the slicer's eye pass gathers a tile's
 * samples): their cells found and prefetched first, then the table reads and the exponentials
 * of the whole batch in loops that vectorise. A ray's first batch is small, since a ray into a
 * thick cloud ends after a few steps and the rest of a batch would be wasted; then they grow. */
#define MARCH_BATCH 32
#define MARCH_FIRST_BATCH 8
#define MARCH_POINTS (2 * MARCH_BATCH + 1) /* a batch's light look-ups: each step's two ends at most */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "clear_margin.h"
#include "light_volume.h"
#include "march_phases.h"
#include "pixel_refine.h"
#include "resolve.h"
#include "segment_parts.h"
#include "sky_light_gather.h"
#include "sl_sample_physics.h"
#include "vector_math.h"

_Static_assert(MARCH_BATCH == SL__SKY_BATCH, "the skylight gather's rows are a march batch");
_Static_assert(MARCH_BATCH == SL__MARCH_PHASE_BATCH, "eq. 26's rows are a march batch");


/* A light-volume look-up in two steps, as the fields' (sl__field_cell_at, sl__field_fetch): a
 * batch of a ray's points finds its cells and prefetches them first, so that their loads overlap
 * instead of each waiting on memory in turn. The lattice is the fields' (clamped inside the
 * grid). */
typedef struct lv_cell {
  const float *c; /* the cell's lowest corner: ln I per wavelength and n per sample */
  double f[3];    /* the fractions within it */
} lv_cell;

static inline __attribute__((always_inline)) void light_volume_cell(const sl_renderer *r, const int nwl,
                                                                    const double x[3], lv_cell *cell)
{
  const sl_volume *v = &r->shape;
  const int stride = nwl + 1;
  int i0[3];
  sl__lattice_cell(&r->lattice, x, i0, cell->f);
  cell->c = r->light_volume + lv_index(v, i0[0], i0[1], i0[2], stride);
  const size_t sy = v->ny > 1 ? (size_t)v->nx * stride : 0;
  const size_t sz = v->nz > 1 ? (size_t)v->nx * v->ny * stride : 0;
  const float *rows[4] = {cell->c, cell->c + sy, cell->c + sz, cell->c + sy + sz};
  for (int k = 0; k < 4; ++k) {
    __builtin_prefetch(rows[k]);
    __builtin_prefetch(rows[k] + 2 * stride - 1);
  }
}

/* Trilinear interpolation of the light state in a cell: ln I per wavelength (the exponentials
 * are the caller's, a batch at once) and n, into out[c][k] for c <= nwl. At three wavelengths a
 * sample's state is one 4-float vector. */
static inline __attribute__((always_inline)) void light_volume_fetch(const sl_renderer *r, const int nwl,
                                                                     const lv_cell *cell, double (*out)[MARCH_POINTS],
                                                                     int k)
{
  const sl_volume *v = &r->shape;
  const int stride = nwl + 1;
  const size_t sx = v->nx > 1 ? (size_t)stride : 0;
  const size_t sy = v->ny > 1 ? (size_t)v->nx * stride : 0;
  const size_t sz = v->nz > 1 ? (size_t)v->nx * v->ny * stride : 0;
  const float *p = cell->c;
  const double *f = cell->f;
  if (stride == 4) {
    const sl__v4f value = sl__trilinear_v4f(p, sx, sy, sz, (float)f[0], (float)f[1], (float)f[2]);
    for (int s = 0; s < 4; ++s) out[s][k] = value[s];
  } else {
    for (int s = 0; s < stride; ++s) {
      const double c00 = p[s] + f[0] * (p[sx + s] - p[s]), c10 = p[sy + s] + f[0] * (p[sy + sx + s] - p[sy + s]);
      const double c01 = p[sz + s] + f[0] * (p[sz + sx + s] - p[sz + s]);
      const double c11 = p[sz + sy + s] + f[0] * (p[sz + sy + sx + s] - p[sz + sy + s]);
      const double c0 = c00 + f[1] * (c10 - c00), c1 = c01 + f[1] * (c11 - c01);
      out[s][k] = c0 + f[2] * (c1 - c0);
    }
  }
}

/* Distance along d from x to where the ray leaves the cube of empty bricks around x's 8^3 brick
 * (every brick less than its empty radius from it: no trilinear footprint in them holds
 * extinction, so every sample inside is exactly zero); -1 when x's brick holds something. The
 * march jumps the cube instead of stepping through it. With `clearance`, also x's distance in
 * cells to the cube's faces inside the lattice, beyond which medium may lie. */
static double empty_brick_exit(const sl_renderer *r, const double x[3], const double d[3], double *clearance)
{
  const sl_grid_view *g = &r->lattice;
  int b[3];
  double f[3];
  sl__lattice_cell(g, x, b, f);
  const int radius = sl__brick_radius(r, b);
  if (!radius) return -1.0;
  double best = INFINITY, inside = INFINITY;
  for (int a = 0; a < 3; ++a) {
    /* The cube's cells are [8 lo, 8 hi + 8) in lattice units; where it holds the first or the
     * last brick it reaches the box's face (the clamped points). */
    const int lo = b[a] / 8 - (radius - 1), hi = b[a] / 8 + (radius - 1);
    const double upper = hi >= sl__last_brick(g, a) ? g->hi[a] : g->origin[a] + 8.0 * (hi + 1) / g->inv_spacing[a];
    const double lower = lo <= 0 ? g->lo[a] : g->origin[a] + 8.0 * lo / g->inv_spacing[a];
    if (clearance) {
      if (lo > 0) inside = fmin(inside, (x[a] - lower) * g->inv_spacing[a]);
      if (hi < sl__last_brick(g, a)) inside = fmin(inside, (upper - x[a]) * g->inv_spacing[a]);
    }
    if (d[a] == 0.0) continue;
    const double face = d[a] > 0.0 ? upper : lower;
    const double t = (face - x[a]) / d[a];
    if (t < best) best = t;
  }
  if (clearance) *clearance = inside;
  return best > 0.0 ? best : 0.0;
}

/* What one frame of the march needs. */
typedef struct march_frame {
  sl_renderer *r;
  const sl_camera *cam;
  sl_image *img;
  const sl_sky_view *view;
  const sun_table *suntab;
  const sl_phase_table *grid_table;
  double fwd[3], right[3], up[3];
  double tan_half, aspect, h_center, f_o;
  double t_far; /* the camera's distance to the content box's farthest corner */
  sl__refine *refine; /* adaptive refinement (sl_scene.march_refine_tolerance), or NULL */
  size_t count;       /* the length of refine's list, shared by the threads */
  long samples;
  int wide_isa; /* which copy ran */
} march_frame;

/* A batch of a ray's march segments (a step, several thin steps as one, or a part of a thick step:
 * march_batch_steps): per segment, and per wavelength and segment (or point: a segment's two ends,
 * shared between neighbours), in arrays that the stages' vector loops read; and the light at the
 * end of the last segment gathered, carried into the next batch when its first segment follows. */
typedef struct march_batch {
  double beta[MARCH_BATCH], ta[MARCH_BATCH], te[MARCH_BATCH], tm[MARCH_BATCH], n[MARCH_BATCH];
  double m0[MARCH_BATCH], m1[MARCH_BATCH], inv_beta[MARCH_BATCH], opacity[MARCH_BATCH];
  double phase[SL_MAX_WAVELENGTHS][MARCH_BATCH], sun[SL_MAX_WAVELENGTHS][MARCH_BATCH];
  double l0[SL_MAX_WAVELENGTHS][MARCH_BATCH], l1[SL_MAX_WAVELENGTHS][MARCH_BATCH];
  double radiance[SL_MAX_WAVELENGTHS][MARCH_BATCH];
  float sky[MARCH_BATCH][SL_MAX_WAVELENGTHS + 4]; /* the skylight's M at each segment's middle */
  double p_t[MARCH_POINTS], p_state[SL_MAX_WAVELENGTHS + 1][MARCH_POINTS];
  lv_cell p_cell[MARCH_POINTS];
  sl__field_cell cell[MARCH_BATCH];
  float raw[MARCH_BATCH][SL__FIELD_LANES]; /* the fields at each found step's middle */
  float fields[MARCH_BATCH][SL_MAX_FIELDS];
  double dt[MARCH_BATCH];
  int step[MARCH_BATCH], len[MARCH_BATCH]; /* the steps found, in steps of the ray's dt */
  int start[MARCH_BATCH], end[MARCH_BATCH];
  int live;
  double carried[SL_MAX_WAVELENGTHS + 1];
  double carried_t; /* where the previous batch's last segment ended (NaN: none) */
  int done_end;     /* the step index where the last step the batches took ended (-1: none) */
  int pending;      /* steps found and fetched that the last batch had no room for: the next's first */
  sl__clear_margin margin; /* the ray's clearance from medium (clear_margin.h), while `track` */
  int track;
} march_batch;

/* The longest step, in steps of dt, that the march may take from step s (sl_scene.march_thin_depth):
 * 1, or a step of 2 or 4 that starts on a multiple of itself (so neighbouring rays' samples stay on
 * one lattice) and lies inside one brick whose largest extinction gives it at most thin_depth of
 * optical depth: there the medium is thin throughout, and one sample at the middle stands for the
 * two or four. */
#define MARCH_THIN_LONGEST 4
static inline __attribute__((always_inline)) int march_step_length(const sl_renderer *r, const double o[3],
                                                                   const double d[3], double t0, double dt,
                                                                   int nsteps, int s, double thin_depth)
{
  if (!(thin_depth > 0.0) || s % 2) return 1;
  const sl_grid_view *g = &r->lattice;
  const double ts = t0 + s * dt;
  const double xs[3] = {o[0] + ts * d[0], o[1] + ts * d[1], o[2] + ts * d[2]};
  int is[3];
  double f[3];
  sl__lattice_cell(g, xs, is, f);
  const size_t brick = sl__brick_index(r, is);
  const double beta_max = r->brick_beta_max[brick];
  for (int len = MARCH_THIN_LONGEST; len > 1; len /= 2) {
    if (s % len || s + len > nsteps || beta_max * len * dt > thin_depth) continue;
    const double te = ts + len * dt;
    const double xe[3] = {o[0] + te * d[0], o[1] + te * d[1], o[2] + te * d[2]};
    int ie[3];
    sl__lattice_cell(g, xe, ie, f);
    if (sl__brick_index(r, ie) == brick) return len;
  }
  return 1;
}

/* A segment [ta, te] of the ray into the batch, with the fields v and their total beta. */
static inline __attribute__((always_inline)) void march_batch_add(const int nf, march_batch *b, double ta, double te,
                                                                  const float *v, double beta)
{
  const int i = b->live++;
  for (int j = 0; j < nf; ++j) b->fields[i][j] = v[j];
  b->beta[i] = beta, b->ta[i] = ta, b->te[i] = te, b->dt[i] = te - ta, b->tm[i] = ta + 0.5 * b->dt[i];
}

/* A thick step [ta, te] of the ray o + t d into the batch in parts fixed in optical depth
 * (sl_segment_parts), on a profile of its total extinction, each part at its profile's mean
 * extinction in the mix of fields where its optical depth's middle lies; returns the step's
 * optical depth. The surface of a cloud inside the step is then where its extinction puts it,
 * not at the step's sample: a step taken whole at its middle puts the surface on the ray's own
 * step lattice, which starts where the ray enters the box, and so draws streaks across the rays
 * where a box face is seen obliquely. */
static inline __attribute__((always_inline)) double march_thick_step(const sl_renderer *r, const int nf,
                                                                     const double o[3], const double d[3],
                                                                     double ta, double te, march_batch *b)
{
  const double step = (te - ta) / SL_PART_PROFILE;
  double step_beta[SL_PART_PROFILE], tau[SL_PART_PROFILE + 1];
  sl__segment_profile_fields kept;
  const double depth = sl__segment_profile(r, nf, o, d, ta, step, step_beta, tau, &kept);
  if (!(depth > 0.0)) return 0.0;
  double t_at[SL_PARTS_MAX + 1], tau_at[SL_PARTS_MAX + 1];
  const int parts = sl_segment_parts(tau, ta, step, te, t_at, tau_at);
  for (int p = 0; p < parts; ++p) {
    const double len = t_at[p + 1] - t_at[p];
    if (!(len > 0.0 && tau_at[p + 1] > tau_at[p])) continue;
    float v[SL_MAX_FIELDS];
    const double beta = sl__segment_part_fields(r, nf, o, d, ta, step, step_beta, tau, &kept, tau_at[p], tau_at[p + 1], len, v);
    if (beta > 0.0) march_batch_add(nf, b, t_at[p], t_at[p + 1], v, beta);
  }
  return depth;
}

/* The clearance in cells from any point of lattice cell i0 to any medium that the cell's 2^3-cell
 * block guarantees (r->clear_blocks): the block's distance in blocks to one holding medium, less
 * its own width. */
static inline __attribute__((always_inline)) double march_cell_clearance(const sl_renderer *r, const int i0[3])
{
  const int *n = r->clear_blocks_n;
  return 2.0 * (r->clear_blocks[((size_t)(i0[2] / 2) * n[1] + i0[1] / 2) * n[0] + i0[0] / 2] - 1);
}

/* The same at point x (the lattice rule of sl__lattice_cell). */
static inline __attribute__((always_inline)) double march_block_clearance(const sl_renderer *r, const double x[3])
{
  int i0[3];
  double f[3];
  sl__lattice_cell(&r->lattice, x, i0, f);
  return march_cell_clearance(r, i0);
}

/* The ray's clearance across a jump from x = o + t d over a cube of empty bricks `exit` long, whose
 * faces inside the lattice lie `cube` cells from x: at x, the better of the cube's and the block's
 * (the cube's falls no faster than to zero at the exit, a concave function along the chord), and
 * at the exit the block's there. */
static inline __attribute__((always_inline)) void march_track_jump(const sl_renderer *r, const double o[3],
                                                                   const double d[3], double t, const double x[3],
                                                                   double cube, double exit, sl__clear_margin *m)
{
  const double block = march_block_clearance(r, x);
  if (cube >= block) sl__clear_margin_point(m, t, cube, exit > 0.0 ? cube / exit : m->rate);
  else sl__clear_margin_point(m, t, block, m->rate);
  const double te = t + exit;
  const double xe[3] = {o[0] + te * d[0], o[1] + te * d[1], o[2] + te * d[2]};
  sl__clear_margin_point(m, te, march_block_clearance(r, xe), m->rate);
}

/* The optical depth of the ray's step `s` (one of dt) by its middle's extinction: 0 past the last. */
static inline __attribute__((always_inline)) double march_step_depth(const sl_renderer *r, const int nf,
                                                                     const double o[3], const double d[3],
                                                                     double t0, double t1, double dt, int nsteps,
                                                                     int s)
{
  if (s >= nsteps) return 0.0;
  const double ta = t0 + s * dt, te = sl_march_step_end(t0, dt, t1, s + 1, nsteps), tm = 0.5 * (ta + te);
  const double x[3] = {o[0] + tm * d[0], o[1] + tm * d[1], o[2] + tm * d[2]};
  float v[SL_MAX_FIELDS];
  if (!sl__sample_fields_n(r, nf, x, v)) return 0.0;
  double beta = 0.0;
  for (int j = 0; j < nf; ++j) beta += v[j];
  return beta * (te - ta);
}

/* The ray's next steps from *s in occupied bricks, up to `size`, their cells prefetched; empty
 * bricks jumped (every step whose midpoint lies before a brick's exit samples nothing). Then their
 * fields, and the batch's segments: a step whose middle holds medium as one segment, or in parts
 * (march_thick_step) where its own optical depth or the next step's is SL_PART_THIN or more (the
 * surface of a cloud may lie in this step's far half while its middle is clear) and the ray's
 * transparency (`transparency` at the batch's start) is still SL_PART_DEEP or more; a thick step
 * after empty bricks takes the step before it in parts too, as a march through them would. Steps
 * whose parts would overflow the batch are left to the next (b->pending: its first steps). */
static inline __attribute__((always_inline)) void march_batch_steps(const sl_renderer *r, const int nf,
                                                                    const double o[3], const double d[3], double t0,
                                                                    double t1, double dt, int nsteps,
                                                                    double thin_depth, int size, double transparency,
                                                                    int *s, march_batch *b, long *samples)
{
  const int kept = b->pending;
  int cnt = kept;
  while (cnt < size && *s < nsteps) {
    const int len = march_step_length(r, o, d, t0, dt, nsteps, *s, thin_depth);
    const double ta = t0 + *s * dt, tm = 0.5 * (ta + sl_march_step_end(t0, dt, t1, *s + len, nsteps));
    const double x[3] = {o[0] + tm * d[0], o[1] + tm * d[1], o[2] + tm * d[2]};
    (*samples)++;
    const int track = b->track && b->margin.ratio > 0.0;
    int i0[3];
    double f[3];
    const int in_box = sl__in_lattice_box(&r->lattice, x);
    if (in_box) sl__lattice_cell(&r->lattice, x, i0, f);
    if (in_box && sl__field_cell_of(r, nf, i0, f, 1, &b->cell[cnt])) {
      if (track) sl__clear_margin_point(&b->margin, tm, march_cell_clearance(r, i0), b->margin.rate);
      b->len[cnt] = len;
      b->step[cnt++] = *s;
      *s += len;
      continue;
    }
    /* Outside the cell lattice's box (in an occupied brick's clamp) every field is zero. */
    double cube;
    const double exit = empty_brick_exit(r, x, d, track ? &cube : NULL);
    if (track && exit >= 0.0) march_track_jump(r, o, d, tm, x, cube, exit, &b->margin);
    const int next = exit >= 0.0 ? (int)ceil((tm + exit - t0) / dt - 0.5) : *s + 1;
    *s = next > *s ? next : *s + 1;
  }
  double step_beta[MARCH_BATCH], step_depth[MARCH_BATCH];
  for (int i = 0; i < cnt; ++i) {
    if (i >= kept) sl__field_fetch(r, nf, &b->cell[i], b->raw[i]);
    double beta = 0.0;
    for (int j = 0; j < nf; ++j) beta += b->raw[i][j];
    const double ta = t0 + b->step[i] * dt;
    step_beta[i] = beta;
    step_depth[i] = beta * (sl_march_step_end(t0, dt, t1, b->step[i] + b->len[i], nsteps) - ta);
  }
  /* Past this optical depth from the batch's start the ray's transparency is below SL_PART_DEEP. */
  const double deep = log(transparency / SL_PART_DEEP);
  double depth = 0.0;
  int i = 0;
  b->live = 0;
  for (; i < cnt && b->live <= MARCH_BATCH - 2 * SL_PARTS_MAX; ++i) {
    const int next = b->step[i] + b->len[i];
    const double ta = t0 + b->step[i] * dt, te = sl_march_step_end(t0, dt, t1, next, nsteps);
    int thick = 0;
    if (depth < deep) {
      thick = step_depth[i] >= SL_PART_THIN;
      const int before = i > 0 ? b->step[i - 1] + b->len[i - 1] : b->done_end;
      /* The step before, jumped as empty at its middle: the surface may begin in its far half. */
      if (thick && b->step[i] > 0 && before != b->step[i])
        depth += march_thick_step(r, nf, o, d, t0 + (b->step[i] - 1) * dt, ta, b);
      if (!thick) {
        const double next_depth = i + 1 < cnt ? (b->step[i + 1] == next ? step_depth[i + 1] : 0.0)
                                              : march_step_depth(r, nf, o, d, t0, t1, dt, nsteps, next);
        thick = next_depth >= SL_PART_THIN;
      }
    }
    if (thick) depth += march_thick_step(r, nf, o, d, ta, te, b);
    else if (step_depth[i] > 0.0) {
      march_batch_add(nf, b, ta, te, b->raw[i], step_beta[i]);
      depth += step_depth[i];
    }
  }
  if (i > 0) b->done_end = b->step[i - 1] + b->len[i - 1];
  /* The steps left over start the next batch, their fields fetched. */
  b->pending = cnt - i;
  for (int k = 0; k < b->pending; ++k) {
    b->step[k] = b->step[i + k], b->len[k] = b->len[i + k];
    memcpy(b->raw[k], b->raw[i + k], sizeof b->raw[k]);
  }
}

/* The light at each segment's two ends from the light volume (a segment that begins where the one
 * before it ended shares that one's end; the first, the previous batch's), its mean n, and the
 * sunlight at each segment's middle. */
static inline __attribute__((always_inline)) void march_batch_light(const sl_renderer *r, const int nwl,
                                                                    const sun_table *suntab,
                                                                    const sl__sun_lane *sun_lane, const double o[3],
                                                                    const double d[3], march_batch *b)
{
  const int live = b->live;
  int npts = 0, first_fetched = 0;
  if (b->ta[0] == b->carried_t) {
    for (int c = 0; c <= nwl; ++c) b->p_state[c][0] = b->carried[c];
    npts = first_fetched = 1;
  }
  for (int i = 0; i < live; ++i) {
    if (i == 0 && first_fetched) b->start[i] = 0;
    else if (i > 0 && b->ta[i] == b->te[i - 1]) b->start[i] = b->end[i - 1];
    else b->p_t[b->start[i] = npts++] = b->ta[i];
    b->p_t[b->end[i] = npts++] = b->te[i];
  }
  for (int k = first_fetched; k < npts; ++k) {
    const double x[3] = {o[0] + b->p_t[k] * d[0], o[1] + b->p_t[k] * d[1], o[2] + b->p_t[k] * d[2]};
    light_volume_cell(r, nwl, x, &b->p_cell[k]);
  }
  for (int k = first_fetched; k < npts; ++k) light_volume_fetch(r, nwl, &b->p_cell[k], b->p_state, k);
  for (int c = 0; c < nwl; ++c) {
    double *restrict lit = b->p_state[c];
#pragma omp simd
    for (int k = first_fetched; k < npts; ++k) lit[k] = exp(lit[k]);
  }
  for (int i = 0; i < live; ++i) {
    const int k0 = b->start[i], k1 = b->end[i];
    for (int c = 0; c < nwl; ++c) b->l0[c][i] = b->p_state[c][k0], b->l1[c][i] = b->p_state[c][k1];
    b->n[i] = 0.5 * (b->p_state[nwl][k0] + b->p_state[nwl][k1]);
    double sunlight[SL_MAX_WAVELENGTHS];
    const double x[3] = {o[0] + b->tm[i] * d[0], o[1] + b->tm[i] * d[1], o[2] + b->tm[i] * d[2]};
    sl__sun_at(suntab, sun_lane, x, sunlight);
    for (int c = 0; c < nwl; ++c) b->sun[c][i] = sunlight[c];
    if (r->sky.radiance) sl__sky_light_at(&r->sky, x, b->sky[i]);
  }
  for (int c = 0; c <= nwl; ++c) b->carried[c] = b->p_state[c][b->end[live - 1]];
  b->carried_t = b->te[live - 1];
}

/* Eq. 26's angular term over only the fields the batch holds (bitwise the same), then the light
 * each step sends toward the eye: the light is linear between a step's ends (the light volume
 * holds it at every point), the slicer's closed-form gather with no extra in-segment attenuation.
 * One exponential serves the step: opacity, transparency and the gather's moments. */
static inline __attribute__((always_inline)) void march_batch_scatter(const sl_light_model *m,
                                                                      const sl_light_model *subsets,
                                                                      const int skylight, const int nf,
                                                                      const int nwl, int angle_index,
                                                                      double angle_weight, march_batch *b)
{
  const int live = b->live;
  const sl_light_model *held_model = m;
  const int held = sl__batch_fields(subsets, nf, live, b->fields, &held_model);
#define MARCH_PHASES(model, mode, count) \
  sl__march_phases(model, mode, count, nwl, live, b->fields, b->n, angle_index, angle_weight, b->phase)
  SL_WITH_BATCH_MODEL(m, held_model, held, nf, MARCH_PHASES);
#undef MARCH_PHASES
#pragma omp simd
  for (int i = 0; i < live; ++i) {
    b->inv_beta[i] = 1.0 / b->beta[i];
    b->opacity[i] = sl_step_opacity(b->beta[i], b->dt[i]);
    const double e = 1.0 - b->opacity[i];
    b->m0[i] = sl_segment_scatter_moment_exp(0, b->beta[i], b->dt[i], 1.0, e);
    b->m1[i] = sl_segment_scatter_moment_exp(1, b->beta[i], b->dt[i], 1.0, e);
  }
  for (int c = 0; c < nwl; ++c) {
#pragma omp simd
    for (int i = 0; i < live; ++i)
      b->radiance[c][i] =
          sl_march_step_light(b->l0[c][i], b->l1[c][i], b->m0[i], b->m1[i], b->phase[c][i], b->inv_beta[i]) *
          b->sun[c][i];
  }
  if (skylight) sl__sky_light_add(held_model, (int)held_model->mode, held, nwl, live, b->fields, b->inv_beta, b->opacity,
                    b->sky, b->radiance);
}

/* The batch into the ray's accumulator a, front to back; 1 once its transparency falls below
 * `termination` (the ray ends). */
static inline __attribute__((always_inline)) int march_batch_composite(const int nwl, const march_batch *b,
                                                                       double depth_per_t, double termination,
                                                                       float *a)
{
  for (int i = 0; i < b->live; ++i) {
    const double w = a[nwl];
    for (int c = 0; c < nwl; ++c) a[c] += (float)(w * b->radiance[c][i]);
    a[nwl + 1] += (float)(w * b->opacity[i] * b->tm[i] * depth_per_t);
    a[nwl] *= (float)(1.0 - b->opacity[i]);
    if (a[nwl] < termination) return 1;
  }
  return 0;
}

/* One pixel's ray d over [t0, t1] into its accumulator a: its scattering angle's table row (fixed
 * along the ray under a collimated sun), steps of at most 1/march_samples of a grid cell along
 * every axis (by default one: the light volume holds the light at the grid's resolution, and a
 * thick step is taken in parts, march_thick_step), or two or four of them as one through thin
 * bricks (march_step_length), gathered a batch at a time; a ray's first batch is small, since a
 * ray into a thick cloud ends after a few steps. */
static inline __attribute__((always_inline)) void march_ray(const march_frame *f, const int nf, const int nwl,
                                                            const sl__sun_lane *sun_lane, const double d[3],
                                                            double t0, double t1, march_batch *b, float *a,
                                                            long *samples)
{
  const sl_renderer *r = f->r;
  const sl_scene *sc = &r->scene;
  const sl_light_model *subsets = r->has_subsets ? r->field_subsets : NULL;
  const sl_phase_table *grid_table = f->grid_table;
  const double *o = f->cam->position, *sun = sc->sun_direction;
  int angle_index = 0;
  double angle_weight = 0.0;
  if (grid_table) {
    double across[3];
    sl_cross3(sun, d, across);
    const double u = sl_angle_grid_position(sqrt(sl_dot3(across, across)), sl_dot3(sun, d), grid_table->inv_step_rad);
    angle_index = sl_angle_row(u, grid_table->n_angles);
    angle_weight = sl_angle_weight(u, angle_index);
  }
  const double dt = sl_march_max_step(r->shape.spacing, d, sl__march_samples(sc));
  const int nsteps = sl_march_steps(t1 - t0, dt);
  const double depth_per_t = sl_dot3(d, f->fwd);
  memset(b->carried, 0, sizeof b->carried);
  b->carried_t = NAN;
  b->done_end = -1;
  int size = MARCH_FIRST_BATCH, ended = 0;
  b->pending = 0;
  for (int s = 0; (s < nsteps || b->pending) && !ended;) {
    march_batch_steps(r, nf, o, d, t0, t1, dt, nsteps, sc->march_thin_depth, size, a[nwl], &s, b, samples);
    if (size < MARCH_BATCH) size *= 2;
    if (!b->live) continue;
    march_batch_light(r, nwl, f->suntab, sun_lane, o, d, b);
    march_batch_scatter(&r->model, subsets, r->sky.radiance != NULL, nf, nwl, angle_index, angle_weight, b);
    ended = march_batch_composite(nwl, b, depth_per_t, sc->termination_transparency, a);
  }
}

/* Pixel q's ray d through the content box, [*t0, *t1] up to any opaque surface; 0 where it has
 * nothing to march (it misses the box, or a surface hides the box). *hard: a surface cuts the ray
 * inside the box or hides it (no block holding its pixel is interpolated, pixel_refine.h). */
static inline __attribute__((always_inline)) int pixel_span(const march_frame *f, size_t q, double d[3], double *t0,
                                                            double *t1, int *hard)
{
  const sl_renderer *r = f->r;
  const sl_camera *cam = f->cam;
  const sl_image *img = f->img;
  sl_camera_pixel_ray(f->fwd, f->right, f->up, f->tan_half, f->aspect, img->width, img->height, (int)(q % img->width),
                      (int)(q / img->width), d);
  *t0 = *t1 = 0.0;
  int hit = sl_ray_box(r->clo, r->chi, cam->position, d, t0, t1) && *t1 > 0.0;
  if (*t0 < 0.0) *t0 = 0.0;
  *hard = hit && cam->opaque_distance && cam->opaque_distance[q] < *t1;
  if (*hard) *t1 = cam->opaque_distance[q];
  return hit && *t1 > *t0;
}

/* Pixel q's accumulator a (radiance per wavelength, transparency, depth numerator) from its ray d
 * over [t0, t1]: empty where the ray meets no medium. */
static inline __attribute__((always_inline)) void march_pixel(const march_frame *f, const int nf, const int nwl,
                                                              const sl__sun_lane *sun_lane, const double d[3],
                                                              double t0, double t1, int hit, march_batch *b,
                                                              float *a, long *samples)
{
  for (int c = 0; c < nwl + 2; ++c) a[c] = 0.0f;
  a[nwl] = 1.0f;
  if (hit) march_ray(f, nf, nwl, sun_lane, d, t0, t1, b, a, samples);
}

/* Pixel q from its accumulator: the resolve against the air in front. */
static inline __attribute__((always_inline)) void resolve_march_pixel(const march_frame *f, const int nwl, size_t q,
                                                                      const double d[3], double t0, double t1,
                                                                      const float *a)
{
  const sl_scene *sc = &f->r->scene;
  const double t_mid = sl_resolve_split(sl_dot3(f->fwd, d), f->h_center - f->f_o, t0, t1);
  sl__resolve_pixel(f->r, nwl, sc->atmosphere ? f->view : NULL, d, t_mid, a, f->img, q);
}

/* Pixel q of the refined march from its accumulator a. Its ray and span only where the resolve
 * reads them, for the air in front of a pixel that holds some medium: without air, or where the
 * volume covers nothing, sl__resolve_pixel reads neither, and most of a frame's pixels are spared
 * the ray and its box test. */
static inline __attribute__((always_inline)) void resolve_refined_pixel(const march_frame *f, const int nwl, size_t q,
                                                                        const float *a)
{
  double d[3] = {0.0, 0.0, 0.0}, t0 = 0.0, t1 = 0.0;
  int hard;
  if (f->r->scene.atmosphere && a[nwl] < 1.0f) pixel_span(f, q, d, &t0, &t1, &hard);
  resolve_march_pixel(f, nwl, q, d, t0, t1, a);
}

/* Pixel q's ray marched into the refinement's accumulator, and its clearance ratio from medium
 * (clear_margin.h) into rf->clear[q] where it met none (0: no bound; also where it misses the box,
 * as the medium may reach the box's faces). */
static inline __attribute__((always_inline)) void march_refined_pixel(const march_frame *f, const int nf,
                                                                      const int nwl, const sl__sun_lane *sun_lane,
                                                                      size_t q, march_batch *b, long *samples)
{
  sl__refine *rf = f->refine;
  const sl_renderer *r = f->r;
  double d[3], t0, t1, exit = 0.0;
  int hard;
  const int hit = pixel_span(f, q, d, &t0, &t1, &hard);
  b->track = hit && !hard;
  if (b->track) {
    const double *inv = r->lattice.inv_spacing;
    double rate = 0.0, entry;
    for (int a = 0; a < 3; ++a) rate = fmax(rate, fabs(d[a]) * inv[a]);
    sl__clear_box_rates(r->clo, r->chi, f->cam->position, d, inv, &entry, &exit);
    sl__clear_margin_begin(&b->margin, rate, t0, entry);
  }
  float *a = rf->acc + q * rf->channels;
  march_pixel(f, nf, nwl, sun_lane, d, t0, t1, hit, b, a, samples);
  /* A little low, so that rounding to float never raises it. */
  rf->clear[q] = b->track && a[nwl] == 1.0f ? (float)(0.999 * sl__clear_margin_end(&b->margin, t1, exit, f->t_far))
                                            : 0.0f;
  b->track = 0;
}

/* The march with adaptive refinement (pixel_refine.h): the rays of each list, shared among the
 * threads, then the next finer list, then the fill and the resolve. Three or four barriers a frame,
 * not one per slice. */
static inline __attribute__((always_inline)) void march_pixels_refined(march_frame *f, const int nf, const int nwl,
                                                                       const sl__sun_lane *sun_lane, march_batch *b,
                                                                       long *samples)
{
  sl__refine *rf = f->refine;
  const size_t np = (size_t)f->img->width * f->img->height;
  const int nc = rf->channels;
  /* Only a camera with opaque distances (the ground, terrain) has rays that a surface cuts; the
   * flags start zero. */
  if (f->cam->opaque_distance) {
#pragma omp for schedule(static)
    for (size_t q = 0; q < np; ++q) {
      double d[3], t0, t1;
      int hard;
      pixel_span(f, q, d, &t0, &t1, &hard);
      rf->hard[q] = (unsigned char)hard;
    }
  }
#pragma omp single
  f->count = sl__refine_first(rf);
  while (f->count) {
#pragma omp for schedule(dynamic, 16)
    for (size_t i = 0; i < f->count; ++i) march_refined_pixel(f, nf, nwl, sun_lane, (size_t)rf->list[i], b, samples);
#pragma omp single
    f->count = sl__refine_next(rf);
  }
  sl__refine_fill(rf);
#pragma omp for schedule(static)
  for (size_t q = 0; q < np; ++q) resolve_refined_pixel(f, nwl, q, rf->acc + q * nc);
}

/* One thread's share of the march (the pixel loop inside binds to the caller's parallel region),
 * inlined into march_run with constant field and wavelength counts as the slicer's passes are
 * (slicer.c, slicer_run): per pixel its ray through the content box up to any opaque surface,
 * then the resolve against the air in front. */
static inline __attribute__((always_inline)) void march_pixels(march_frame *f, const int nf, const int nwl)
{
  const sl__sun_lane sun_lane = sl__sun_table_lane(f->suntab);
  const size_t np = (size_t)f->img->width * f->img->height;
  long samples = 0;
  march_batch batch; /* this thread's */
  batch.track = 0;
  if (f->refine) march_pixels_refined(f, nf, nwl, &sun_lane, &batch, &samples);
  else {
#pragma omp for schedule(dynamic, 64) nowait
    for (size_t q = 0; q < np; ++q) {
      float a[SL_MAX_WAVELENGTHS + 2];
      double d[3], t0, t1;
      int hard;
      const int hit = pixel_span(f, q, d, &t0, &t1, &hard);
      march_pixel(f, nf, nwl, &sun_lane, d, t0, t1, hit, &batch, a, &samples);
      resolve_march_pixel(f, nwl, q, d, t0, t1, a);
    }
  }
#pragma omp atomic
  f->samples += samples;
}

#ifdef SL_WIDE_TARGET
SL_WIDE_TARGET static void march_run_wide(march_frame *f)
{
  SL_RUN_SPECIALISED(march_pixels, f, f->r->model.nf, f->r->model.nwl);
}
#endif

/* The march in the AVX-512 copy where the CPU has it (sl__wide_isa), as the slicer's passes. */
static void march_run(march_frame *f)
{
  f->samples = 0;
  f->wide_isa = 0;
#ifdef SL_WIDE_TARGET
  if (sl__wide_isa(&f->r->scene)) {
    f->wide_isa = 1;
    march_run_wide(f);
    return;
  }
#endif
  SL_RUN_SPECIALISED(march_pixels, f, f->r->model.nf, f->r->model.nwl);
}

int sl__render_with_light_volume(sl_renderer *r, const sl_camera *cam, sl_image *img, sl_render_stats *stats,
                                 sl_error *err)
{
  const sl_scene *sc = &r->scene;
  if (!r->light_volume && sl_renderer_build_light_volume(r, err)) return err->code;
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up))
    return sl_fail(err, SL_ERR_ARG, "render: camera position equals the target, or up is parallel to the view");
  sl_sky_view view = {0};
  if (sc->atmosphere && sl_sky_view_init(&view, sc->atmosphere, cam->position, sc->sun_direction, err)) return err->code;
  sun_table *suntab = malloc(sizeof *suntab);
  if (!suntab) return sl_fail(err, SL_ERR_NOMEM, "render: out of memory");
  sl__sun_table_init(suntab, sc, &view, r->clo, r->chi);
  const sl_light_model *m = &r->model;
  const sl_phase_table *grid_table = m->nf > 0 && m->mode != SL_LIGHTING_LOW_ALBEDO ? m->table[0][0] : NULL;
  const double tan_half = tan(0.5 * cam->fov_deg * M_PI / 180.0);
  const double aspect = (double)img->width / img->height;
  const double *o = cam->position;
  const double h_center = sl_dot3(fwd, r->content_center), f_o = sl_dot3(fwd, o);
  const double t_begin = omp_get_wtime();
  march_frame f = {.r = r, .cam = cam, .img = img, .view = &view, .suntab = suntab, .grid_table = grid_table,
                   .tan_half = tan_half, .aspect = aspect, .h_center = h_center, .f_o = f_o};
  for (int a = 0; a < 3; ++a) f.fwd[a] = fwd[a], f.right[a] = right[a], f.up[a] = up[a];
  for (int k = 0; k < 8; ++k) {
    const double corner[3] = {k & 1 ? r->chi[0] : r->clo[0], k & 2 ? r->chi[1] : r->clo[1], k & 4 ? r->chi[2] : r->clo[2]};
    const double to[3] = {corner[0] - o[0], corner[1] - o[1], corner[2] - o[2]};
    f.t_far = fmax(f.t_far, sqrt(sl_dot3(to, to)));
  }
  sl__refine refine;
  if (sc->march_refine_tolerance > 0.0) {
    if (!r->clear_blocks && sl__clear_blocks_build(r, err)) {
      free(suntab);
      return err->code;
    }
    /* A pixel's unit ray lies within pitch / sqrt 2 of its nearest lattice ray per pixel of the
     * lattice's spacing (rays through an image plane at distance 1, normalised: a contraction),
     * so at t within that times t times the most cells per unit length (clear_margin.h). */
    const double pitch = 2.0 * tan_half / img->height;
    double cells_per_length = 0.0;
    for (int a = 0; a < 3; ++a) cells_per_length = fmax(cells_per_length, r->lattice.inv_spacing[a]);
    if (!sl__refine_init(&refine, img->width, img->height, m->nwl + 2, m->nwl, sc->march_refine_tolerance,
                         pitch / sqrt(2.0) * cells_per_length)) {
      free(suntab);
      return sl_fail(err, SL_ERR_NOMEM, "render: out of memory");
    }
    f.refine = &refine;
  }
  march_run(&f);
  if (f.refine) sl__refine_free(&refine);
  const long samples = f.samples;
  if (stats) {
    memset(stats, 0, sizeof *stats);
    stats->eye_seconds = omp_get_wtime() - t_begin;
    stats->light_seconds = r->light_volume_seconds;
    stats->eye_samples = samples;
    stats->night = view.night;
    stats->wide_isa = f.wide_isa; /* the march's copy; the sweep runs baseline only */
    stats->light_width = r->shape.nx, stats->light_height = r->shape.ny;
  }
  free(suntab);
  return SL_OK;
}
