/* Empty space: which 8^3 bricks of the lattice hold medium, each empty brick's distance to the
 * nearest occupied one, the walk that finds where a ray first meets medium, the box around the
 * medium, and each 2^3-cell block's distance to medium (the adaptive march's clear blocks). Every
 * pass of render/volume starts its rays and texels here. */
#include "renderer_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int sl__bricks_build(sl_renderer *r, sl_error *err)
{
  /* A brick is occupied where any trilinear cell with its lower corner in it reads a non-zero
   * total extinction; then each empty brick's distance to the nearest occupied one. */
  const sl_volume *v = &r->shape;
  const int nf = r->model.nf > 0 ? r->model.nf : 1;
  const int n[3] = {v->nx, v->ny, v->nz};
  for (int a = 0; a < 3; ++a) r->bricks[a] = (n[a] + 7) / 8;
  const size_t bricks = (size_t)r->bricks[0] * r->bricks[1] * r->bricks[2];
  r->empty_radius = malloc(bricks);
  r->brick_beta_max = calloc(bricks, sizeof(float));
  if (!r->empty_radius || !r->brick_beta_max) return sl_fail(err, SL_ERR_NOMEM, "renderer: out of memory");
  memset(r->empty_radius, 1, bricks);
  /* Outside the volume's content box every field, and so the total, is zero. Brick by brick, so
   * that the threads share the bricks and none writes another's: a brick's cells have their lower
   * corners at samples 8b .. 8b + 7 along each axis and read samples 8b .. 8b + 8. */
  int lo[3], hi[3], b_lo[3], b_hi[3];
  if (!sl_volume_content_samples(v, lo, hi)) {
    sl__brick_empty_radius(r->bricks, r->empty_radius);
    return SL_OK;
  }
  for (int a = 0; a < 3; ++a) {
    b_lo[a] = lo[a] > 0 ? (lo[a] - 1) / 8 : 0;
    b_hi[a] = hi[a] / 8 < r->bricks[a] - 1 ? hi[a] / 8 : r->bricks[a] - 1;
  }
  const int rows_y = b_hi[1] - b_lo[1] + 1, rows = (b_hi[2] - b_lo[2] + 1) * rows_y;
#pragma omp parallel for schedule(dynamic, 1)
  for (int row = 0; row < rows; ++row) {
    const int bz = b_lo[2] + row / rows_y, by = b_lo[1] + row % rows_y;
    for (int bx = b_lo[0]; bx <= b_hi[0]; ++bx) {
      const int b3[3] = {bx, by, bz};
      int s0[3], s1[3];
      for (int a = 0; a < 3; ++a) {
        s0[a] = 8 * b3[a] > lo[a] ? 8 * b3[a] : lo[a];
        s1[a] = 8 * b3[a] + 8 < hi[a] ? 8 * b3[a] + 8 : hi[a];
      }
      float beta_max = 0.0f;
      for (int k = s0[2]; k <= s1[2]; ++k)
        for (int j = s0[1]; j <= s1[1]; ++j)
          for (int i = s0[0]; i <= s1[0]; ++i) {
            const float beta = sl__sample_total(r->fields + sl_volume_index(v, i, j, k) * nf, nf);
            if (beta > beta_max) beta_max = beta;
          }
      if (beta_max > 0.0f) {
        const size_t b = ((size_t)bz * r->bricks[1] + by) * r->bricks[0] + bx;
        r->empty_radius[b] = 0;
        r->brick_beta_max[b] = beta_max;
      }
    }
  }
  sl__brick_empty_radius(r->bricks, r->empty_radius);
  return SL_OK;
}

void sl__brick_empty_radius(const int n[3], unsigned char *radius)
{
  /* The chessboard distance is the path length in the lattice's 26-neighbour graph, so two
   * raster scans of the 3^3 mask with unit steps give it exactly (Rosenfeld & Pfaltz's chamfer
   * transform): forward, each brick from its 13 neighbours already visited; backward, from the
   * other 13. */
  const size_t count = (size_t)n[0] * n[1] * n[2];
  for (size_t i = 0; i < count; ++i)
    if (radius[i]) radius[i] = 255;
  for (int pass = 0; pass < 2; ++pass) {
    const int dir = pass == 0 ? 1 : -1;
    for (int zz = 0; zz < n[2]; ++zz)
      for (int yy = 0; yy < n[1]; ++yy)
        for (int xx = 0; xx < n[0]; ++xx) {
          const int z = dir > 0 ? zz : n[2] - 1 - zz, y = dir > 0 ? yy : n[1] - 1 - yy, x = dir > 0 ? xx : n[0] - 1 - xx;
          unsigned char *here = radius + ((size_t)z * n[1] + y) * n[0] + x;
          if (!*here) continue;
          int best = *here;
          /* The neighbours before this brick in the scan's order: the scan's previous plane, the
           * previous row of this plane, the previous brick of this row. */
          for (int dz = -1; dz <= 0; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                const int nx = x + dir * dx, ny = y + dir * dy, nz = z + dir * dz;
                if (nx < 0 || ny < 0 || nz < 0 || nx >= n[0] || ny >= n[1] || nz >= n[2]) continue;
                const int v = radius[((size_t)nz * n[1] + ny) * n[0] + nx] + 1;
                if (v < best) best = v;
              }
          *here = (unsigned char)(best < 255 ? best : 255);
        }
  }
}

/* Where the ray o + t d, from t0 on, first enters an occupied 8^3 brick before t1; INFINITY when
 * it crosses none. A walk through the brick lattice (after Amanatides & Woo) that leaves each
 * empty brick's whole empty cube at once (sl__brick_empty_radius): the rays past a cloud's edge
 * crossed 30-90 empty bricks one by one. Bricks are assigned as sl__sample_fields_n assigns a
 * point (its lattice cell, clamped into the grid, divided by 8), so every sample before the
 * returned point reads zero. */
static double first_occupied(const sl_renderer *r, const double o[3], const double d[3], double t0, double t1)
{
  const sl_grid_view *g = &r->lattice;
  int b[3], b_last[3], step[3];
  double u0[3], du[3], inv_du[3]; /* lattice coordinates at t0, their change per unit of t and its
                                     reciprocal (a division per axis and turn was a third of the walk) */
  const ptrdiff_t stride[3] = {1, r->bricks[0], (ptrdiff_t)r->bricks[0] * r->bricks[1]};
  for (int a = 0; a < 3; ++a) {
    u0[a] = (o[a] + t0 * d[a] - g->origin[a]) * g->inv_spacing[a];
    du[a] = d[a] * g->inv_spacing[a];
    inv_du[a] = du[a] != 0.0 ? 1.0 / du[a] : 0.0;
    b_last[a] = sl__last_brick(g, a);
    const double cell = u0[a] < 0.0 ? 0.0 : floor(u0[a]);
    b[a] = (int)sl__min(cell * 0.125, (double)b_last[a]);
    if (b[a] < 0) b[a] = 0;
    step[a] = du[a] > 0.0 ? 1 : du[a] < 0.0 ? -1 : 0;
  }
  double t = 0.0; /* from t0 to where the ray enters brick b */
  for (;;) {
    const int radius = r->empty_radius[b[2] * stride[2] + b[1] * stride[1] + b[0]];
    if (!radius) return t0 + t;
    /* Every brick within radius - 1 of b is empty: where the ray leaves that cube, through the
     * face of the first axis it reaches (a cube that reaches the lattice's side along an axis
     * does not end there: the ray leaves the box). Measured from t0, not accumulated. */
    int exit_axis = -1;
    double t_exit = INFINITY;
    for (int a = 0; a < 3; ++a) {
      if (!step[a]) continue;
      const int past = b[a] + step[a] * radius; /* the first brick beyond the cube */
      if (past < 0 || past > b_last[a]) continue;
      const double ta = (8.0 * (step[a] > 0 ? past : past + 1) - u0[a]) * inv_du[a];
      if (ta < t_exit) t_exit = ta, exit_axis = a;
    }
    if (exit_axis < 0 || !(t0 + t_exit < t1)) return INFINITY;
    /* Into the brick beyond that face: the exit axis steps past the cube; the others follow the
     * ray there, held inside the cube and never stepping back (rounding at an edge), so every
     * turn advances and the walk ends. */
    for (int a = 0; a < 3; ++a) {
      if (a == exit_axis) {
        b[a] += step[a] * radius;
      } else if (step[a]) {
        const int at = (int)floor((u0[a] + t_exit * du[a]) * 0.125);
        const int lo = step[a] > 0 ? b[a] : b[a] - (radius - 1) > 0 ? b[a] - (radius - 1) : 0;
        const int hi = step[a] < 0 ? b[a] : b[a] + (radius - 1) < b_last[a] ? b[a] + (radius - 1) : b_last[a];
        b[a] = at < lo ? lo : at > hi ? hi : at;
      }
    }
    if (t_exit > t) t = t_exit;
  }
}

/* Two walks that stop at the first occupied brick, one from each end (the second along -d),
 * instead of one through the whole stretch: a ray into a cloud meets occupied bricks soon from
 * both sides, and the empty ones between are not its business (in the 256^3 storm the whole
 * walks were about 6 % of the frame). */
void sl__occupied_span(const sl_renderer *r, const double o[3], const double d[3], double t0, double t1,
                       double *first, double *last)
{
  *first = first_occupied(r, o, d, t0, t1);
  *last = -INFINITY;
  if (*first == INFINITY) return;
  const double back[3] = {-d[0], -d[1], -d[2]};
  /* Back over the whole stretch, not only to *first: a walk that stopped at *first's brick face
   * could miss that brick by rounding; it cannot miss it here, and t1 stands in if it did. */
  const double from_end = first_occupied(r, o, back, -t1, -t0);
  *last = from_end < INFINITY ? -from_end : t1;
}

void sl__content_bounds(const sl_renderer *r, const int medium_lo[3], const int medium_hi[3], double lo[3],
                        double hi[3])
{
  const sl_volume *v = &r->shape;
  if (medium_hi[0] < 0) {
    memcpy(lo, r->lo, sizeof r->lo);
    memcpy(hi, r->hi, sizeof r->hi);
    return;
  }
  for (int a = 0; a < 3; ++a) {
    lo[a] = fmax(r->lo[a], v->origin[a] + (medium_lo[a] - 1) * v->spacing[a]);
    hi[a] = fmin(r->hi[a], v->origin[a] + (medium_hi[a] + 1) * v->spacing[a]);
  }
}

void sl_renderer_content_bounds(const sl_renderer *r, double lo[3], double hi[3])
{
  memcpy(lo, r->clo, sizeof r->clo);
  memcpy(hi, r->chi, sizeof r->chi);
}

int sl__clear_blocks_build(sl_renderer *r, sl_error *err)
{
  /* A block of 2^3 lattice cells holds medium where any of its cells has a non-zero corner: a
   * non-zero sample marks the blocks of the (up to 8) cells around it. Then each block's
   * Chebyshev distance to the nearest such block, as the bricks' (sl__brick_empty_radius). */
  const sl_volume *v = &r->shape;
  const int nf = r->model.nf > 0 ? r->model.nf : 1;
  const int n[3] = {v->nx, v->ny, v->nz};
  int cells[3];
  for (int a = 0; a < 3; ++a) {
    cells[a] = n[a] > 1 ? n[a] - 1 : 1;
    r->clear_blocks_n[a] = (cells[a] + 1) / 2;
  }
  const size_t blocks = (size_t)r->clear_blocks_n[0] * r->clear_blocks_n[1] * r->clear_blocks_n[2];
  unsigned char *map = malloc(blocks);
  if (!map) return sl_fail(err, SL_ERR_NOMEM, "renderer: out of memory");
  memset(map, 1, blocks);
  int lo[3], hi[3];
  if (sl_volume_content_samples(v, lo, hi)) {
    const long rows = sl_volume_box_rows(lo, hi);
    for (long row = 0; row < rows; ++row) {
      const size_t first = sl_volume_box_row(v, lo, hi, row);
      const int j = lo[1] + (int)(row % (hi[1] - lo[1] + 1)), k = lo[2] + (int)(row / (hi[1] - lo[1] + 1));
      for (int i = lo[0]; i <= hi[0]; ++i) {
        if (!(sl__sample_total(r->fields + (first + (size_t)(i - lo[0])) * nf, nf) > 0.0f)) continue;
        const int s[3] = {i, j, k};
        int b_lo[3], b_hi[3]; /* the blocks of cells s - 1 and s, inside the lattice */
        for (int a = 0; a < 3; ++a) {
          const int c_lo = s[a] - 1 > 0 ? s[a] - 1 : 0, c_hi = s[a] < cells[a] - 1 ? s[a] : cells[a] - 1;
          b_lo[a] = c_lo / 2, b_hi[a] = c_hi / 2;
        }
        for (int bz = b_lo[2]; bz <= b_hi[2]; ++bz)
          for (int by = b_lo[1]; by <= b_hi[1]; ++by)
            for (int bx = b_lo[0]; bx <= b_hi[0]; ++bx)
              map[((size_t)bz * r->clear_blocks_n[1] + by) * r->clear_blocks_n[0] + bx] = 0;
      }
    }
  }
  sl__brick_empty_radius(r->clear_blocks_n, map);
  r->clear_blocks = map;
  return SL_OK;
}
