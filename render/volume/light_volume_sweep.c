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
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "light_volume.h"
#include "sl_sample_physics.h"
#include "sl_sweep_geometry.h"
#include "vector_math.h"

void sl_sweep_geometry_init(const int n[3], const double spacing[3], const double sun[3], sl_sweep_geometry *g)
{
  const double p[3] = {-sun[0], -sun[1], -sun[2]}; /* the sunlight's propagation */
  g->axis = 0;
  for (int a = 1; a < 3; ++a)
    if (fabs(p[a]) > fabs(p[g->axis])) g->axis = a;
  g->a1 = (g->axis + 1) % 3, g->a2 = (g->axis + 2) % 3;
  g->step = p[g->axis] > 0.0 ? 1 : -1;
  g->first = g->step > 0 ? 0 : n[g->axis] - 1;
  g->path = spacing[g->axis] / fabs(p[g->axis]);
  g->shift[0] = -g->path * p[g->a1] / spacing[g->a1];
  g->shift[1] = -g->path * p[g->a2] / spacing[g->a2];
  g->first_path = 0.5 * spacing[g->axis] / fabs(p[g->axis]);
}


/* Bilinear look-up of the light state in a plane across axis `axis` (its samples in rows along
 * a1, stride floats each) at the fractional in-plane coordinates (u, w) along the two other axes
 * (a1, a2). Returns 0 outside the plane. */
static int plane_lookup(const sl_renderer *r, const float *plane, int axis, double u, double w, double *out)
{
  const sl_volume *v = &r->shape;
  const int n[3] = {v->nx, v->ny, v->nz};
  const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
  if (!sl_sweep_in_plane(u, w, n[a1], n[a2])) return 0;
  const double fresh = sl_sweep_fresh_weight(u, w, n[a1], n[a2]);
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

/* What the sweep needs: its geometry and the planes it keeps. */
typedef struct sweep_frame {
  const sl_renderer *r;
  float *state;
  /* The last SWEEP_PLANES planes, the one being swept among them, in rows along a1: the sweep
   * reads the previous plane from here (a megabyte at 256^2) instead of from the volume, where a
   * plane across x or y is a sample every few kilobytes and each look-up missed the cache; and
   * writes them to the volume together, SWEEP_PLANES at a time (sweep_planes, after each group). */
  float *plane[SWEEP_PLANES];
  sl_sweep_geometry g;
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
  const sl_sweep_geometry *g = &f->g;
  const int stride = nwl + 1, axis = g->axis, a1 = g->a1, a2 = g->a2, step = g->step;
  const int n[3] = {v->nx, v->ny, v->nz};
  const double *sun = r->scene.sun_direction;
  float *state = f->state;
  for (int kk = 0; kk < n[axis]; ++kk) {
    const int k = g->first + kk * step;
#pragma omp for schedule(static)
    for (int jj = 0; jj < n[a2]; ++jj)
      for (int ii = 0; ii < n[a1]; ++ii) {
        int idx[3];
        idx[axis] = k, idx[a1] = ii, idx[a2] = jj;
        float *out = f->plane[kk % SWEEP_PLANES] + ((size_t)jj * n[a1] + ii) * stride;
        double prev[SL_MAX_WAVELENGTHS + 1];
        double x[3];
        for (int a = 0; a < 3; ++a) x[a] = v->origin[a] + idx[a] * v->spacing[a];
        double len = g->path;
        /* The state where this sample's sun ray crossed the previous plane, or fresh sunlight
         * entering the box (through the first plane or a side face) over a shorter path. */
        if (kk == 0 ||
            !plane_lookup(r, f->plane[(kk - 1) % SWEEP_PLANES], axis, ii + g->shift[0], jj + g->shift[1], prev)) {
          for (int c = 0; c < nwl; ++c) prev[c] = 0.0;
          prev[nwl] = 0.0;
          len = sl__min(g->path, sl__box_exit_distance(&f->sun_exit, x));
          if (kk == 0) len = g->first_path;
        }
        /* Fields at the middle of the path since the previous plane (toward the sun from x). */
        const double mid[3] = {x[0] + 0.5 * len * sun[0], x[1] + 0.5 * len * sun[1], x[2] + 0.5 * len * sun[2]};
        float beta[SL_MAX_FIELDS];
        sl__sample_fields_n(r, nf, mid, beta);
        double total = 0.0;
        for (int j = 0; j < nf; ++j) total += beta[j];
        if (!(total > 0.0 && len > 0.0)) {
          /* Nothing on the path: the light arrives as it left the previous plane. */
          for (int c = 0; c < nwl; ++c) out[c] = fmaxf((float)prev[c], (float)SL_LOG_FLOOR);
          out[nwl] = (float)prev[nwl];
          continue;
        }
        /* One light step on the stored ln I and n (no exponential and logarithm around it). */
        for (int s = 0; s <= nwl; ++s) out[s] = (float)prev[s];
        sl_log_light_step_at(m, (int)m->mode, nf, nwl, beta, len, out, 0);
        for (int c = 0; c < nwl; ++c) out[c] = fmaxf(out[c], (float)SL_LOG_FLOOR);
      }
    if (kk % SWEEP_PLANES == SWEEP_PLANES - 1 || kk == n[axis] - 1) {
      /* The planes since the last flush into the volume, sample by sample across them. */
      const int held = kk % SWEEP_PLANES + 1;
#pragma omp for schedule(static)
      for (int jj = 0; jj < n[a2]; ++jj)
        for (int ii = 0; ii < n[a1]; ++ii)
          for (int b = 0; b < held; ++b) {
            int idx[3];
            idx[axis] = g->first + (kk - held + 1 + b) * step, idx[a1] = ii, idx[a2] = jj;
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
  const int n[3] = {v->nx, v->ny, v->nz};
  sl_sweep_geometry_init(n, v->spacing, sun, &f.g);
  double box_lo[3], box_hi[3];
  sl_volume_bounds(v, box_lo, box_hi);
  sl__box_exit_init(&f.sun_exit, box_lo, box_hi, sun);
  const double t0 = omp_get_wtime();
  const size_t plane_floats = (size_t)n[f.g.a1] * n[f.g.a2] * stride;
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
