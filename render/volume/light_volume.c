/* The cached, view-independent light volume: for a fixed sun the light transport (intensity I
 * per wavelength and the expected scattering count n, eqs. 21-25) does not depend on the
 * camera, so it is swept once onto the volume's own grid and every frame afterwards pays only
 * an eye pass, here a ray march with the same per-sample gather as the slicer's eye pass.
 *
 * The sweep visits the grid's planes across the sun's dominant axis in the light's order; each
 * sample takes the state where its sun ray crossed the previous plane (bilinear in that plane)
 * and applies one light step over the path between the planes. The volume stores ln I rather
 * than I: through a uniform medium ln I falls linearly with the path, so interpolating it is
 * exact there, where interpolating the convex I would brighten every step a little (measured:
 * 4 % too bright after 20 planes, 14 % near a sunlit face). */
#define LOG_FLOOR (-80.0f) /* ln I of light that is gone: exp(-80) is below any radiance of note */
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

#include "renderer_internal.h"
#include "sl_sample_physics.h"
#include "vector_math.h"

static size_t lv_index(const sl_volume *v, int i, int j, int k, int stride)
{
  return sl_volume_index(v, i, j, k) * (size_t)stride;
}

/* Bilinear look-up of the light state in a plane across axis `axis` (its samples in rows along
 * a1, stride floats each) at the fractional in-plane coordinates (u, w) along the two other axes
 * (a1, a2). Returns 0 outside the plane. */
static int plane_lookup(const sl_renderer *r, const float *plane, int axis, double u, double w, double *out)
{
  const sl_volume *v = &r->shape;
  const int n[3] = {v->nx, v->ny, v->nz};
  const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
  if (u < -0.5 || w < -0.5 || u > n[a1] - 0.5 || w > n[a2] - 0.5) return 0;
  /* Between the outermost samples and the box's faces the light has just entered: blend toward
   * fresh sunlight (I = 1, n = 0) at the face instead of holding the edge sample's state. */
  double fresh = 0.0;
  if (u < 0.0) fresh = fmax(fresh, -2.0 * u);
  if (u > n[a1] - 1) fresh = fmax(fresh, 2.0 * (u - (n[a1] - 1)));
  if (w < 0.0) fresh = fmax(fresh, -2.0 * w);
  if (w > n[a2] - 1) fresh = fmax(fresh, 2.0 * (w - (n[a2] - 1)));
  if (fresh > 1.0) fresh = 1.0;
  u = u < 0.0 ? 0.0 : u > n[a1] - 1 ? n[a1] - 1 : u;
  w = w < 0.0 ? 0.0 : w > n[a2] - 1 ? n[a2] - 1 : w;
  int i = (int)u, j = (int)w;
  if (i > n[a1] - 2) i = n[a1] > 1 ? n[a1] - 2 : 0;
  if (j > n[a2] - 2) j = n[a2] > 1 ? n[a2] - 2 : 0;
  const double fu = n[a1] > 1 ? u - i : 0.0, fw = n[a2] > 1 ? w - j : 0.0;
  const int stride = r->model.nwl + 1;
  if (stride == 4) {
    /* Three wavelengths and n: a sample's state is one 4-float vector, lerped at once as the
     * slicer's light-buffer look-up does (the sweep's time was this function's loads and
     * conversions, channel by channel in double). */
    const size_t di = n[a1] > 1 ? 4 : 0, dj = n[a2] > 1 ? (size_t)n[a1] * 4 : 0;
    const float *p = plane + ((size_t)j * n[a1] + i) * 4;
    const float gu = (float)fu, gw = (float)fw;
    const sl__v4f r0 = sl__load_v4f(p) + gu * (sl__load_v4f(p + di) - sl__load_v4f(p));
    const sl__v4f r1 = sl__load_v4f(p + dj) + gu * (sl__load_v4f(p + dj + di) - sl__load_v4f(p + dj));
    const sl__v4f value = (r0 + gw * (r1 - r0)) * (float)(1.0 - fresh); /* fresh light: ln I = 0, n = 0 */
    for (int s = 0; s < 4; ++s) out[s] = value[s];
    return 1;
  }
  const double wt[4] = {(1 - fu) * (1 - fw), fu * (1 - fw), (1 - fu) * fw, fu * fw};
  for (int s = 0; s < stride; ++s) out[s] = 0.0;
  for (int c = 0; c < 4; ++c) {
    const int ci = i + ((c & 1) && n[a1] > 1), cj = j + ((c & 2) && n[a2] > 1);
    const float *p = plane + ((size_t)cj * n[a1] + ci) * stride;
    for (int s = 0; s < stride; ++s) out[s] += wt[c] * p[s];
  }
  for (int s = 0; s < stride; ++s) out[s] *= 1.0 - fresh; /* fresh light: ln I = 0, n = 0 */
  return 1;
}

/* Planes the sweep keeps before it writes them to the volume: across x, four consecutive planes'
 * states (16 bytes each at three wavelengths) fill one 64-byte cache line, which plane by plane
 * was written a quarter at a time (each plane's writes 4 KB apart, every line fetched four
 * times). */
#define SWEEP_PLANES 4

/* What the sweep needs: the planes across the sun's dominant axis and the path between them. */
typedef struct sweep_frame {
  const sl_renderer *r;
  float *state;
  /* The last SWEEP_PLANES planes, the one being swept among them, in rows along a1: the sweep
   * reads the previous plane from here (a megabyte at 256^2) instead of from the volume, where a
   * plane across x or y is a sample every few kilobytes and each look-up missed the cache; and
   * writes them to the volume together, SWEEP_PLANES at a time (sweep_planes, after each group). */
  float *plane[SWEEP_PLANES];
  double p[3];           /* the sunlight's propagation */
  int axis, a1, a2, step, first;
  double path;           /* from one plane to the next along the sunlight */
  double shift1, shift2; /* the in-plane shift that path brings, in samples */
  sl__box_exit sun_exit; /* the way out of the box toward the sun */
} sweep_frame;

/* One thread's share of the sweep, plane after plane (each plane's loop binds to the caller's
 * parallel region and ends in its barrier); inlined with constant field and wavelength counts
 * (SL_RUN_SPECIALISED). */
static inline __attribute__((always_inline)) void sweep_planes(sweep_frame *f, const int nf, const int nwl)
{
  const sl_renderer *r = f->r;
  const sl_volume *v = &r->shape;
  const sl_light_model *m = &r->model;
  const int stride = nwl + 1, axis = f->axis, a1 = f->a1, a2 = f->a2, step = f->step;
  const int n[3] = {v->nx, v->ny, v->nz};
  const double *p = f->p;
  float *state = f->state;
  for (int kk = 0; kk < n[axis]; ++kk) {
    const int k = f->first + kk * step;
#pragma omp for schedule(static)
    for (int jj = 0; jj < n[a2]; ++jj)
      for (int ii = 0; ii < n[a1]; ++ii) {
        int idx[3];
        idx[axis] = k, idx[a1] = ii, idx[a2] = jj;
        float *out = f->plane[kk % SWEEP_PLANES] + ((size_t)jj * n[a1] + ii) * stride;
        double prev[SL_MAX_WAVELENGTHS + 1];
        double x[3];
        for (int a = 0; a < 3; ++a) x[a] = v->origin[a] + idx[a] * v->spacing[a];
        double len = f->path;
        /* The state where this sample's sun ray crossed the previous plane, or fresh sunlight
         * entering the box (through the first plane or a side face) over a shorter path. */
        if (kk == 0 ||
            !plane_lookup(r, f->plane[(kk - 1) % SWEEP_PLANES], axis, ii + f->shift1, jj + f->shift2, prev)) {
          for (int c = 0; c < nwl; ++c) prev[c] = 0.0;
          prev[nwl] = 0.0;
          len = sl__min(f->path, sl__box_exit_distance(&f->sun_exit, x));
          if (kk == 0) len = 0.5 * v->spacing[axis] / fabs(p[axis]);
        }
        /* Fields at the middle of the path since the previous plane. */
        const double mid[3] = {x[0] - 0.5 * len * p[0], x[1] - 0.5 * len * p[1], x[2] - 0.5 * len * p[2]};
        float beta[SL_MAX_FIELDS];
        sl__sample_fields_n(r, nf, mid, beta);
        double total = 0.0;
        for (int j = 0; j < nf; ++j) total += beta[j];
        if (!(total > 0.0 && len > 0.0)) {
          /* Nothing on the path: the light arrives as it left the previous plane. */
          for (int c = 0; c < nwl; ++c) out[c] = fmaxf((float)prev[c], LOG_FLOOR);
          out[nwl] = (float)prev[nwl];
          continue;
        }
        /* One light step on the stored ln I and n (no exponential and logarithm around it). */
        for (int s = 0; s <= nwl; ++s) out[s] = (float)prev[s];
        sl_log_light_step_at(m, (int)m->mode, nf, nwl, beta, len, out, 0);
        for (int c = 0; c < nwl; ++c) out[c] = fmaxf(out[c], LOG_FLOOR);
      }
    if (kk % SWEEP_PLANES == SWEEP_PLANES - 1 || kk == n[axis] - 1) {
      /* The planes since the last flush into the volume, sample by sample across them. */
      const int held = kk % SWEEP_PLANES + 1;
#pragma omp for schedule(static)
      for (int jj = 0; jj < n[a2]; ++jj)
        for (int ii = 0; ii < n[a1]; ++ii)
          for (int b = 0; b < held; ++b) {
            int idx[3];
            idx[axis] = f->first + (kk - held + 1 + b) * step, idx[a1] = ii, idx[a2] = jj;
            memcpy(state + lv_index(v, idx[0], idx[1], idx[2], stride),
                   f->plane[b] + ((size_t)jj * n[a1] + ii) * stride, (size_t)stride * sizeof(float));
          }
    }
  }
}

int sl_renderer_build_light_volume(sl_renderer *r, sl_error *err)
{
  const sl_volume *v = &r->shape;
  const int nwl = r->model.nwl, stride = nwl + 1;
  const size_t count = sl_volume_count(v);
  if ((double)count * stride * sizeof(float) > 2.0e9)
    return sl_fail(err, SL_ERR_NOMEM, "light volume: %dx%dx%d samples x %d values exceed 2 GB", v->nx, v->ny, v->nz,
                   stride);
  sweep_frame f = {.r = r};
  f.state = sl__huge_alloc(count * stride * sizeof(float)); /* looked up at every eye sample */
  if (!f.state) return sl_fail(err, SL_ERR_NOMEM, "light volume: out of memory");
  const double *sun = r->scene.sun_direction;
  for (int a = 0; a < 3; ++a) f.p[a] = -sun[a];
  f.axis = 0;
  for (int a = 1; a < 3; ++a)
    if (fabs(f.p[a]) > fabs(f.p[f.axis])) f.axis = a;
  f.a1 = (f.axis + 1) % 3, f.a2 = (f.axis + 2) % 3;
  const int n[3] = {v->nx, v->ny, v->nz};
  f.step = f.p[f.axis] > 0.0 ? 1 : -1;
  f.first = f.step > 0 ? 0 : n[f.axis] - 1;
  f.path = v->spacing[f.axis] / fabs(f.p[f.axis]);
  f.shift1 = -f.path * f.p[f.a1] / v->spacing[f.a1], f.shift2 = -f.path * f.p[f.a2] / v->spacing[f.a2];
  double box_lo[3], box_hi[3];
  sl_volume_bounds(v, box_lo, box_hi);
  sl__box_exit_init(&f.sun_exit, box_lo, box_hi, sun);
  const double t0 = omp_get_wtime();
  const size_t plane_floats = (size_t)n[f.a1] * n[f.a2] * stride;
  f.plane[0] = malloc(SWEEP_PLANES * plane_floats * sizeof(float));
  if (!f.plane[0]) {
    free(f.state);
    return sl_fail(err, SL_ERR_NOMEM, "light volume: out of memory");
  }
  for (int b = 1; b < SWEEP_PLANES; ++b) f.plane[b] = f.plane[b - 1] + plane_floats;
  SL_RUN_SPECIALISED(sweep_planes, &f, r->model.nf, nwl);
  free(f.plane[0]);
  free(r->light_volume);
  r->light_volume = f.state;
  r->light_volume_seconds = omp_get_wtime() - t0;
  return SL_OK;
}

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
  sl__lattice_cell(&r->beta_view, x, i0, cell->f);
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
 * march jumps the cube instead of stepping through it. */
static double empty_brick_exit(const sl_renderer *r, const double x[3], const double d[3])
{
  const sl_grid_view *g = &r->beta_view;
  int b[3];
  double f[3];
  sl__lattice_cell(g, x, b, f);
  const int radius = sl__brick_radius(r, b);
  if (!radius) return -1.0;
  double best = INFINITY;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) continue;
    /* The cube's cells are [8 lo, 8 hi + 8) in lattice units; where it holds the first or the
     * last brick it reaches the box's face (the clamped points). */
    const int lo = b[a] / 8 - (radius - 1), hi = b[a] / 8 + (radius - 1);
    const double upper = hi >= sl__last_brick(g, a) ? g->hi[a] : g->origin[a] + 8.0 * (hi + 1) / g->inv_spacing[a];
    const double lower = lo <= 0 ? g->lo[a] : g->origin[a] + 8.0 * lo / g->inv_spacing[a];
    const double face = d[a] > 0.0 ? upper : lower;
    const double t = (face - x[a]) / d[a];
    if (t < best) best = t;
  }
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
  long samples;
  int wide_isa; /* which copy ran */
} march_frame;

/* The table reads of a batch of a ray's steps: eq. 26's angular term per wavelength at the mean
 * expected scattering count of each step's two ends (the angle is the ray's). One loop over the
 * steps that GCC turns into gathers; the steps are independent (ivdep). */
static inline __attribute__((always_inline)) void march_batch_phases(const sl_light_model *m, const int mode,
                                                                     const int nf, const int nwl, const int live,
                                                                     float (*restrict fields)[SL_MAX_FIELDS],
                                                                     const double *restrict n, const int angle_index,
                                                                     const double angle_weight,
                                                                     double (*restrict phase)[MARCH_BATCH])
{
#pragma GCC ivdep
  for (int s = 0; s < live; ++s) {
    double ph[SL_MAX_WAVELENGTHS];
    sl_eye_phase_at(m, mode, nf, nwl, fields[s], n[s], angle_index, angle_weight, ph);
    for (int c = 0; c < nwl; ++c) phase[c][s] = ph[c];
  }
}

/* One thread's share of the march (the pixel loop inside binds to the caller's parallel region),
 * inlined into march_run with constant field and wavelength counts as the slicer's passes are
 * (renderer.c, slicer_run). */
static inline __attribute__((always_inline)) void march_pixels(march_frame *f, const int nf, const int nwl)
{
  sl_renderer *r = f->r;
  const sl_scene *sc = &r->scene;
  const sl_light_model *m = &r->model;
  const sl_light_model *subsets = r->has_subsets ? r->field_subsets : NULL;
  const sl_camera *cam = f->cam;
  sl_image *img = f->img;
  const sun_table *suntab = f->suntab;
  const sl__sun_lane sun_lane = sl__sun_table_lane(suntab);
  const sl_phase_table *grid_table = f->grid_table;
  const double *fwd = f->fwd, *right = f->right, *up = f->up;
  const double tan_half = f->tan_half, aspect = f->aspect, h_center = f->h_center, f_o = f->f_o;
  const size_t np = (size_t)img->width * img->height;
  const double *o = cam->position, *sun = sc->sun_direction;
  const int march_samples = sl__march_samples(sc);
  long samples = 0;
  /* This thread's batch: per step, and per wavelength and step (or point), in arrays that the
   * vector loops read. */
  int b_step[MARCH_BATCH], b_start[MARCH_BATCH], b_end[MARCH_BATCH];
  sl__field_cell b_cell[MARCH_BATCH];
  float b_fields[MARCH_BATCH][SL_MAX_FIELDS];
  double b_beta[MARCH_BATCH], b_tm[MARCH_BATCH], b_n[MARCH_BATCH], b_opacity[MARCH_BATCH];
  double b_phase[SL_MAX_WAVELENGTHS][MARCH_BATCH], b_sun[SL_MAX_WAVELENGTHS][MARCH_BATCH];
  double b_l0[SL_MAX_WAVELENGTHS][MARCH_BATCH], b_l1[SL_MAX_WAVELENGTHS][MARCH_BATCH];
  double b_radiance[SL_MAX_WAVELENGTHS][MARCH_BATCH];
  double p_t[MARCH_POINTS], p_state[SL_MAX_WAVELENGTHS + 1][MARCH_POINTS];
  lv_cell p_cell[MARCH_POINTS];
#pragma omp for schedule(dynamic, 64) nowait
  for (size_t q = 0; q < np; ++q) {
    double d[3];
    sl_camera_pixel_ray(fwd, right, up, tan_half, aspect, img->width, img->height, (int)(q % img->width),
                  (int)(q / img->width), d);
    float a[SL_MAX_WAVELENGTHS + 2];
    memset(a, 0, sizeof a);
    a[nwl] = 1.0f;
    double t0 = 0.0, t1 = 0.0;
    int hit = sl_ray_box(r->clo, r->chi, o, d, &t0, &t1) && t1 > 0.0;
    if (t0 < 0.0) t0 = 0.0;
    if (cam->opaque_distance && cam->opaque_distance[q] < t1) t1 = cam->opaque_distance[q];
    if (t1 <= t0) hit = 0; /* an opaque surface in front of the volume */
    if (hit) {
      int angle_index = 0;
      double angle_weight = 0.0;
      if (grid_table) {
        double c = sl_dot3(sun, d);
        c = c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c;
        const double u = acos(c) * grid_table->inv_step_rad;
        angle_index = (int)u;
        if (angle_index > grid_table->n_angles - 2) angle_index = grid_table->n_angles - 2;
        angle_weight = u - angle_index > 1.0 ? 1.0 : u - angle_index;
      }
      /* By default two samples per grid cell along every axis: the light volume holds the light
       * at the grid's resolution, and a finer march keeps optically thick surfaces from
       * speckling. */
      double dt = INFINITY;
      for (int ax = 0; ax < 3; ++ax)
        if (fabs(d[ax]) > 1e-12) dt = fmin(dt, r->shape.spacing[ax] / (march_samples * fabs(d[ax])));
      const int nsteps = sl_march_steps(t1 - t0, dt);
      dt = (t1 - t0) / (nsteps > 0 ? nsteps : 1);
      const double depth_per_t = sl_dot3(d, fwd);
      /* The light at the end of the last step gathered (carried into the next batch when the
       * next step gathered follows it directly). */
      double carried[SL_MAX_WAVELENGTHS + 1] = {0};
      int carried_step = -2, batch = MARCH_FIRST_BATCH, ended = 0;
      for (int s = 0; s < nsteps && !ended;) {
        /* The batch's steps in occupied bricks, their cells prefetched; empty bricks jumped:
         * every step whose midpoint lies before a brick's exit samples nothing. */
        int cnt = 0;
        while (cnt < batch && s < nsteps) {
          const double tm = t0 + s * dt + 0.5 * dt;
          const double x[3] = {o[0] + tm * d[0], o[1] + tm * d[1], o[2] + tm * d[2]};
          samples++;
          if (sl__field_cell_at(r, nf, x, 1, &b_cell[cnt])) {
            b_step[cnt++] = s++;
            continue;
          }
          /* Outside the cell lattice's box (in an occupied brick's clamp) every field is zero. */
          const double exit = empty_brick_exit(r, x, d);
          const int next = exit >= 0.0 ? (int)ceil((tm + exit - t0) / dt - 0.5) : s + 1;
          s = next > s ? next : s + 1;
        }
        if (batch < MARCH_BATCH) batch *= 2;
        int live = 0;
        for (int i = 0; i < cnt; ++i) {
          float v[SL__FIELD_LANES];
          sl__field_fetch(r, nf, &b_cell[i], v);
          double beta = 0.0;
          for (int j = 0; j < nf; ++j) beta += v[j];
          if (!(beta > 0.0)) continue;
          for (int j = 0; j < nf; ++j) b_fields[live][j] = v[j];
          b_beta[live] = beta, b_step[live] = b_step[i];
          b_tm[live] = t0 + b_step[i] * dt + 0.5 * dt;
          live++;
        }
        if (!live) continue;
        /* The light at each step's two ends: a step that follows the one before it directly
         * shares that one's end (the first, the previous batch's). */
        int npts = 0, first_fetched = 0;
        if (b_step[0] == carried_step + 1) {
          for (int c = 0; c <= nwl; ++c) p_state[c][0] = carried[c];
          npts = first_fetched = 1;
        }
        for (int i = 0; i < live; ++i) {
          if (i == 0 && first_fetched) b_start[i] = 0;
          else if (i > 0 && b_step[i] == b_step[i - 1] + 1) b_start[i] = b_end[i - 1];
          else p_t[b_start[i] = npts++] = t0 + b_step[i] * dt;
          p_t[b_end[i] = npts++] = t0 + b_step[i] * dt + dt;
        }
        for (int k = first_fetched; k < npts; ++k) {
          const double x[3] = {o[0] + p_t[k] * d[0], o[1] + p_t[k] * d[1], o[2] + p_t[k] * d[2]};
          light_volume_cell(r, nwl, x, &p_cell[k]);
        }
        for (int k = first_fetched; k < npts; ++k) light_volume_fetch(r, nwl, &p_cell[k], p_state, k);
        for (int c = 0; c < nwl; ++c) {
          double *restrict lit = p_state[c];
#pragma omp simd
          for (int k = first_fetched; k < npts; ++k) lit[k] = exp(lit[k]);
        }
        for (int i = 0; i < live; ++i) {
          const int k0 = b_start[i], k1 = b_end[i];
          for (int c = 0; c < nwl; ++c) b_l0[c][i] = p_state[c][k0], b_l1[c][i] = p_state[c][k1];
          b_n[i] = 0.5 * (p_state[nwl][k0] + p_state[nwl][k1]);
          double sunlight[SL_MAX_WAVELENGTHS];
          const double x[3] = {o[0] + b_tm[i] * d[0], o[1] + b_tm[i] * d[1], o[2] + b_tm[i] * d[2]};
          sl__sun_at(suntab, &sun_lane, x, sunlight);
          for (int c = 0; c < nwl; ++c) b_sun[c][i] = sunlight[c];
        }
        for (int c = 0; c <= nwl; ++c) carried[c] = p_state[c][b_end[live - 1]];
        carried_step = b_step[live - 1];
        /* Eq. 26's angular term, over only the fields the batch holds (bitwise the same). */
        const sl_light_model *held_model = m;
        const int held = sl__batch_fields(subsets, nf, live, b_fields, &held_model);
#define MARCH_PHASES(model, mode, count) \
  march_batch_phases(model, mode, count, nwl, live, b_fields, b_n, angle_index, angle_weight, b_phase)
        SL_WITH_BATCH_MODEL(m, held_model, held, nf, MARCH_PHASES);
#undef MARCH_PHASES
        /* The light is linear between a step's ends (the light volume holds it at every point):
         * the slicer's closed-form gather with no extra in-segment attenuation. One exponential
         * serves the step: opacity, transparency and the gather's moments. */
        double b_m0[MARCH_BATCH], b_m1[MARCH_BATCH], b_inv_beta[MARCH_BATCH];
#pragma omp simd
        for (int i = 0; i < live; ++i) {
          b_inv_beta[i] = 1.0 / b_beta[i];
          b_opacity[i] = -expm1(-b_beta[i] * dt);
          const double e = 1.0 - b_opacity[i];
          b_m0[i] = sl_segment_scatter_moment_exp(0, b_beta[i], dt, 1.0, e);
          b_m1[i] = sl_segment_scatter_moment_exp(1, b_beta[i], dt, 1.0, e);
        }
        for (int c = 0; c < nwl; ++c) {
#pragma omp simd
          for (int i = 0; i < live; ++i)
            b_radiance[c][i] =
                (b_l0[c][i] * b_m0[i] + (b_l1[c][i] - b_l0[c][i]) * b_m1[i]) * b_phase[c][i] * b_inv_beta[i] * b_sun[c][i];
        }
        /* Front to back, until the ray's transparency falls below the termination threshold. */
        for (int i = 0; i < live; ++i) {
          const double w = a[nwl];
          for (int c = 0; c < nwl; ++c) a[c] += (float)(w * b_radiance[c][i]);
          a[nwl + 1] += (float)(w * b_opacity[i] * b_tm[i] * depth_per_t);
          a[nwl] *= (float)(1.0 - b_opacity[i]);
          if (a[nwl] < sc->termination_transparency) {
            ended = 1;
            break;
          }
        }
      }
    }
    double t_mid = fabs(sl_dot3(fwd, d)) > 1e-12 ? (h_center - f_o) / sl_dot3(fwd, d) : 0.5 * (t0 + t1);
    t_mid = t_mid < t0 ? t0 : t_mid > t1 ? t1 : t_mid;
    sl__resolve_pixel(r, sc->atmosphere ? f->view : NULL, d, t_mid, a, img, q);
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
  march_run(&f);
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
