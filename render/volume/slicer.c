/* Half-angle slicing on the CPU (Riley et al. 2004, sec. 4). Per slice, the eye pass gathers light
 * scattered toward the camera from the slice, reading the light buffer (transparency from the sun
 * to the slice), then the light pass attenuates the light buffer through the slice. Every pixel
 * and texel is independent within a pass, so the image does not depend on the number of threads.
 * The frame's geometry is slicing.c's, its tiles tiles.h's, the eye pass's batches eye_batch.h's. */
#include "eye_batch.h"
#include "light_kink.h"
#include "resolve.h"
#include "slicer.h"

#include <limits.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* Each light texel's ray: its state at the top of the volume (ln I = 0, n = 0), its span in the
 * content box and occupied stretch (kept from the last frame when the sun and lattice are the
 * same), where it enters the medium (under a low sun), and the slices it crosses; then each texel
 * cell's least and largest entry (light_kink). */
static inline __attribute__((always_inline)) void texel_setup(slicer_frame *f, const light_buffer *Lp, const int nwl)
{
  const sl_renderer *r = f->r;
  const light_buffer L = *Lp;
  const double *h = f->h, *prop = f->prop;
  const double inv_hp = f->inv_hp, hp = f->hp, smin = f->smin, ds = f->ds;
  const int kink = f->kink;
  const size_t nl = (size_t)L.w * L.h;
  /* Dynamic: a texel's entry march (sl__texel_entry) runs from a few samples to its whole ray. */
#pragma omp for schedule(dynamic, 256)
  for (size_t t = 0; t < nl; ++t) {
    const int i = (int)(t % L.w), j = (int)(t / L.w);
    const double ca = L.amin + (i + 0.5) * L.texel_a, cb = L.bmin + (j + 0.5) * L.texel_b;
    const double origin[3] = {ca * L.a[0] + cb * L.b[0], ca * L.a[1] + cb * L.b[1], ca * L.a[2] + cb * L.b[2]};
    double u0, u1;
    float *st = L.state + t * L.stride;
    for (int c = 0; c < nwl; ++c) st[c] = 0.0f; /* ln I: the sunlight above the volume */
    st[nwl] = 0.0f;
    L.h_origin[t] = sl_dot3(h, origin);
    L.k_lo[t] = 1, L.k_hi[t] = 0;
    if (!f->spans_kept) {
      /* u_in, u_out of a miss are read (and discarded) by the light pass's vector set-up. */
      L.u_in[t] = L.u_out[t] = 0.0f;
      f->texel_first[t] = 1.0, f->texel_last[t] = 0.0;
      f->texel_entry[t] = NAN;
      if (sl_ray_box(r->clo, r->chi, origin, prop, &u0, &u1)) {
        L.u_in[t] = (float)u0, L.u_out[t] = (float)u1;
        sl__occupied_span(r, origin, prop, u0, u1, &f->texel_first[t], &f->texel_last[t]);
        if (kink && f->texel_first[t] <= f->texel_last[t])
          f->texel_entry[t] =
              (float)sl__texel_entry(r, origin, prop, f->texel_first[t], f->texel_last[t], f->entry_step);
      }
    }
    if (kink) {
      L.entry_g[t] = L.h_origin[t] * inv_hp + f->texel_entry[t];
      L.entry_state[t * L.stride + nwl] = -1.0f; /* not kept yet (n is never negative) */
    }
    const double first = f->texel_first[t], last = f->texel_last[t];
    if (first <= last) {
      const double s0 = L.h_origin[t] + first * hp, s1 = L.h_origin[t] + last * hp;
      L.k_lo[t] = (int)floor((s0 - smin) / ds) - 1;
      L.k_hi[t] = (int)floor((s1 - smin) / ds) + 1;
    }
  }
  /* Each texel cell's least and largest entry (light_kink): a slice plane lies between them
   * where some of its corners have entered the medium and some have not yet. */
#pragma omp for schedule(static)
  for (size_t t = 0; t < (kink ? nl : 0); ++t) {
    const int i = (int)(t % L.w), j = (int)(t / L.w);
    const int i1 = i + 1 < L.w ? i + 1 : i, j1 = j + 1 < L.h ? j + 1 : j;
    const double g[4] = {L.entry_g[t], L.entry_g[(size_t)j * L.w + i1], L.entry_g[(size_t)j1 * L.w + i],
                         L.entry_g[(size_t)j1 * L.w + i1]};
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 4; ++k)
      if (g[k] == g[k]) lo = g[k] < lo ? g[k] : lo, hi = g[k] > hi ? g[k] : hi;
    /* Only where the surface meets the sunlight at a grazing angle (neighbouring entries more
     * than KINK_SPREAD texel widths apart along the rays, an angle below 14 degrees): a surface
     * more across the sunlight is crossed within a few texels of its rows, which the texel size
     * resolves (slicing.c, light_texel_resolving). fmax passes over a NaN (a ray that never
     * enters). */
    const double spread_a = fmax(fabs(g[1] - g[0]), fabs(g[3] - g[2]));
    const double spread_b = fmax(fabs(g[2] - g[0]), fabs(g[3] - g[1]));
    if (!(spread_a > KINK_SPREAD * L.texel_a || spread_b > KINK_SPREAD * L.texel_b))
      lo = INFINITY, hi = -INFINITY;
    L.cell_gmin[t] = lo, L.cell_gmax[t] = hi;
  }
}

/* Each pixel's ray: its direction, its span in the content box (up to an opaque surface), the
 * slices its occupied stretch crosses, and its scattering angle's table index and weight (fixed
 * along the ray under a collimated sun, so hoisted out of the slice loop). */
static inline __attribute__((always_inline)) void ray_setup(slicer_frame *f, const int nwl)
{
  const sl_renderer *r = f->r;
  const sl_camera *cam = f->cam;
  const sl_image *img = f->img;
  float *acc = f->acc;
  double *ray = f->ray;
  int *pk = f->pk, *angle_index = f->angle_index;
  float *angle_weight = f->angle_weight;
  const sl_phase_table *grid_table = f->grid_table;
  const double *fwd = f->fwd, *right = f->right, *up = f->up, *h = f->h;
  const double *sun = r->scene.sun_direction, *o = cam->position;
  const double tan_half = f->tan_half, aspect = f->aspect, h_o = f->h_o, smin = f->smin, ds = f->ds;
  const int acc_stride = nwl + 2;
  const size_t np = (size_t)img->width * img->height;
#pragma omp for schedule(static)
  for (size_t q = 0; q < np; ++q) {
    double d[3];
    sl_camera_pixel_ray(fwd, right, up, tan_half, aspect, img->width, img->height, (int)(q % img->width),
                        (int)(q / img->width), d);
    float *a = acc + q * acc_stride;
    a[nwl] = 1.0f; /* transparency toward the eye */
    double *rq = ray + q * RAY_STRIDE;
    rq[0] = d[0], rq[1] = d[1], rq[2] = d[2];
    rq[5] = sl_dot3(h, d);
    rq[6] = rq[5] != 0.0 ? 1.0 / rq[5] : 0.0;
    pk[2 * q] = 1, pk[2 * q + 1] = 0;
    rq[3] = rq[4] = 0.0; /* an empty span until the box is hit: the resolve reads every ray's */
    angle_index[q] = 0, angle_weight[q] = 0.0f;
    if (grid_table) {
      /* Scattering angle between the sunlight's propagation and the direction to the eye. */
      double across[3];
      sl_cross3(sun, d, across);
      const double u = sl_angle_grid_position(sqrt(sl_dot3(across, across)), sl_dot3(sun, d), grid_table->inv_step_rad);
      const int i = sl_angle_row(u, grid_table->n_angles);
      angle_index[q] = i;
      angle_weight[q] = (float)sl_angle_weight(u, i);
    }
    double t0, t1;
    /* A ray almost parallel to the slices crosses none of them within the box. */
    if (fabs(rq[5]) < 1e-9 || !sl_ray_box(r->clo, r->chi, o, d, &t0, &t1) || t1 <= 0.0) continue;
    if (t0 < 0.0) t0 = 0.0;
    if (cam->opaque_distance && cam->opaque_distance[q] < t1) t1 = cam->opaque_distance[q];
    if (t1 <= t0) continue; /* an opaque surface in front of the volume */
    rq[3] = t0, rq[4] = t1;
    double first, last;
    sl__occupied_span(r, o, d, t0, t1, &first, &last);
    if (first > last) continue; /* the ray crosses only empty bricks */
    const double s0 = h_o + first * rq[5], s1 = h_o + last * rq[5];
    pk[2 * q] = (int)floor((sl__min(s0, s1) - smin) / ds) - 1;
    pk[2 * q + 1] = (int)floor((sl__max(s0, s1) - smin) / ds) + 1;
  }
}

/* The samples of eye tile ti in slice k (centre sk): per row the pixels whose span holds the
 * slice (most do not: a scalar test each), then their segments and lattice cells as a vector loop
 * (gathers), then bricks per sample; the cells prefetched, so that their loads are in flight
 * while the next rows are found. Returns their count; *tile_last: the last slice any of the
 * tile's rays still wants. */
static inline __attribute__((always_inline)) int eye_tile_samples(const slicer_frame *f, const int nf, int k,
                                                                  double sk, int tx0, int ty0, int *sq,
                                                                  double *smid, double *slen,
                                                                  sl__field_cell *cells, sl__field_cell *far_cells,
                                                                  int *tile_last,
                                                                  long *eye_samples)
{
  const sl_renderer *r = f->r;
  const sl_image *img = f->img;
  const int *pk = f->pk;
  const double *ray = f->ray, *o = f->cam->position;
  const double h_o = f->h_o, ds = f->ds;
  const sl_grid_view *g = &r->lattice;
  const int tx1 = tx0 + TILE < img->width ? tx0 + TILE : img->width;
  int cnt = 0;
  for (int py = ty0; py < ty0 + TILE && py < img->height; ++py) {
    const size_t row = (size_t)py * img->width;
    int active[TILE], n = 0;
    for (int px = tx0; px < tx1; ++px) {
      const size_t q = row + px;
      active[n] = px;
      n += k >= pk[2 * q] && k <= pk[2 * q + 1];
      *tile_last = pk[2 * q + 1] > *tile_last ? pk[2 * q + 1] : *tile_last;
    }
    if (!n) continue;
    row_lattice rl, far;
    double mid_of[TILE], len_of[TILE];
    int lanes[TILE];
#pragma GCC ivdep
    for (int i = 0; i < n; ++i) {
      /* ray[rq...]: the ray's record, as an index (GCC gathers base + index x 8, not x 56) */
      const ptrdiff_t rq = ((ptrdiff_t)row + active[i]) * RAY_STRIDE;
      double mid;
      rl.take[i] = clip_segment((sk - h_o) * ray[rq + 6], 0.5 * ds * fabs(ray[rq + 6]), ray[rq + 3], ray[rq + 4],
                                &mid, &len_of[i]);
      mid_of[i] = mid;
      const double x[3] = {o[0] + mid * ray[rq], o[1] + mid * ray[rq + 1], o[2] + mid * ray[rq + 2]};
      row_lattice_set(&rl, i, g, x);
      double x_far[3];
      sl__segment_far_end(g, o, ray + rq, mid + 0.5 * len_of[i], x_far);
      row_lattice_set(&far, i, g, x_far);
    }
    const int found = row_cells(r, nf, &rl, &far, n, eye_samples, lanes, cells + cnt, far_cells + cnt);
    for (int s = 0; s < found; ++s) {
      const int i = lanes[s];
      sq[cnt + s] = (int)(row + active[i]), smid[cnt + s] = mid_of[i], slen[cnt + s] = len_of[i];
    }
    cnt += found;
  }
  return cnt;
}

/* Eye pass over tile ti in slice k: gather the light scattered toward the eye (eq. 26), one batch
 * of the tile's samples at a time (eye_batch.h), and record the tile's cost and last slice. */
static inline __attribute__((always_inline)) void eye_pass_tile(const slicer_frame *f, const int nf, const int nwl,
                                                                const light_buffer *L, ptrdiff_t light_di,
                                                                ptrdiff_t light_dj, const sl__sun_lane *sun_lane,
                                                                tile_ranges *eye_tiles, int k, size_t ti,
                                                                eye_batch *b, long *eye_samples)
{
  const double sk = f->smin + (k + 0.5) * f->ds;
  const unsigned long long tile_start = tile_clock();
  const int tx0 = (int)(ti % eye_tiles->nx) * TILE, ty0 = (int)(ti / eye_tiles->nx) * TILE;
  int sq[TILE * TILE];
  double smid[TILE * TILE], slen[TILE * TILE];
  sl__field_cell cells[TILE * TILE], far_cells[TILE * TILE];
  int tile_last = k;
  const int cnt =
      eye_tile_samples(f, nf, k, sk, tx0, ty0, sq, smid, slen, cells, far_cells, &tile_last, eye_samples);
  const double s_start = sk - 0.5 * f->ds;
  for (int si = 0; si < cnt;) {
    si = eye_batch_parts(f, nf, nwl, b, cells, far_cells, sq, smid, slen, si, cnt);
    eye_batch_geometry(f, L, sun_lane, s_start, b);
    eye_batch_light(f, nf, nwl, L, light_di, light_dj, s_start, b);
    eye_batch_scatter(f, nf, nwl, b);
    eye_batch_composite(f, nwl, k, b);
  }
  eye_tiles->work[(size_t)((k + 1) & 1) * eye_tiles->nx * eye_tiles->ny + ti] = tile_cost(tile_start, cnt);
  /* Rays that have become opaque end their spans (eye_batch_composite); a tile whose rays have
   * all ended leaves the list from the next slice but one (this slice's end is seen in the next
   * one's scan), where it took 256 failing tests per slice to the far side of the cloud. The new
   * end is never below k: another thread may be listing slice k's tiles now, and k's membership
   * stays as it was (tiles_active). */
  if (tile_last < eye_tiles->k[2 * ti + 1]) __atomic_store_n(&eye_tiles->k[2 * ti + 1], tile_last, __ATOMIC_RELAXED);
}

/* Light pass over tile ti in slice k: carry the light and its expected scattering count through
 * the slice (eqs. 21, 24). The tile's cells first, prefetched (per row, row_lattice); then their
 * fields, whose loads overlap; then the steps. */
static inline __attribute__((always_inline)) void light_pass_tile(const slicer_frame *f, const int nf, const int nwl,
                                                                  const light_buffer *Lp, tile_ranges *light_tiles,
                                                                  int k, size_t ti, long *light_samples)
{
  const sl_renderer *r = f->r;
  const sl_light_model *m = &r->model;
  const light_buffer L = *Lp;
  const double *prop = f->prop;
  const double inv_hp = f->inv_hp, ds = f->ds, sk = f->smin + (k + 0.5) * f->ds;
  const int kink = f->kink;
  const unsigned long long tile_start = tile_clock();
  const int tx0 = (int)(ti % light_tiles->nx) * TILE, ty0 = (int)(ti / light_tiles->nx) * TILE;
  int cnt = 0;
  int idx[TILE * TILE];
  double seg[TILE * TILE], seg_end[TILE * TILE];
  float bj[TILE * TILE][SL_MAX_FIELDS];
  sl__field_cell cells[TILE * TILE];
  const double half = 0.5 * ds * inv_hp;
  const sl_grid_view *g = &r->lattice;
  const int tx1 = tx0 + TILE < L.w ? tx0 + TILE : L.w;
  const double *restrict h_origin = L.h_origin;
  const float *restrict u_in = L.u_in, *restrict u_out = L.u_out;
  const int *restrict k_lo = L.k_lo, *restrict k_hi = L.k_hi;
  const double amin = L.amin, texel_a = L.texel_a;
  const double la[3] = {L.a[0], L.a[1], L.a[2]}, lb[3] = {L.b[0], L.b[1], L.b[2]};
  for (int ty = ty0; ty < ty0 + TILE && ty < L.h; ++ty) {
    const size_t row = (size_t)ty * L.w + tx0;
    const double cb = L.bmin + (ty + 0.5) * L.texel_b;
    row_lattice rl;
    double len_of[TILE], end_of[TILE];
    int lanes[TILE];
#pragma GCC ivdep
    for (int i = 0; i < tx1 - tx0; ++i) {
      const size_t t = row + i;
      double mid;
      const int crosses = clip_segment((sk - h_origin[t]) * inv_hp, half, u_in[t], u_out[t], &mid, &len_of[i]);
      end_of[i] = mid + 0.5 * len_of[i];
      rl.take[i] = (k >= k_lo[t]) & (k <= k_hi[t]) & crosses;
      const double ca = amin + (tx0 + i + 0.5) * texel_a;
      const double x[3] = {ca * la[0] + cb * lb[0] + mid * prop[0], ca * la[1] + cb * lb[1] + mid * prop[1],
                           ca * la[2] + cb * lb[2] + mid * prop[2]};
      row_lattice_set(&rl, i, g, x);
    }
    const int found = row_cells(r, nf, &rl, NULL, tx1 - tx0, light_samples, lanes, cells + cnt, NULL);
    for (int s = 0; s < found; ++s)
      idx[cnt + s] = (int)(row + lanes[s]), seg[cnt + s] = len_of[lanes[s]], seg_end[cnt + s] = end_of[lanes[s]];
    cnt += found;
  }
  int live = 0;
  for (int i = 0; i < cnt; ++i) {
    float v[SL__FIELD_LANES];
    sl__field_fetch(r, nf, &cells[i], v);
    double beta = 0.0;
    for (int j = 0; j < nf; ++j) beta += v[j];
    if (!(beta > 0.0)) continue;
    idx[live] = idx[i], seg[live] = seg[i], seg_end[live] = seg_end[i];
    for (int j = 0; j < nf; ++j) bj[live][j] = v[j];
    live++;
  }
  cnt = live;
  const sl_light_model *held_model = m;
  const int held = sl__batch_fields(f->subsets, nf, cnt, bj, &held_model);
  /* The state where each ray enters the medium: before the first step it takes past that (steps
   * not taken leave the state as it was, so it is the state at the entry). */
  for (int i = 0; i < (kink ? cnt : 0); ++i) {
    float *kept = L.entry_state + (size_t)idx[i] * L.stride;
    if (seg_end[i] > L.u_entry[idx[i]] && kept[nwl] < 0.0f)
      for (int c = 0; c <= nwl; ++c) kept[c] = L.state[(size_t)idx[i] * L.stride + c];
  }
#define LIGHT_STEPS(model, mode, count) light_steps(model, mode, count, nwl, cnt, idx, seg, bj, L.state, L.stride)
  SL_WITH_BATCH_MODEL(m, held_model, held, nf, LIGHT_STEPS);
#undef LIGHT_STEPS
  light_tiles->work[(size_t)((k + 1) & 1) * light_tiles->nx * light_tiles->ny + ti] = tile_cost(tile_start, cnt);
}

/* Resolve: premultiplied volume radiance, opacity and the opacity-weighted depth. With an
 * atmosphere the air in front of the volume's midplane (sec. 5) attenuates the volume and adds its
 * own light: frame = L_front + T_front V + T_vol (L_back + L_sun). The layer carries
 * V' = T_front V + (1 - T_vol) L_front, so that V' + T_vol (whole sky + sun) is that frame.
 * Spectral radiance becomes linear sRGB here (sl__resolve_pixel). */
static inline __attribute__((always_inline)) void slicer_resolve(slicer_frame *f, const int nwl)
{
  const sl_renderer *r = f->r;
  const double *ray = f->ray;
  const float *acc = f->acc;
  sl_image *img = f->img;
  const int acc_stride = nwl + 2;
  const size_t np = (size_t)img->width * img->height;
  const double h_center = sl_dot3(f->h, r->content_center), h_o = f->h_o;
  const sl_sky_view *view = r->scene.atmosphere ? f->view : NULL;
#pragma omp for schedule(static)
  for (size_t q = 0; q < np; ++q) {
    const double *rq = ray + q * RAY_STRIDE;
    const double t_mid = sl_resolve_split(rq[5], h_center - h_o, rq[3], rq[4]);
    sl__resolve_pixel(r, nwl, view, rq, t_mid, acc + q * acc_stride, img, q);
  }
}

/* One thread's share of a frame's passes (called by every thread of a parallel region; the
 * work-sharing loops inside bind to it): light-buffer and ray set-up, then per slice the eye pass
 * and the light pass, then the resolve. Always inlined into the parallel regions of
 * SL_RUN_SPECIALISED, each with constant field and wavelength counts, so that the per-sample
 * loops over fields and wavelengths unroll. */
static inline __attribute__((always_inline)) void slicer_passes(slicer_frame *f, const int nf, const int nwl)
{
  const sl_renderer *r = f->r;
  const sl_scene *sc = &r->scene;
  const light_buffer L = *f->L;
  const sl__sun_lane sun_lane = sl__sun_table_lane(f->suntab);
  ptrdiff_t light_di, light_dj;
  light_texel_steps(&L, &light_di, &light_dj);
  tile_ranges eye_tiles = *f->eye_tiles, light_tiles = *f->light_tiles;
  const int nslices = f->nslices;
  long eye_samples = 0, light_samples = 0;
  eye_batch batch; /* this thread's batch of an eye tile's samples */

  texel_setup(f, &L, nwl);
  ray_setup(f, nwl);
  const size_t n_eye_tiles = (size_t)eye_tiles.nx * eye_tiles.ny, n_light_tiles = (size_t)light_tiles.nx * light_tiles.ny;
#pragma omp for schedule(static)
  for (size_t i = 0; i < n_eye_tiles; ++i)
    sl__tile_range_from(&eye_tiles, i, f->img->width, f->img->height, f->pk, f->pk + 1, 2);
#pragma omp for schedule(static)
  for (size_t i = 0; i < n_light_tiles; ++i) sl__tile_range_from(&light_tiles, i, L.w, L.h, L.k_lo, L.k_hi, 1);

#pragma omp single
  f->barrier.team = omp_get_num_threads();
  for (int k = 0; k < nslices && r->any_extinction; ++k) {
    double t_start = 0.0;
#pragma omp master
    t_start = omp_get_wtime();
    int n_active, pos;
    const int *active_tiles = tiles_active(&eye_tiles, k, &n_active);
    while (tiles_take(&eye_tiles, k, active_tiles, n_active, &pos))
      eye_pass_tile(f, nf, nwl, &L, light_di, light_dj, &sun_lane, &eye_tiles, k, (size_t)active_tiles[pos], &batch,
                    &eye_samples);
    /* The light pass rewrites the buffer the eye pass reads. */
    slice_barrier_wait(&f->barrier);
#pragma omp master
    {
      const double t_mid = omp_get_wtime();
      f->eye_seconds += t_mid - t_start;
      t_start = t_mid;
    }
    active_tiles = tiles_active(&light_tiles, k, &n_active);
    while (tiles_take(&light_tiles, k, active_tiles, n_active, &pos))
      light_pass_tile(f, nf, nwl, &L, &light_tiles, k, (size_t)active_tiles[pos], &light_samples);
    slice_barrier_wait(&f->barrier);
#pragma omp master
    {
      f->light_seconds += omp_get_wtime() - t_start;
      if (sc->progress) sc->progress(sc->progress_user, (k + 1.0) / nslices);
    }
  }
  slicer_resolve(f, nwl);
#pragma omp atomic
  f->eye_samples += eye_samples;
#pragma omp atomic
  f->light_samples += light_samples;
}

#ifdef SL_WIDE_TARGET
SL_WIDE_TARGET static void slicer_run_wide(slicer_frame *f)
{
  SL_RUN_SPECIALISED(slicer_passes, f, f->r->model.nf, f->r->model.nwl);
}
#endif

static void slicer_run(slicer_frame *f)
{
  f->eye_samples = f->light_samples = 0;
  f->eye_seconds = f->light_seconds = 0.0;
  f->wide_isa = 0;
#ifdef SL_WIDE_TARGET
  if (sl__wide_isa(&f->r->scene)) {
    f->wide_isa = 1;
    slicer_run_wide(f);
    return;
  }
#endif
  SL_RUN_SPECIALISED(slicer_passes, f, f->r->model.nf, f->r->model.nwl);
}


/* A frame of the slicer: the slicing, the light buffer and the frame's buffers, then the passes
 * (slicer_run); fwd, right, up: the camera's basis (sl_camera_basis). */
int sl__render_slicer(sl_renderer *r, const sl_camera *cam, const double fwd[3], const double right[3],
                      const double up[3], sl_image *img, sl_render_stats *stats, sl_error *err)
{
  const sl_scene *sc = &r->scene;
  const double *sun = sc->sun_direction;
  sl_sky_view view = {0};
  if (sc->atmosphere && sl_sky_view_init(&view, sc->atmosphere, cam->position, sun, err)) return err->code;
  sun_table *suntab = malloc(sizeof *suntab);
  if (!suntab) return sl_fail(err, SL_ERR_NOMEM, "render: out of memory");
  sl__sun_table_init(suntab, sc, &view, r->clo, r->chi);
  const double prop[3] = {-sun[0], -sun[1], -sun[2]};
  sl_slicing slicing;
  sl_choose_slicing(fwd, sun, &slicing);
  const double *h = slicing.half_vector;
  const int back_to_front = slicing.back_to_front;

  double smin, smax; /* the slices span the content box along h */
  sl__slice_range(r, h, &smin, &smax);
  int nslices = sc->slices;
  if (nslices == 0) nslices = sl_slices_resolving_grid(&r->shape, h, fwd, prop, smax - smin);
  const double ds = (smax - smin) / nslices;
  const double hp = sl_dot3(h, prop); /* > 0 by construction */
  const double inv_hp = 1.0 / hp;
  sl__box_exit sun_exit;
  sl__box_exit_init(&sun_exit, r->clo, r->chi, sun);

  const double tan_half = tan(0.5 * cam->fov_deg * M_PI / 180.0);
  /* Light buffer: an orthographic grid perpendicular to the sunlight covering the box. */
  light_buffer L = {0};
  double to_centre[3];
  for (int a = 0; a < 3; ++a) to_centre[a] = r->content_center[a] - cam->position[a];
  const double pixel = sqrt(sl_dot3(to_centre, to_centre)) * 2.0 * tan_half / img->height;
  sl__light_buffer_lattice(r, prop, pixel, img->width > img->height ? img->width : img->height, &L);
  const sl_light_model *m = &r->model;
  const int nwl = m->nwl, nf = m->nf;
  const int acc_stride = nwl + 2; /* radiance per wavelength, transparency, depth numerator */
  L.stride = nwl + 1;
  const size_t nl = (size_t)L.w * L.h, np = (size_t)img->width * img->height;
  if (nl * L.stride > INT_MAX) { /* the eye pass's texel offsets are ints (light_texel_lane) */
    free(suntab);
    return sl_fail(err, SL_ERR_ARG, "render: a %d x %d light buffer is too large (at most 2^31 values)", L.w,
                   L.h);
  }
  const int spans_kept = sl__texel_spans_hold(&r->texel_spans, prop, &L);
  if (!spans_kept && sl__texel_spans_prepare(&r->texel_spans, prop, &L)) {
    free(suntab);
    return sl_fail(err, SL_ERR_NOMEM, "render: out of memory for the light buffer");
  }
  L.u_in = r->texel_spans.u_in, L.u_out = r->texel_spans.u_out, L.u_entry = r->texel_spans.u_entry;
  L.state = malloc((nl * L.stride + LIGHT_STATE_PAD) * sizeof(float));
  if (L.state)
    for (int i = 0; i < LIGHT_STATE_PAD; ++i) L.state[nl * L.stride + i] = 0.0f;
  /* The entry kink (light_kink) where flat tops meet the sunlight at a grazing angle: under a sun
   * below KINK_SUN_ELEVATION. Where it runs it costs up to half an eye pass (docs/PERFORMANCE.md),
   * which a higher sun's frames need not pay. */
  const int kink = sun[2] < sin(KINK_SUN_ELEVATION * M_PI / 180.0);
  if (kink) {
    L.entry_state = malloc(nl * L.stride * sizeof(float));
    L.entry_g = malloc(nl * sizeof(double));
    L.cell_gmin = malloc(nl * sizeof(double)), L.cell_gmax = malloc(nl * sizeof(double));
  }
  L.h_origin = malloc(nl * sizeof(double));
  L.k_lo = malloc(nl * sizeof(int));
  L.k_hi = malloc(nl * sizeof(int));
  float *acc = calloc(np * acc_stride, sizeof(float));
  double *ray = malloc(np * RAY_STRIDE * sizeof(double)); /* direction xyz, t_in, t_out, h.d, 1 / h.d */
  int *pk = malloc(np * 2 * sizeof(int));
  /* The scattering angle is fixed along a pixel's ray (collimated sun): its table index and
   * weight are hoisted out of the slice loop. */
  int *angle_index = malloc(np * sizeof(int));
  float *angle_weight = malloc(np * sizeof(float));
  tile_ranges eye_tiles = {0}, light_tiles = {0};
  const int threads = omp_get_max_threads();
  const int tiles_ok =
      sl__tiles_init(&eye_tiles, img->width, img->height, threads) && sl__tiles_init(&light_tiles, L.w, L.h, threads);
  const int kink_ok = !kink || (L.entry_state && L.entry_g && L.cell_gmin && L.cell_gmax);
  if (!L.state || !L.h_origin || !L.k_lo || !L.k_hi || !kink_ok || !acc || !ray || !pk || !angle_index ||
      !angle_weight || !tiles_ok) {
    free(L.state), free(L.h_origin), free(L.k_lo), free(L.k_hi);
    free(L.entry_state), free(L.entry_g), free(L.cell_gmin), free(L.cell_gmax);
    free(acc), free(ray), free(pk), free(suntab), free(angle_index), free(angle_weight);
    sl__tiles_free(&eye_tiles), sl__tiles_free(&light_tiles);
    return sl_fail(err, SL_ERR_NOMEM, "render: out of memory for the buffers");
  }
  const sl_phase_table *grid_table = nf > 0 && m->mode != SL_LIGHTING_LOW_ALBEDO ? m->table[0][0] : NULL;
  const double aspect = (double)img->width / img->height;
  const double *o = cam->position;
  const double h_o = sl_dot3(h, o);
  slicer_frame f = {.subsets = r->has_subsets ? r->field_subsets : NULL, .r = r, .cam = cam, .img = img, .view = &view, .suntab = suntab, .L = &L,
                    .eye_tiles = &eye_tiles, .light_tiles = &light_tiles, .acc = acc, .ray = ray, .pk = pk,
                    .angle_index = angle_index, .angle_weight = angle_weight, .grid_table = grid_table,
                    .sun_exit = sun_exit, .tan_half = tan_half, .aspect = aspect, .h_o = h_o, .hp = hp,
                    .inv_hp = inv_hp, .smin = smin, .ds = ds, .nslices = nslices, .back_to_front = back_to_front,
                    .texel_first = r->texel_spans.first, .texel_last = r->texel_spans.last,
                    .texel_entry = r->texel_spans.u_entry, .spans_kept = spans_kept, .kink = kink,
                    .barrier = SLICE_BARRIER_INIT};
  /* The entry march's step: one grid cell along the sunlight (the shortest axis's crossing). */
  f.entry_step = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const int n_a = a == 0 ? r->shape.nx : a == 1 ? r->shape.ny : r->shape.nz;
    if (n_a > 1 && fabs(prop[a]) > 1e-12) f.entry_step = fmin(f.entry_step, r->shape.spacing[a] / fabs(prop[a]));
  }
  for (int a = 0; a < 3; ++a)
    f.fwd[a] = fwd[a], f.right[a] = right[a], f.up[a] = up[a], f.h[a] = h[a], f.prop[a] = prop[a];
  slicer_run(&f);
  r->texel_spans.valid = 1;
  const long eye_samples = f.eye_samples, light_samples = f.light_samples;
  const double light_seconds = f.light_seconds, eye_seconds = f.eye_seconds;
  if (stats) {
    stats->light_seconds = light_seconds;
    stats->eye_seconds = eye_seconds;
    stats->slices = nslices;
    stats->light_width = L.w;
    stats->light_height = L.h;
    stats->eye_samples = eye_samples;
    stats->light_samples = light_samples;
    stats->night = view.night;
    stats->wide_isa = f.wide_isa;
  }
  free(suntab);
  free(L.state), free(L.h_origin), free(L.k_lo), free(L.k_hi);
  free(L.entry_state), free(L.entry_g), free(L.cell_gmin), free(L.cell_gmax);
  free(acc), free(ray), free(pk), free(angle_index), free(angle_weight);
  sl__tiles_free(&eye_tiles), sl__tiles_free(&light_tiles);
  return SL_OK;
}

