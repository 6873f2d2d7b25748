/* Half-angle slicing on the CPU. Per slice, the eye pass gathers light scattered toward the
 * camera from the slice, reading the light buffer (transparency from the sun to the slice),
 * then the light pass attenuates the light buffer through the slice. Every pixel and texel is
 * independent within a pass, so the image does not depend on the number of threads. */
#include "sl_renderer.h"

#include "lighting.h"
#include "renderer_internal.h"
#include "sl_cie.h"
#include "sl_sample_physics.h"
#include "vector_math.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif
#include <string.h>





/* The altitudes the box [lo, hi] spans: its bottom and top on the flat ground; on the sphere,
 * from the bottom point nearest the sphere's centre's vertical to the top corner farthest out. */
static void box_altitudes(const sl_atmosphere *atm, const double lo[3], const double hi[3], double *hlo, double *hhi)
{
  if (!atm || !(atm->ground_radius > 0.0)) {
    *hlo = lo[2], *hhi = hi[2];
    return;
  }
  double near[3], far[3];
  for (int a = 0; a < 2; ++a) {
    near[a] = lo[a] > 0.0 ? lo[a] : hi[a] < 0.0 ? hi[a] : 0.0;
    far[a] = fabs(lo[a]) > fabs(hi[a]) ? lo[a] : hi[a];
  }
  near[2] = lo[2], far[2] = hi[2];
  *hlo = sl_sky_altitude(atm, near, NULL);
  *hhi = sl_sky_altitude(atm, far, NULL);
}

void sl__sun_table_init(sun_table *t, const sl_scene *sc, const sl_sky_view *view, const double lo[3],
                        const double hi[3])
{
  t->nwl = sc->atmosphere ? sc->atmosphere->count : SL_CHANNELS;
  t->atm = sc->atmosphere;
  double hlo, hhi;
  box_altitudes(sc->atmosphere, lo, hi, &hlo, &hhi);
  t->z0 = hlo;
  t->dz = (hhi - hlo) / (SUN_TABLE_SIZE - 1);
  for (int i = 0; i < SUN_TABLE_SIZE; ++i)
    for (int c = 0; c < t->nwl; ++c) {
      if (!sc->atmosphere) {
        t->rgb[i][c] = sc->sun_irradiance[c];
        continue;
      }
      const sl_atmosphere *atm = sc->atmosphere;
      const double z = hlo + i * t->dz;
      t->rgb[i][c] = view->night ? 0.0
                                 : atm->sun_irradiance[c] *
                                       exp(-sl_sky_sun_optical_depth(atm->beta_sea_level[c], 1.0 / atm->scale_height,
                                                                     z, view->airmass));
    }
}

int sl_total_extinction(const sl_volume *v, float *beta_out, sl_error *err)
{
  const size_t n = sl_volume_count(v);
  memset(beta_out, 0, n * sizeof(float));
  for (int k = 0; k < SL_VOLUME_SLOTS; ++k) {
    if (!v->eta[k]) continue;
    const sl_particle p = sl_volume_field_type(v, k);
    const double sigma = sl_particle_properties(p)->sigma_ext_m2;
    for (size_t i = 0; i < n; ++i) {
      const float eta = v->eta[k][i];
      if (!(eta >= 0.0f) || !isfinite(eta))
        return sl_fail(err, SL_ERR_DATA, "%s concentration is negative or not finite at sample %zu",
                       sl_particle_name(p), i);
      beta_out[i] += (float)(eta * sigma); /* Riley et al. 2004, eqs. 2-3 */
    }
  }
  return SL_OK;
}

int sl_slices_resolving_grid(const sl_volume *v, const double h[3], const double view_dir[3],
                             const double light_dir[3], double depth)
{
  /* A ray r crosses consecutive planes ds / |h.r| apart, a step of ds |r_a| / |h.r| along axis a:
   * one sample per grid cell along every axis, for the eye's central ray and for the light,
   * needs ds <= spacing_a |h.r| / |r_a|. */
  double ds = INFINITY;
  const double *rays[2] = {view_dir, light_dir};
  for (int k = 0; k < 2; ++k) {
    const double hr = fabs(sl_dot3(h, rays[k]));
    if (hr < 1e-6) continue;
    for (int a = 0; a < 3; ++a)
      if (fabs(rays[k][a]) > 1e-12) ds = fmin(ds, v->spacing[a] * hr / fabs(rays[k][a]));
  }
  const double n = ceil(depth / ds);
  return n < 256 ? 256 : n > 4096 ? 4096 : (int)n;
}

void sl_choose_slicing(const double view_dir[3], const double sun_dir[3], sl_slicing *out)
{
  const double p[3] = {-sun_dir[0], -sun_dir[1], -sun_dir[2]}; /* light propagation */
  const double vp = sl_dot3(view_dir, p);
  const double sign = vp >= 0.0 ? 1.0 : -1.0;
  double h[3] = {sign * view_dir[0] + p[0], sign * view_dir[1] + p[1], sign * view_dir[2] + p[2]};
  sl_normalize3(h);
  memcpy(out->half_vector, h, sizeof h);
  out->back_to_front = sign < 0.0;
  double c = sl_dot3(view_dir, sun_dir);
  c = c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c;
  out->eye_sun_angle_deg = acos(c) * 180.0 / M_PI;
}

sl_renderer *sl_renderer_create(const sl_scene *scene, sl_error *err)
{
  if (!scene || !scene->volume) {
    sl_fail(err, SL_ERR_ARG, "renderer: no volume");
    return NULL;
  }
  double sun[3] = {scene->sun_direction[0], scene->sun_direction[1], scene->sun_direction[2]};
  if (sl_normalize3(sun)) {
    sl_fail(err, SL_ERR_ARG, "renderer: the sun direction is not a finite non-zero vector");
    return NULL;
  }
  if (scene->slices < 0 || scene->slices > 16384) {
    sl_fail(err, SL_ERR_ARG, "renderer: %d slices is out of range (1..16384)", scene->slices);
    return NULL;
  }
  if (scene->march_samples < 0 || scene->march_samples > 8) {
    sl_fail(err, SL_ERR_ARG, "renderer: %d march samples per grid cell is out of range (1..8)", scene->march_samples);
    return NULL;
  }
  if (scene->light_resolution < 0 || scene->light_resolution > 8192) {
    sl_fail(err, SL_ERR_ARG, "renderer: light-buffer resolution %d is out of range (1..8192)",
            scene->light_resolution);
    return NULL;
  }
  sl_renderer *r = calloc(1, sizeof *r);
  if (!r) {
    sl_fail(err, SL_ERR_NOMEM, "renderer: out of memory");
    return NULL;
  }
  r->scene = *scene;
  memcpy(r->scene.sun_direction, sun, sizeof sun);
  r->shape = *scene->volume;
  memset(r->shape.eta, 0, sizeof r->shape.eta);
  r->beta = malloc(sl_volume_count(scene->volume) * sizeof(float));
  if (!r->beta) {
    sl_fail(err, SL_ERR_NOMEM, "renderer: out of memory for the extinction grid");
    free(r);
    return NULL;
  }
  sl_grid_view_init(&r->beta_view, r->beta, &r->shape);
  sl_volume_bounds(&r->shape, r->lo, r->hi);
  if (sl_light_model_init(&r->model, scene, err)) {
    sl_renderer_destroy(r);
    return NULL;
  }
  r->has_subsets = r->model.mode == SL_LIGHTING_MULTIPLE && r->model.nf > 1;
  if (r->has_subsets)
    for (unsigned mask = 1; mask < 1u << r->model.nf; ++mask)
      sl_light_model_subset(&r->model, mask, &r->field_subsets[mask]);
  if (!scene->atmosphere && r->model.nwl != SL_CHANNELS) {
    sl_fail(err, SL_ERR_ARG, "renderer: without an atmosphere the renderer works in its three channels");
    sl_renderer_destroy(r);
    return NULL;
  }
  /* Three wavelengths are the paper's red, green and blue channels as they are; any other set is
   * spectral radiance, converted to linear sRGB through the CIE 1931 observer. */
  r->spectral = r->model.nwl != SL_CHANNELS;
  memset(r->to_rgb, 0, sizeof r->to_rgb);
  if (r->spectral) {
    if (sl_cie_srgb_weights(scene->atmosphere->wavelength_nm, r->model.nwl, 1, r->to_rgb, err)) {
      sl_renderer_destroy(r);
      return NULL;
    }
  } else {
    for (int c = 0; c < SL_CHANNELS; ++c) r->to_rgb[c * SL_CHANNELS + c] = 1.0;
  }
  /* Extinction per field from the tables' cross-sections (eq. 2), interleaved so one trilinear
   * look-up serves every field; the total (eq. 3) for bounds and emptiness. */
  const size_t count = sl_volume_count(scene->volume);
  const int nf = r->model.nf;
  const size_t field_bytes = ((nf > 0 ? nf : 1) * count + SL__FIELD_LANES) * sizeof(float); /* sl__field_fetch's last load */
  r->fields = sl__huge_alloc(field_bytes);
  if (!r->fields) {
    sl_fail(err, SL_ERR_NOMEM, "renderer: out of memory for the extinction grids");
    sl_renderer_destroy(r);
    return NULL;
  }
  /* The loop below writes every field of every sample; zeroed here only the padding (and the
   * whole array without fields), not 268 MB at 256^3 that the loop then overwrites. */
  memset(r->fields + (size_t)nf * count, 0, field_bytes - (size_t)nf * count * sizeof(float));
  for (size_t i = 0; i < count; ++i) {
    double total = 0.0;
    for (int j = 0; j < nf; ++j) {
      const float eta = scene->volume->eta[r->model.slot[j]][i];
      if (!(eta >= 0.0f) || !isfinite(eta)) {
        sl_fail(err, SL_ERR_DATA, "%s concentration is negative or not finite at sample %zu",
                sl_particle_name(r->model.field[j]), i);
        sl_renderer_destroy(r);
        return NULL;
      }
      const double b = eta * r->model.sigma_ext[j];
      r->fields[i * nf + j] = (float)b;
      total += b;
    }
    r->beta[i] = (float)total;
    if (total > r->beta_max) r->beta_max = total;
    if (total > 0.0) r->any_extinction = 1;
  }
  /* Brick occupancy for empty-space skipping inside the content box, then each empty brick's
   * distance to the nearest occupied one. */
  {
    const sl_volume *v = &r->shape;
    const int n[3] = {v->nx, v->ny, v->nz};
    for (int a = 0; a < 3; ++a) r->bricks[a] = (n[a] + 7) / 8;
    const size_t bricks = (size_t)r->bricks[0] * r->bricks[1] * r->bricks[2];
    r->empty_radius = malloc(bricks);
    if (!r->empty_radius) {
      sl_fail(err, SL_ERR_NOMEM, "renderer: out of memory");
      sl_renderer_destroy(r);
      return NULL;
    }
    memset(r->empty_radius, 1, bricks);
    for (int k = 0; k < v->nz; ++k)
      for (int j = 0; j < v->ny; ++j)
        for (int i = 0; i < v->nx; ++i) {
          if (!(r->beta[sl_volume_index(v, i, j, k)] > 0.0f)) continue;
          /* A sample feeds the trilinear cells whose lower corner is itself or one below it. */
          for (int dk = -1; dk <= 0; ++dk)
            for (int dj = -1; dj <= 0; ++dj)
              for (int di = -1; di <= 0; ++di) {
                const int ii = i + di, jj = j + dj, kk = k + dk;
                if (ii < 0 || jj < 0 || kk < 0) continue;
                r->empty_radius[((size_t)(kk / 8) * r->bricks[1] + jj / 8) * r->bricks[0] + ii / 8] = 0;
              }
        }
    sl__brick_empty_radius(r->bricks, r->empty_radius);
  }
  sl_renderer_content_bounds(r, r->clo, r->chi);
  for (int a = 0; a < 3; ++a) r->content_center[a] = 0.5 * (r->clo[a] + r->chi[a]);
  return r;
}

void sl_renderer_destroy(sl_renderer *r)
{
  if (!r) return;
  sl_light_model_free(&r->model);
  free(r->beta);
  free(r->fields); /* sl__huge_alloc's memory is posix_memalign's: free releases it */
  free(r->light_volume);
  free(r->empty_radius);
  free(r->texel_spans.u_in), free(r->texel_spans.u_out), free(r->texel_spans.first), free(r->texel_spans.last);
  free(r->texel_spans.u_entry);
  free(r);
}

int sl_renderer_set_sun(sl_renderer *r, const double sun_direction[3], sl_error *err)
{
  double sun[3] = {sun_direction[0], sun_direction[1], sun_direction[2]};
  if (sl_normalize3(sun)) return sl_fail(err, SL_ERR_ARG, "renderer: the sun direction is not a finite non-zero vector");
  memcpy(r->scene.sun_direction, sun, sizeof sun);
  /* The cached light volume was lit by the old sun; the next frame that needs it rebuilds it. */
  free(r->light_volume);
  r->light_volume = NULL;
  return SL_OK;
}

int sl_renderer_set_march_samples(sl_renderer *r, int samples, sl_error *err)
{
  if (samples < 0 || samples > 8)
    return sl_fail(err, SL_ERR_ARG, "renderer: %d march samples per grid cell is out of range (1..8)", samples);
  r->scene.march_samples = samples;
  return SL_OK;
}

void sl_renderer_set_xi(sl_renderer *r, double xi)
{
  r->scene.xi = xi;
  r->model.xi = xi;
  for (int mask = 0; mask < 1 << SL_MAX_FIELDS; ++mask) r->field_subsets[mask].xi = xi;
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
  const sl_grid_view *g = &r->beta_view;
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

void sl__resolve_pixel(const sl_renderer *r, const sl_sky_view *view, const double d[3], double t_mid,
                       const float *a, sl_image *img, size_t q)
{
  const int nwl = r->model.nwl;
  const float transparency = a[nwl];
  double front[SL_MAX_WAVELENGTHS] = {0}, front_t[SL_MAX_WAVELENGTHS], spectrum[SL_MAX_WAVELENGTHS];
  for (int c = 0; c < nwl; ++c) front_t[c] = 1.0;
  if (view && transparency < 1.0f) sl_sky_view_segment(view, d, 0.0, t_mid, front, front_t);
  for (int c = 0; c < nwl; ++c) spectrum[c] = front_t[c] * a[c] + (1.0 - transparency) * front[c];
  double rgb[3];
  sl_cie_apply(r->to_rgb, nwl, spectrum, rgb);
  for (int c = 0; c < SL_CHANNELS; ++c) img->rgba[4 * q + c] = (float)rgb[c];
  img->rgba[4 * q + 3] = 1.0f - transparency;
  img->transparency[q] = transparency;
  const double coverage = 1.0 - transparency;
  img->depth[q] = coverage > 1e-4 ? (float)(a[nwl + 1] / coverage) : INFINITY;
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

/* Square tiles of a w x h lattice (image pixels or light texels), each with the range of slices in
 * which any of its elements is active: a pass over one slice visits only the tiles whose range
 * holds it, instead of testing every element of the lattice against its own range per slice
 * (256 slices x 512^2 pixels is 67M tests, most failing, for ~8M samples). */
#define TILE 16
#define RAY_STRIDE 7
typedef struct tile_ranges {
  int nx, ny;
  int *k;      /* per tile: first and last active slice (first > last: never active) */
  int *active; /* per thread, room for a list of every tile (tiles_active) */
  int *work;   /* two per tile: its cost in a slice it had work (tile_cost; tiles_share): slice k's
                  cuts read row k % 2 while its tiles write row (k + 1) % 2, so that no thread's
                  cut sees another's writes of the same slice */
} tile_ranges;

static int tiles_init(tile_ranges *t, int w, int h, int threads)
{
  t->nx = (w + TILE - 1) / TILE, t->ny = (h + TILE - 1) / TILE;
  t->k = malloc((size_t)t->nx * t->ny * 2 * sizeof(int));
  t->active = malloc((size_t)t->nx * t->ny * threads * sizeof(int));
  t->work = malloc((size_t)t->nx * t->ny * 2 * sizeof(int));
  return t->k != NULL && t->active != NULL && t->work != NULL;
}

static void tiles_free(tile_ranges *t) { free(t->k), free(t->active), free(t->work); }

/* The tiles whose range holds slice k, in order, in the calling thread's own list (returned).
 * Every thread builds the same list (no barrier), and shares it out with tiles_share. */
static inline int *tiles_active(const tile_ranges *t, int k, int *count)
{
  const size_t n = (size_t)t->nx * t->ny;
  int *list = t->active + (size_t)omp_get_thread_num() * n, c = 0;
  for (size_t i = 0; i < n; ++i) {
    list[c] = (int)i;
    c += k >= t->k[2 * i] && k <= __atomic_load_n(&t->k[2 * i + 1], __ATOMIC_RELAXED);
  }
  *count = c;
  return list;
}

/* A tile's cost as its share weight: the time it took (the cycle counter, a few cycles to read),
 * so that the cuts follow what the tiles really cost, parts, fields and all; its sample count
 * where there is no cycle counter. */
static inline unsigned long long tile_clock(void)
{
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#else
  return 0;
#endif
}

static inline int tile_cost(unsigned long long start, int samples)
{
#if defined(__x86_64__) || defined(__i386__)
  (void)samples;
  const unsigned long long cycles = (__rdtsc() - start) >> 6;
  return cycles < (1u << 24) ? (int)cycles + 1 : 1 << 24;
#else
  (void)start;
  return samples + 1;
#endif
}

/* The calling thread's part [*first, *end) of a slice's active tiles: a contiguous run of the
 * list, the runs cut where the tiles' work in their last slice adds up to equal shares. Contiguous
 * runs keep a thread on the same part of the image (or light buffer) from slice to slice, its
 * pixels and texels in its own core's caches: with a dynamic schedule, tiles went to whichever
 * thread asked, and the two threads did a fifth more work than one (docs/PERFORMANCE.md, session
 * 14). Every thread computes every cut from the same list and counts, so the runs tile the list. */
static inline void tiles_share(const tile_ranges *t, int k, const int *list, int count, int *first, int *end)
{
  const int threads = omp_get_num_threads(), me = omp_get_thread_num();
  *first = 0, *end = count;
  if (threads == 1) return;
  const int *work = t->work + (size_t)(k & 1) * t->nx * t->ny;
  long total = 0;
  for (int i = 0; i < count; ++i) total += work[list[i]];
  /* Tile i goes to the thread whose share holds the middle of its work. */
  long before = 0;
  *first = *end = count;
  for (int i = 0; i < count; ++i) {
    const long w = work[list[i]];
    const int owner = (int)((2 * before + w) * threads / (2 * total + 1));
    before += w;
    if (owner == me && *first == count) *first = i;
    if (owner > me) {
      *end = i;
      break;
    }
  }
  if (*first > *end) *first = *end;
}

/* Tile i's range from its elements' ranges (k_lo[e], k_hi[e] of element e = y * w + x). */
static void tile_range_from(tile_ranges *t, size_t i, int w, int h, const int *k_lo, const int *k_hi, size_t stride)
{
  const int tx = (int)(i % t->nx), ty = (int)(i / t->nx);
  int lo = 1 << 30, hi = -(1 << 30);
  for (int y = ty * TILE; y < (ty + 1) * TILE && y < h; ++y)
    for (int x = tx * TILE; x < (tx + 1) * TILE && x < w; ++x) {
      const size_t e = (size_t)y * w + x;
      if (k_lo[e * stride] > k_hi[e * stride]) continue;
      if (k_lo[e * stride] < lo) lo = k_lo[e * stride];
      if (k_hi[e * stride] > hi) hi = k_hi[e * stride];
    }
  t->k[2 * i] = lo, t->k[2 * i + 1] = hi;
  t->work[i] = t->work[(size_t)t->nx * t->ny + i] = 1; /* until the tile has run: its cost is unknown */
}

/* The light-buffer texel along the unit axis u (perpendicular to the sunlight) over a box extent
 * long, given the pixel's size (metres) at the content and the largest extinction: as long as the
 * pixel or the shortest mean free path, whichever is longer, but no longer than the step that
 * moves one spacing along some grid axis (u's largest component in cells); axes of one sample do
 * not count. Then within 128..limit texels over the extent (and at most 2048). Not bounded below
 * by the grid's resolution: in optically thick cells the light falls off within a cell, and where
 * a cloud's surface is oblique to the sun neighbouring texels see that fall-off at different
 * depths (the glory scene's deck, seen from 6 km: 4.4 % relative RMSE at 128 texels against 1024,
 * 0.5 % at 512; its 256 slices' own error is 1.2 %). Where every cell is optically thin the light
 * changes little across one, and a texel of a cell serves (the halo's cirrus). */
static double light_texel_resolving(const sl_volume *shape, const double u[3], double extent, double pixel,
                                    double beta_max, int limit)
{
  const int n[3] = {shape->nx, shape->ny, shape->nz};
  const double free_path = beta_max > 0.0 ? 1.0 / beta_max : INFINITY;
  double texel = fmax(pixel > 0.0 ? pixel : 0.0, free_path);
  for (int a = 0; a < 3; ++a)
    if (n[a] > 1 && fabs(u[a]) > 1e-12) texel = fmin(texel, shape->spacing[a] / fabs(u[a]));
  double count = isfinite(texel) && texel > 0.0 ? ceil(extent / texel - 1e-9) : 128.0;
  if (limit > 2048) limit = 2048;
  count = count < 128.0 ? 128.0 : count > limit ? limit : count;
  return extent > 0.0 ? extent / count : 1.0;
}

/* One row of a tile in one slice, its samples found in two steps: first every lane's segment and
 * lattice cell in a loop without branches (vector code: row_lattice_set per lane), then per lane
 * that holds a sample its brick flag, cell and prefetch (row_cells). Found one at a time, the
 * light pass's cells were a fifth of its time. The light pass's lanes are a row's texels; the
 * eye pass's only the pixels whose span holds the slice (most of a row's do not, and all sixteen
 * as lanes made it 5-10 % slower; PERFORMANCE.md, session 10). */
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
 * lane in lanes[], in order. Returns how many did. */
static inline __attribute__((always_inline)) int row_cells(const sl_renderer *r, const int nf, const row_lattice *rl,
                                                           int n, long *samples, int *lanes, sl__field_cell *cells)
{
  int cnt = 0;
  for (int i = 0; i < n; ++i) {
    if (!rl->take[i]) continue;
    ++*samples;
    const int cell[3] = {rl->i0[0][i], rl->i0[1][i], rl->i0[2][i]};
    const double frac[3] = {rl->f[0][i], rl->f[1][i], rl->f[2][i]};
    if (!rl->inside[i] || !sl__field_cell_of(r, nf, cell, frac, 1, &cells[cnt])) continue;
    lanes[cnt++] = i;
  }
  return cnt;
}

/* Bilinear look-up of the light buffer's state (ln I per wavelength and n) at a point's projection,
 * in two steps for the eye pass's loops over a batch of samples: first per sample its texel and
 * weights (light_texel_lane, no branch: the buffer's one-texel axes are selections, so the batch
 * loop around it vectorises), then per channel the lerps (light_bilinear_lane; GCC 12 leaves that
 * loop scalar: "no vectype" for its float gathers by 64-bit index). */
static inline __attribute__((always_inline)) void light_texel_lane(const light_buffer *L, const double x[3],
                                                                   ptrdiff_t *texel, double *u, double *v)
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
  *texel = ((ptrdiff_t)j * L->w + i) * L->stride;
}

/* The offsets of a texel's neighbours along a and b (di, dj), 0 along an axis of one texel. */
static inline void light_texel_steps(const light_buffer *L, ptrdiff_t *di, ptrdiff_t *dj)
{
  *di = L->w > 1 ? L->stride : 0;
  *dj = L->h > 1 ? (ptrdiff_t)L->w * L->stride : 0;
}

static inline __attribute__((always_inline)) double light_bilinear_lane(const float *st, ptrdiff_t di, ptrdiff_t dj,
                                                                        ptrdiff_t t, double u, double v)
{
  const double r0 = st[t] + u * (st[t + di] - st[t]);
  const double r1 = st[t + dj] + u * (st[t + dj + di] - st[t + dj]);
  return r0 + v * (r1 - r0);
}

/* The sun's elevation (degrees) below which the slicer places the light's kink at surfaces
 * (light_kink): flat tops under a low sun are where texel rows meet a surface kilometres apart. */
#define KINK_SUN_ELEVATION 15.0
/* Texel widths that a cell's entries must spread over along the rays for light_kink. */
#define KINK_SPREAD 4.0
/* The least difference in ln I or n between a cell's texels for light_kink. */
#define KINK_MIN_FALL 0.25f

/* The light at a cloud's surface between light texels. Where a flat top meets the sunlight at a
 * grazing angle, one texel row's ray runs just above the top (ln I = 0) while the next entered it
 * kilometres upwind and has lost tens of optical depths; ln I interpolated between them put the
 * surface's light anywhere between the two, one stripe per row (Katrina's lid at dawn,
 * DESIGN-NOTES.md), and the light of a top whose density ramps up over one grid level is decided
 * within the first texel row's spacing. Each texel knows where its ray entered the medium
 * (texel_entry) and the state there; the distance e its ray has run inside since is linear across
 * texels under a planar surface, so its bilinear interpolation e* is exact where that of ln I is
 * not. Where a cell's texels straddle the entry (some e > 0, some e <= 0), or have all entered but
 * the nearest less than the cell's spread of entries ago (past a ramped top ln I is not yet linear
 * in e there), the point's light is rebuilt from its own entry: the texels' states at entry
 * interpolated (the ones not yet in give their current state, which has not changed since the
 * sunlight came in), and when e* > 0 the light steps (eq. 24, eq. 21) along the last e* of its ray
 * to the plane, sampled every half grid cell at their middles (exact for extinction linear along
 * the ray, as a top's ramp between two levels is). A texel whose ray never enters is left out of
 * the interpolations. Only in cells marked grazing (slicer_passes), under a low sun.
 * Replaces value[c], c <= nwl, the bilinear state at (u, v) in the cell whose first texel's state
 * is at t, for the point p on the slice plane where a ray has run e_plane - g; returns 0 (value
 * untouched) where none of its texels has entered. */
static inline __attribute__((always_inline)) int light_kink(const sl_renderer *r, const int nf, const int nwl,
                                                            const light_buffer *L, ptrdiff_t di, ptrdiff_t dj,
                                                            ptrdiff_t t, double u, double v, double e_plane,
                                                            const double p[3], const double prop[3], double step,
                                                            double *value)
{
  const int stride = nwl + 1;
  const ptrdiff_t off[4] = {t, t + di, t + dj, t + di + dj};
  const double w[4] = {(1.0 - u) * (1.0 - v), u * (1.0 - v), (1.0 - u) * v, u * v};
  double e[4], inside = 0.0, outside = 0.0, known = 0.0;
  for (int k = 0; k < 4; ++k) {
    e[k] = e_plane - L->entry_g[off[k] / stride];
    if (e[k] > 0.0) inside += w[k] * e[k];
    else if (e[k] <= 0.0) outside += w[k] * e[k];
    known += e[k] == e[k] ? w[k] : 0.0;
  }
  if (!(inside > 0.0)) return 0;
  /* Where ln I and n differ little between the texels, their interpolation cannot be far off (at
   * most that difference, at a kink) and is kept: an optically thin medium's. */
  float lo = INFINITY, hi = -INFINITY, n_lo = INFINITY, n_hi = -INFINITY;
  for (int k = 0; k < 4; ++k)
    if (e[k] == e[k]) {
      lo = fminf(lo, L->state[off[k]]), hi = fmaxf(hi, L->state[off[k]]);
      n_lo = fminf(n_lo, L->state[off[k] + nwl]), n_hi = fmaxf(n_hi, L->state[off[k] + nwl]);
    }
  if (!(hi - lo > KINK_MIN_FALL || n_hi - n_lo > KINK_MIN_FALL)) return 0;
  /* The weights over the texels whose rays enter: one that never does (it passes above a top or
   * beside a wall) says nothing of where a point with medium in the cell entered. */
  const double renorm = 1.0 / known;
  inside *= renorm, outside *= renorm;
  float state[SL_MAX_WAVELENGTHS + 1];
  for (int c = 0; c < stride; ++c) {
    double at_entry = 0.0;
    for (int k = 0; k < 4; ++k) {
      if (e[k] != e[k]) continue;
      /* A texel past its entry whose step there was not taken (no medium at its middle) has kept
       * no entry state: its state is still the one at entry. */
      const int kept = e[k] > 0.0 && L->entry_state[off[k] + stride - 1] >= 0.0f;
      at_entry += w[k] * (kept ? L->entry_state[off[k] + c] : L->state[off[k] + c]);
    }
    state[c] = (float)(at_entry * renorm);
  }
  const double e_star = inside + outside;
  if (e_star > 0.0) {
    const double parts = ceil(e_star / step);
    const int n = parts < 1.0 ? 1 : parts > 16.0 ? 16 : (int)parts;
    const double len = e_star / n;
    const sl_light_model *m = &r->model;
    for (int i = 0; i < n; ++i) {
      const double back = e_star - (i + 0.5) * len;
      const double x[3] = {p[0] - back * prop[0], p[1] - back * prop[1], p[2] - back * prop[2]};
      float bj[SL_MAX_FIELDS];
      if (!sl__sample_fields_n(r, nf, x, bj)) continue;
#define KINK_STEP(model, mode, count) sl_log_light_step_at(model, mode, count, nwl, bj, len, state, 0)
      SL_WITH_BATCH_MODEL(m, m, nf, nf, KINK_STEP);
#undef KINK_STEP
      /* Past e^-80 in every wavelength no light is left to shape (the n of no light is moot). */
      int lit = 0;
      for (int c = 0; c < nwl; ++c) lit |= state[c] > -80.0f;
      if (!lit) break;
    }
  }
  for (int c = 0; c < stride; ++c) value[c] = state[c];
  return 1;
}

/* The total extinction at o + u d (the renderer's total-extinction grid). */
static double ray_extinction(const sl_renderer *r, const double o[3], const double d[3], double u)
{
  const double x[3] = {o[0] + u * d[0], o[1] + u * d[1], o[2] + u * d[2]};
  return sl_grid_sample(&r->beta_view, x);
}

/* Where a light texel's ray o + u prop enters the medium: where its optical depth from `first`
 * (its first occupied brick; every sample before is zero) reaches SL__ENTRY_DEPTH; NaN when it
 * does not by `last`. Trapezoids one grid cell long, then the step that crosses in sixteen, then
 * within that sixteenth the extinction taken linear: a sixteenth of a cell is where a flat top
 * under a grazing sun is placed (Katrina's lid: 190 m along the ray, 14 m in height, against
 * texel rows 2.9 km apart along it). */
static double texel_entry(const sl_renderer *r, const double o[3], const double prop[3], double first, double last,
                          double step)
{
  double u = first, tau = 0.0;
  double beta_u = ray_extinction(r, o, prop, u);
  while (u < last) {
    const double u_next = u + step < last ? u + step : last;
    const double beta_next = ray_extinction(r, o, prop, u_next);
    const double dtau = 0.5 * (beta_u + beta_next) * (u_next - u);
    if (tau + dtau >= SL__ENTRY_DEPTH) {
      const double h = (u_next - u) / 16.0;
      double a = u, beta_a = beta_u;
      for (int i = 1; i <= 16; ++i) {
        const double b = i == 16 ? u_next : u + i * h;
        double beta_b = beta_next;
        if (i < 16) beta_b = ray_extinction(r, o, prop, b);
        const double d = 0.5 * (beta_a + beta_b) * (b - a);
        if (tau + d >= SL__ENTRY_DEPTH || i == 16) {
          /* tau + beta_a s + (beta_b - beta_a) s^2 / (2 (b - a)) = SL__ENTRY_DEPTH, the root in
           * [0, b - a] in the form without cancellation. */
          const double need = SL__ENTRY_DEPTH - tau, q = (beta_b - beta_a) / (2.0 * (b - a));
          const double disc = beta_a * beta_a + 4.0 * q * need;
          const double den = beta_a + sqrt(disc > 0.0 ? disc : 0.0);
          double s = den > 0.0 ? 2.0 * need / den : b - a;
          s = s < 0.0 ? 0.0 : s > b - a ? b - a : s;
          return a + s;
        }
        tau += d, a = b, beta_a = beta_b;
      }
    }
    tau += dtau, u = u_next, beta_u = beta_next;
  }
  return NAN;
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

/* Samples of a tile in a slice whose exponentials the eye pass takes at once: a multiple of the
 * vector width, and few enough that the batch's arrays stay in the L1 cache at 16 wavelengths (at
 * a whole tile, 256, the 16-wavelength eye pass ran 1.4x slower than before batching). */
#define EYE_BATCH 32

/* The parts an eye sample's segment is taken in, each with the fields at its own middle: one
 * where the segment is optically thin, up to EYE_PARTS_MAX where it is thick (one per unit of
 * optical depth at the segment's middle). A thick segment's light comes from its first mean
 * free path, and one extinction for the whole segment puts that at the slab's front plane
 * wherever the cloud's surface lies within the slab. Against 2048 slices this halves the error
 * of several bundled scenes at their default slices for a few per cent of the eye pass
 * (docs/ACCURACY.md, "Slices"). */
#define EYE_PART_DEPTH 1.0
#define EYE_PARTS_MAX 4
static inline int eye_parts(double depth)
{
  const double parts = ceil(depth * (1.0 / EYE_PART_DEPTH));
  return parts <= 1.0 ? 1 : parts >= EYE_PARTS_MAX ? EYE_PARTS_MAX : (int)parts;
}

/* The table look-ups of a batch of eye samples, in one loop over the samples that vectorises
 * (gathers), as the light pass's steps do: per sample the exponents of eq. 24's fraction over its
 * probe path, the expected scattering count at its middle (eq. 21) and eq. 26's angular term there,
 * times the sunlight over the extinction (sun_per_beta) as the segment gather's source. The
 * samples are independent (ivdep). */
static inline __attribute__((always_inline)) void eye_batch_phases(
    const sl_light_model *restrict m, const int mode, const int nf, const int nwl, const int live,
    float (*restrict fields)[SL_MAX_FIELDS], const double *restrict n, const double *restrict probe,
    const double *restrict path_mid, const int *restrict angle_index, const double *restrict angle_weight,
    double (*restrict sun_per_beta)[EYE_BATCH], double (*restrict log_kept)[EYE_BATCH],
    double (*restrict source)[EYE_BATCH])
{
#pragma GCC ivdep
  for (int s = 0; s < live; ++s) {
    double lk[SL_MAX_WAVELENGTHS], phase[SL_MAX_WAVELENGTHS];
    sl_light_fraction_exponents(m, mode, nf, nwl, fields[s], n[s], probe[s], lk);
    const double n_sample =
        mode != SL_LIGHTING_LOW_ALBEDO ? sl_expected_scatter_count(m, mode, nf, nwl, fields[s], n[s], path_mid[s]) : n[s];
    sl_eye_phase_at(m, mode, nf, nwl, fields[s], n_sample, angle_index[s], angle_weight[s], phase);
    for (int c = 0; c < nwl; ++c) {
      log_kept[c][s] = lk[c];
      /* scatter_over_segment integrates beta * ...; the source per unit extinction is the phase
       * term (beta_sca Ams) over beta. */
      source[c][s] = phase[c] * sun_per_beta[c][s];
    }
  }
}

/* The eye pass's exponentials for a batch of samples (of one tile in one slice), every wavelength:
 * the opacity of each sample's segment, the slab's effective extinction (the log of the light it
 * keeps over the probe path, eq. 24, per metre), and the closed-form gather of
 * sl_segment_scatter_moments; radiance[c][s] is the light sample s sends toward the eye at
 * wavelength c before the eye's own attenuation in front of it. Loops over the samples inside
 * loops over the wavelengths, each branch-free, so that every one vectorises (libmvec's exp and
 * expm1) whatever the wavelength count. */
static inline __attribute__((always_inline)) void eye_batch_radiance(
    const int nwl, const int live, const double *restrict beta, const double *restrict inv_beta,
    const double *restrict len, const double *restrict inv_len, const double *restrict inv_probe,
    const double *restrict path_near, const double *restrict light_rate, double (*restrict log_kept)[EYE_BATCH],
    double (*restrict l0)[EYE_BATCH], double (*restrict l1)[EYE_BATCH], double (*restrict source)[EYE_BATCH],
    double *restrict opacity, double (*restrict radiance)[EYE_BATCH])
{
#pragma omp simd
  for (int s = 0; s < live; ++s) opacity[s] = -expm1(-beta[s] * len[s]);
  for (int c = 0; c < nwl; ++c) {
    const double *restrict lk = log_kept[c], *restrict a0 = l0[c], *restrict a1 = l1[c], *restrict src = source[c];
    double *restrict out = radiance[c];
#pragma omp simd
    for (int s = 0; s < live; ++s) {
      const double slab_extinction = -lk[s] * inv_probe[s];
      /* The light along the segment: the buffer's values (ln I) at its ends, log-linear between them
       * (exact where the light falls off exponentially across the buffer, as it does into a
       * cloud; taken linear, it overestimated the light where a thick segment crosses a shadow's
       * edge, across which the buffer falls by up to e^-34 in the bundled storm, and showed the
       * slices as a hatch), times the slab's own attenuation. */
      const double decay = (a0[s] - a1[s]) * inv_len[s];
      const double rate = 1.0 + (slab_extinction * light_rate[s] + decay) * inv_beta[s];
      /* The light entering at the near end, and that times e^-x (x = beta rate len) as one
       * exponential: the log of the far end's light times the segment's transparency, never above
       * 0, where e^-x alone overflows when the light grows by hundreds of e-folds along a thick
       * segment (sl_segment_scatter_moment_scaled). */
      const double near = a0[s] - slab_extinction * path_near[s];
      const double gathered = sl_segment_scatter_moment_scaled(0, beta[s], len[s], rate, exp(near),
                                                               exp(near - beta[s] * rate * len[s]));
      out[s] = gathered * src[s];
    }
  }
}

/* Whether the kept texel spans are this frame's: the same sunlight and the same lattice. */
static int texel_spans_hold(const sl__texel_spans *c, const double prop[3], const light_buffer *L)
{
  if (!c->valid || c->w != L->w || c->h != L->h) return 0;
  for (int a = 0; a < 3; ++a)
    if (c->prop[a] != prop[a] || c->a[a] != L->a[a] || c->b[a] != L->b[a]) return 0;
  return c->amin == L->amin && c->bmin == L->bmin && c->texel_a == L->texel_a && c->texel_b == L->texel_b;
}

/* Makes room for L's texels and keys the spans to its lattice, not yet valid (the frame's set-up
 * fills them, and the frame marks them valid when it has run). Returns 1 when out of memory. */
static int texel_spans_prepare(sl__texel_spans *c, const double prop[3], const light_buffer *L)
{
  const size_t n = (size_t)L->w * L->h;
  c->valid = 0;
  if (n > c->capacity) {
    free(c->u_in), free(c->u_out), free(c->first), free(c->last), free(c->u_entry);
    c->u_in = malloc(n * sizeof(float)), c->u_out = malloc(n * sizeof(float));
    c->first = malloc(n * sizeof(double)), c->last = malloc(n * sizeof(double));
    c->u_entry = malloc(n * sizeof(float));
    c->capacity = c->u_in && c->u_out && c->first && c->last && c->u_entry ? n : 0;
    if (!c->capacity) {
      free(c->u_in), free(c->u_out), free(c->first), free(c->last), free(c->u_entry);
      c->u_in = c->u_out = c->u_entry = NULL, c->first = c->last = NULL;
      return 1;
    }
  }
  for (int a = 0; a < 3; ++a) c->prop[a] = prop[a], c->a[a] = L->a[a], c->b[a] = L->b[a];
  c->amin = L->amin, c->bmin = L->bmin, c->texel_a = L->texel_a, c->texel_b = L->texel_b;
  c->w = L->w, c->h = L->h;
  return 0;
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
} slicer_frame;

/* One thread's share of a frame's passes (called by every thread of a parallel region; the
 * work-sharing loops inside bind to it): light-buffer and ray set-up, then per slice the eye pass
 * and the light pass, then the resolve. Always inlined into the parallel regions of
 * SL_RUN_SPECIALISED, each with constant field and wavelength counts, so that the per-sample
 * loops over fields and wavelengths unroll. */
static inline __attribute__((always_inline)) void slicer_passes(slicer_frame *f, const int nf, const int nwl)
{
  sl_renderer *r = f->r;
  const sl_scene *sc = &r->scene;
  const sl_light_model *m = &r->model;
  const sl_camera *cam = f->cam;
  sl_image *img = f->img;
  const sl_sky_view *view = f->view;
  const sun_table *suntab = f->suntab;
  const light_buffer L = *f->L;
  const sl__sun_lane sun_lane = sl__sun_table_lane(suntab);
  ptrdiff_t light_di, light_dj;
  light_texel_steps(&L, &light_di, &light_dj);
  tile_ranges eye_tiles = *f->eye_tiles, light_tiles = *f->light_tiles;
  float *acc = f->acc;
  double *ray = f->ray;
  int *pk = f->pk, *angle_index = f->angle_index;
  float *angle_weight = f->angle_weight;
  const sl_phase_table *grid_table = f->grid_table;
  const double *fwd = f->fwd, *right = f->right, *up = f->up, *h = f->h, *prop = f->prop;
  const double *sun = sc->sun_direction, *o = cam->position;
  const sl__box_exit sun_exit = f->sun_exit;
  const double tan_half = f->tan_half, aspect = f->aspect, h_o = f->h_o, hp = f->hp, inv_hp = f->inv_hp;
  const double smin = f->smin, ds = f->ds;
  const double kink_step = 0.5 * f->entry_step; /* light_kink's light steps */
  const int kink = f->kink;
  const int nslices = f->nslices, back_to_front = f->back_to_front;
  const int acc_stride = nwl + 2;
  const size_t nl = (size_t)L.w * L.h, np = (size_t)img->width * img->height;
  long eye_samples = 0, light_samples = 0;
  /* This thread's batch of up to EYE_BATCH of an eye tile's samples in a slice: per sample, and per
   * wavelength and sample, in separate arrays that eye_batch_radiance's loops read as vectors. */
  int b_q[EYE_BATCH];
  double b_beta[EYE_BATCH], b_inv_beta[EYE_BATCH], b_len[EYE_BATCH], b_inv_len[EYE_BATCH], b_inv_probe[EYE_BATCH];
  double b_path_near[EYE_BATCH], b_light_rate[EYE_BATCH], b_depth[EYE_BATCH], b_opacity[EYE_BATCH];
  double b_log_kept[SL_MAX_WAVELENGTHS][EYE_BATCH], b_l0[SL_MAX_WAVELENGTHS][EYE_BATCH];
  double b_l1[SL_MAX_WAVELENGTHS][EYE_BATCH], b_source[SL_MAX_WAVELENGTHS][EYE_BATCH];
  double b_radiance[SL_MAX_WAVELENGTHS][EYE_BATCH];
  float b_fields[EYE_BATCH][SL_MAX_FIELDS];
  double b_mid[EYE_BATCH], b_n_far[EYE_BATCH], b_tu[2][EYE_BATCH], b_tv[2][EYE_BATCH], b_sun_frac[EYE_BATCH];
  ptrdiff_t b_texel[2][EYE_BATCH];
  int b_sun_row[EYE_BATCH];
  double b_n[EYE_BATCH], b_probe[EYE_BATCH], b_path_mid[EYE_BATCH], b_sun[SL_MAX_WAVELENGTHS][EYE_BATCH];
  int b_angle_index[EYE_BATCH];
  double b_angle_weight[EYE_BATCH];

  {
    /* Dynamic: a texel's entry march (texel_entry) runs from a few samples to its whole ray. */
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
                (float)texel_entry(r, origin, prop, f->texel_first[t], f->texel_last[t], f->entry_step);
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
       * resolves (light_texel_resolving). fmax passes over a NaN (a ray that never enters). */
      const double spread_a = fmax(fabs(g[1] - g[0]), fabs(g[3] - g[2]));
      const double spread_b = fmax(fabs(g[2] - g[0]), fabs(g[3] - g[1]));
      if (!(spread_a > KINK_SPREAD * L.texel_a || spread_b > KINK_SPREAD * L.texel_b))
        lo = INFINITY, hi = -INFINITY;
      L.cell_gmin[t] = lo, L.cell_gmax[t] = hi;
    }
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
        double c = sl_dot3(sun, d);
        c = c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c;
        const double u = acos(c) * grid_table->inv_step_rad;
        int i = (int)u;
        if (i > grid_table->n_angles - 2) i = grid_table->n_angles - 2;
        angle_index[q] = i;
        angle_weight[q] = (float)(u - i > 1.0 ? 1.0 : u - i);
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
    const size_t n_eye_tiles = (size_t)eye_tiles.nx * eye_tiles.ny, n_light_tiles = (size_t)light_tiles.nx * light_tiles.ny;
#pragma omp for schedule(static)
    for (size_t i = 0; i < n_eye_tiles; ++i) tile_range_from(&eye_tiles, i, img->width, img->height, pk, pk + 1, 2);
#pragma omp for schedule(static)
    for (size_t i = 0; i < n_light_tiles; ++i) tile_range_from(&light_tiles, i, L.w, L.h, L.k_lo, L.k_hi, 1);

    for (int k = 0; k < nslices && r->any_extinction; ++k) {
      const double sk = smin + (k + 0.5) * ds;
      double t_start = 0.0;
#pragma omp master
      t_start = omp_get_wtime();
      /* Eye pass: gather the light scattered toward the eye from this slice (eq. 26). */
      int n_active;
      const int *active_tiles = tiles_active(&eye_tiles, k, &n_active);
      int a_first, a_end;
      tiles_share(&eye_tiles, k, active_tiles, n_active, &a_first, &a_end);
      for (int ai = a_first; ai < a_end; ++ai) {
        const size_t ti = (size_t)active_tiles[ai];
        const unsigned long long tile_start = tile_clock();
        const int tx0 = (int)(ti % eye_tiles.nx) * TILE, ty0 = (int)(ti / eye_tiles.nx) * TILE;
        /* The tile's segments and cells first, prefetched; then per sample its fields (whose
         * loads have been in flight meanwhile) and the gather. */
        int cnt = 0;
        int sq[TILE * TILE];
        double smid[TILE * TILE], slen[TILE * TILE];
        sl__field_cell cells[TILE * TILE];
        const sl_grid_view *g = &r->beta_view;
        const int tx1 = tx0 + TILE < img->width ? tx0 + TILE : img->width;
        int tile_last = k; /* the last slice any of the tile's rays still wants */
        for (int py = ty0; py < ty0 + TILE && py < img->height; ++py) {
          /* The row's pixels whose span holds this slice (most do not: a scalar test each), then
           * their segments and lattice cells as a vector loop (gathers), then bricks per sample. */
          const size_t row = (size_t)py * img->width;
          int active[TILE], n = 0;
          for (int px = tx0; px < tx1; ++px) {
            const size_t q = row + px;
            active[n] = px;
            n += k >= pk[2 * q] && k <= pk[2 * q + 1];
            tile_last = pk[2 * q + 1] > tile_last ? pk[2 * q + 1] : tile_last;
          }
          if (!n) continue;
          row_lattice rl;
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
          }
          const int found = row_cells(r, nf, &rl, n, &eye_samples, lanes, cells + cnt);
          for (int s = 0; s < found; ++s) {
            const int i = lanes[s];
            sq[cnt + s] = (int)(row + active[i]), smid[cnt + s] = mid_of[i], slen[cnt + s] = len_of[i];
          }
          cnt += found;
        }
        /* Then per batch: the samples' fields and parts, their geometry, light-buffer values and
         * sunlight (vector loops, gathers), their table look-ups (eye_batch_phases), the
         * exponentials and moments of every sample and wavelength at once (eye_batch_radiance,
         * libmvec's exp), and the accumulation into the pixels. */
        for (int si = 0; si < cnt;) {
        /* First per sample its fields and parts (scalar: a sample's parts vary); the batch holds
         * each part's pixel, middle, length, fields and extinction. */
        int live = 0;
        for (; si < cnt && live <= EYE_BATCH - EYE_PARTS_MAX; ++si) {
        float v[SL__FIELD_LANES];
        sl__field_fetch(r, nf, &cells[si], v);
        double beta_mid = 0.0;
        for (int j = 0; j < nf; ++j) beta_mid += v[j];
        if (!(beta_mid > 0.0)) continue;
        const int parts = eye_parts(beta_mid * slen[si]);
        if (parts == 1) {
          for (int j = 0; j < nf; ++j) b_fields[live][j] = v[j];
          b_q[live] = sq[si], b_mid[live] = smid[si], b_len[live] = slen[si], b_beta[live] = beta_mid;
          live++;
          continue;
        }
        const double *rq = ray + (size_t)sq[si] * RAY_STRIDE;
        for (int p = 0; p < parts; ++p) {
          /* The parts in the order of compositing: nearest first, or farthest first back to front. */
          const int part = back_to_front ? parts - 1 - p : p;
          const double len = slen[si] / parts, mid = smid[si] + (part + 0.5 - 0.5 * parts) * len;
          const double x[3] = {o[0] + mid * rq[0], o[1] + mid * rq[1], o[2] + mid * rq[2]};
          float *beta_j = b_fields[live];
          sl__sample_fields_n(r, nf, x, beta_j);
          double beta = 0.0;
          for (int j = 0; j < nf; ++j) beta += beta_j[j];
          if (!(beta > 0.0)) continue;
          b_q[live] = sq[si], b_mid[live] = mid, b_len[live] = len, b_beta[live] = beta;
          live++;
        }
        }
        /* Then per part its geometry, light-buffer values and sunlight, in one loop over the
         * batch without branches, so that it vectorises (gathers from the rays, the light
         * buffer and the sun table); as a scalar loop this was the eye pass's largest stage.
         * The light buffer holds the light up to this slab's first plane; from there the light
         * crosses this slab's own medium for a path that grows linearly along the eye segment.
         * The buffer's ln I is taken linear between the segment's two ends and the slab's own
         * attenuation exponential in the path, so the gather has a closed form
         * (sl_segment_scatter_moment_exp). Within the slab, the light keeps fraction(path) of
         * itself (eq. 24 or the plain transparency); its log, per metre of path, is the slab's
         * effective extinction. The fraction is probed at the segment's middle path; its table
         * look-ups wait for eye_batch_phases, its exponentials for eye_batch_radiance. */
        const double s_start = sk - 0.5 * ds;
#pragma GCC ivdep
        for (int s = 0; s < live; ++s) {
          const ptrdiff_t rq = (ptrdiff_t)b_q[s] * RAY_STRIDE;
          const double d[3] = {ray[rq], ray[rq + 1], ray[rq + 2]};
          const double mid = b_mid[s], len = b_len[s];
          const double t_near = mid - 0.5 * len, t_far = mid + 0.5 * len;
          const double x[3] = {o[0] + mid * d[0], o[1] + mid * d[1], o[2] + mid * d[2]};
          const double x_near[3] = {o[0] + t_near * d[0], o[1] + t_near * d[1], o[2] + t_near * d[2]};
          const double x_far[3] = {o[0] + t_far * d[0], o[1] + t_far * d[1], o[2] + t_far * d[2]};
          const double path_near = sl__max(
              sl__min((h[0] * x_near[0] + h[1] * x_near[1] + h[2] * x_near[2] - s_start) * inv_hp,
                      sl__box_exit_distance(&sun_exit, x_near)),
              0.0);
          const double path_far = sl__max(
              sl__min((h[0] * x_far[0] + h[1] * x_far[1] + h[2] * x_far[2] - s_start) * inv_hp,
                      sl__box_exit_distance(&sun_exit, x_far)),
              0.0);
          const double inv_beta = 1.0 / b_beta[s];
          light_texel_lane(&L, x_near, &b_texel[0][s], &b_tu[0][s], &b_tv[0][s]);
          light_texel_lane(&L, x_far, &b_texel[1][s], &b_tu[1][s], &b_tv[1][s]);
          sl__sun_row(suntab, &sun_lane, x, &b_sun_row[s], &b_sun_frac[s]);
          const double path_mid = 0.5 * (path_near + path_far);
          b_path_mid[s] = path_mid;
          const double probe = sl__max(path_mid, 1e-3 * inv_beta);
          b_probe[s] = probe;
          b_angle_index[s] = angle_index[b_q[s]], b_angle_weight[s] = angle_weight[b_q[s]];
          b_inv_beta[s] = inv_beta, b_inv_len[s] = 1.0 / len;
          b_inv_probe[s] = 1.0 / probe, b_path_near[s] = path_near;
          b_light_rate[s] = (path_far - path_near) / len;
          b_depth[s] = mid * (d[0] * fwd[0] + d[1] * fwd[1] + d[2] * fwd[2]);
        }
        /* The light buffer's channels and the sunlight, per channel a loop over the batch (the
         * sunlight's vectorises). */
        for (int c = 0; c <= nwl; ++c) {
          double *restrict out0 = c < nwl ? b_l0[c] : b_n, *restrict out1 = c < nwl ? b_l1[c] : b_n_far;
          const float *restrict st = L.state + c;
          for (int s = 0; s < live; ++s) {
            out0[s] = light_bilinear_lane(st, light_di, light_dj, b_texel[0][s], b_tu[0][s], b_tv[0][s]);
            out1[s] = light_bilinear_lane(st, light_di, light_dj, b_texel[1][s], b_tu[1][s], b_tv[1][s]);
          }
        }
        /* Where an end's texels meet a cloud's surface at a grazing angle, its light from its own
         * entry (light_kink). */
        const double e_plane = s_start * inv_hp;
        for (int s = 0; s < (kink ? live : 0); ++s)
          for (int end = 0; end < 2; ++end) {
            const ptrdiff_t cell = b_texel[end][s] / (nwl + 1);
            const double gmin = L.cell_gmin[cell], gmax = L.cell_gmax[cell];
            if (!(gmin < e_plane && e_plane < 2.0 * gmax - gmin)) continue;
            const double *rq = ray + (size_t)b_q[s] * RAY_STRIDE;
            const double te = b_mid[s] + (end ? 0.5 : -0.5) * b_len[s];
            const double x[3] = {o[0] + te * rq[0], o[1] + te * rq[1], o[2] + te * rq[2]};
            const double back = (h[0] * x[0] + h[1] * x[1] + h[2] * x[2] - s_start) * inv_hp;
            const double p[3] = {x[0] - back * prop[0], x[1] - back * prop[1], x[2] - back * prop[2]};
            double value[SL_MAX_WAVELENGTHS + 1];
            if (!light_kink(r, nf, nwl, &L, light_di, light_dj, b_texel[end][s], b_tu[end][s], b_tv[end][s],
                            e_plane, p, prop, kink_step, value))
              continue;
            for (int c = 0; c < nwl; ++c) (end ? b_l1 : b_l0)[c][s] = value[c];
            (end ? b_n_far : b_n)[s] = value[nwl];
          }
#pragma omp simd
        for (int s = 0; s < live; ++s) b_n[s] = 0.5 * (b_n[s] + b_n_far[s]);
        for (int c = 0; c < nwl; ++c) {
          double *restrict out = b_sun[c];
          const double *restrict rgb = &suntab->rgb[0][0];
#pragma omp simd
          for (int s = 0; s < live; ++s) out[s] = sl__sun_lerp(rgb, b_sun_row[s], b_sun_frac[s], c) * b_inv_beta[s];
        }
        const sl_light_model *held_model = m;
        const int held = sl__batch_fields(f->subsets, nf, live, b_fields, &held_model);
#define EYE_PHASES(model, mode, count) \
  eye_batch_phases(model, mode, count, nwl, live, b_fields, b_n, b_probe, b_path_mid, b_angle_index, b_angle_weight, \
                   b_sun, b_log_kept, b_source)
        SL_WITH_BATCH_MODEL(m, held_model, held, nf, EYE_PHASES);
#undef EYE_PHASES
        eye_batch_radiance(nwl, live, b_beta, b_inv_beta, b_len, b_inv_len, b_inv_probe, b_path_near, b_light_rate, b_log_kept,
                           b_l0, b_l1, b_source, b_opacity, b_radiance);
        for (int s = 0; s < live; ++s) {
          const size_t q = (size_t)b_q[s];
          const double opacity = b_opacity[s];
          float *a = acc + q * acc_stride;
          const double w = back_to_front ? 1.0 : a[nwl];
          for (int c = 0; c < nwl; ++c) {
            const double radiance = b_radiance[c][s];
            if (back_to_front) a[c] = (float)(a[c] * (1.0 - opacity) + radiance);
            else a[c] += (float)(w * radiance);
          }
          if (back_to_front) a[nwl + 1] = (float)(a[nwl + 1] * (1.0 - opacity) + opacity * b_depth[s]);
          else a[nwl + 1] += (float)(w * opacity * b_depth[s]);
          a[nwl] *= (float)(1.0 - opacity); /* exp(-beta len), from expm1's exact small end */
          if (!back_to_front && a[nwl] < sc->termination_transparency) pk[2 * q + 1] = k;
        }
        }
        eye_tiles.work[(size_t)((k + 1) & 1) * eye_tiles.nx * eye_tiles.ny + ti] = tile_cost(tile_start, cnt);
        /* Rays that have become opaque end their spans (below); a tile whose rays have all ended
         * leaves the list from the next slice but one (this slice's end is seen in the next
         * one's scan), where it took 256 failing tests per slice to the far side of the cloud.
         * The new end is never below k: another thread may be listing slice k's tiles now, and
         * k's membership stays as it was (tiles_active). */
        if (tile_last < eye_tiles.k[2 * ti + 1]) __atomic_store_n(&eye_tiles.k[2 * ti + 1], tile_last, __ATOMIC_RELAXED);
      }
      /* The light pass rewrites the buffer the eye pass reads. */
#pragma omp barrier
#pragma omp master
      {
        const double t_mid = omp_get_wtime();
        f->eye_seconds += t_mid - t_start;
        t_start = t_mid;
      }
      /* Light pass: carry the light and its expected scattering count through this slice. */
      active_tiles = tiles_active(&light_tiles, k, &n_active);
      tiles_share(&light_tiles, k, active_tiles, n_active, &a_first, &a_end);
      for (int ai = a_first; ai < a_end; ++ai) {
        const size_t ti = (size_t)active_tiles[ai];
        const unsigned long long tile_start = tile_clock();
        const int tx0 = (int)(ti % light_tiles.nx) * TILE, ty0 = (int)(ti / light_tiles.nx) * TILE;
        int cnt = 0;
        int idx[TILE * TILE];
        double seg[TILE * TILE], seg_end[TILE * TILE];
        float bj[TILE * TILE][SL_MAX_FIELDS];
        sl__field_cell cells[TILE * TILE];
        /* The tile's cells first, prefetched (per row, row_lattice); then their fields, whose
         * loads overlap. */
        const double half = 0.5 * ds * inv_hp;
        const sl_grid_view *g = &r->beta_view;
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
          const int found = row_cells(r, nf, &rl, tx1 - tx0, &light_samples, lanes, cells + cnt);
          for (int s = 0; s < found; ++s)
            idx[cnt + s] = (int)(row + lanes[s]), seg[cnt + s] = len_of[lanes[s]], seg_end[cnt + s] = end_of[lanes[s]];
          cnt += found;
        }
        int live = 0;
        for (int i = 0; i < cnt; ++i) {
          float v[SL__FIELD_LANES];
          sl__field_fetch(r, nf, &cells[i], v);
          double beta = 0.0;
          for (int f = 0; f < nf; ++f) beta += v[f];
          if (!(beta > 0.0)) continue;
          idx[live] = idx[i], seg[live] = seg[i], seg_end[live] = seg_end[i];
          for (int f = 0; f < nf; ++f) bj[live][f] = v[f];
          live++;
        }
        cnt = live;
        const sl_light_model *held_model = m;
        const int held = sl__batch_fields(f->subsets, nf, cnt, bj, &held_model);
        /* The state where each ray enters the medium: before the first step it takes past that
         * (steps not taken leave the state as it was, so it is the state at the entry). */
        for (int i = 0; i < (kink ? cnt : 0); ++i) {
          float *kept = L.entry_state + (size_t)idx[i] * L.stride;
          if (seg_end[i] > L.u_entry[idx[i]] && kept[nwl] < 0.0f)
            for (int c = 0; c <= nwl; ++c) kept[c] = L.state[(size_t)idx[i] * L.stride + c];
        }
#define LIGHT_STEPS(model, mode, count) light_steps(model, mode, count, nwl, cnt, idx, seg, bj, L.state, L.stride)
        SL_WITH_BATCH_MODEL(m, held_model, held, nf, LIGHT_STEPS);
#undef LIGHT_STEPS
        light_tiles.work[(size_t)((k + 1) & 1) * light_tiles.nx * light_tiles.ny + ti] = tile_cost(tile_start, cnt);
      }
#pragma omp barrier
#pragma omp master
      {
        f->light_seconds += omp_get_wtime() - t_start;
        if (sc->progress) sc->progress(sc->progress_user, (k + 1.0) / nslices);
      }
    }

    /* Resolve: premultiplied volume radiance, opacity and the opacity-weighted depth. With an
     * atmosphere the air in front of the volume's midplane (sec. 5) attenuates the volume and adds
     * its own light: frame = L_front + T_front V + T_vol (L_back + L_sun). The layer carries
     * V' = T_front V + (1 - T_vol) L_front, so that V' + T_vol (whole sky + sun) is that frame.
     * Spectral radiance becomes linear sRGB here. */
    const double h_center = sl_dot3(h, r->content_center);
#pragma omp for schedule(static)
    for (size_t q = 0; q < np; ++q) {
      const double *rq = ray + q * RAY_STRIDE;
      double t_mid = fabs(rq[5]) > 1e-12 ? (h_center - h_o) / rq[5] : 0.5 * (rq[3] + rq[4]);
      t_mid = t_mid < rq[3] ? rq[3] : t_mid > rq[4] ? rq[4] : t_mid;
      sl__resolve_pixel(r, sc->atmosphere ? view : NULL, rq, t_mid, acc + q * acc_stride, img, q);
    }
  }
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

int sl_renderer_render(sl_renderer *r, const sl_camera *cam, sl_image *img, sl_render_stats *stats, sl_error *err)
{
  if (!cam || cam->width != img->width || cam->height != img->height)
    return sl_fail(err, SL_ERR_ARG, "render: the image is not the camera's size");
  if (!(cam->fov_deg > 0.0 && cam->fov_deg < 170.0))
    return sl_fail(err, SL_ERR_ARG, "render: field of view %g degrees is out of range (0, 170)", cam->fov_deg);
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up))
    return sl_fail(err, SL_ERR_ARG, "render: camera position equals the target, or up is parallel to the view");
  if (r->scene.light_volume && r->any_extinction) return sl__render_with_light_volume(r, cam, img, stats, err);

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

  /* Slices span the box along h. */
  double smin = INFINITY, smax = -INFINITY;
  for (int c = 0; c < 8; ++c) {
    const double corner[3] = {c & 1 ? r->chi[0] : r->clo[0], c & 2 ? r->chi[1] : r->clo[1], c & 4 ? r->chi[2] : r->clo[2]};
    const double s = sl_dot3(h, corner);
    if (s < smin) smin = s;
    if (s > smax) smax = s;
  }
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
  {
    const double helper[3] = {fabs(prop[2]) < 0.9 ? 0.0 : 1.0, 0.0, fabs(prop[2]) < 0.9 ? 1.0 : 0.0};
    sl_cross3(prop, helper, L.a);
    sl_normalize3(L.a);
    sl_cross3(prop, L.a, L.b);
    double amax = -INFINITY, bmax = -INFINITY;
    L.amin = L.bmin = INFINITY;
    for (int c = 0; c < 8; ++c) {
      const double corner[3] = {c & 1 ? r->chi[0] : r->clo[0], c & 2 ? r->chi[1] : r->clo[1],
                                c & 4 ? r->chi[2] : r->clo[2]};
      const double a = sl_dot3(L.a, corner), b = sl_dot3(L.b, corner);
      if (a < L.amin) L.amin = a;
      if (a > amax) amax = a;
      if (b < L.bmin) L.bmin = b;
      if (b > bmax) bmax = b;
    }
    const double extent_a = amax - L.amin, extent_b = bmax - L.bmin;
    if (sc->light_resolution > 0) {
      /* Square texels, light_resolution of them along the longer side. */
      L.texel_a = L.texel_b = fmax(extent_a, extent_b) / sc->light_resolution;
    } else {
      /* Per buffer axis (light_texel_resolving): shadows as fine as a pixel at the content's
       * centre shows them (but no finer than the shortest mean free path), and every cell the
       * sun's rays cross sampled. On a flat WRF grid under a
       * low sun the axis across the layers then follows the vertical spacing and the other the
       * horizontal, where the earlier square texel (the finest foreshortened spacing on both axes)
       * left the layers 44 texels and spent 512 on the horizontal. At most max(512, the image's
       * longer side) texels per axis: finer shadows than twice the image's resolution cannot be
       * seen. Measured in PERFORMANCE.md, session 7. */
      const int side = img->width > img->height ? img->width : img->height;
      const int image_limit = side > 512 ? side : 512;
      double to_centre[3];
      for (int a = 0; a < 3; ++a) to_centre[a] = r->content_center[a] - cam->position[a];
      const double pixel = sqrt(sl_dot3(to_centre, to_centre)) * 2.0 * tan_half / img->height;
      L.texel_a = light_texel_resolving(&r->shape, L.a, extent_a, pixel, r->beta_max, image_limit);
      L.texel_b = light_texel_resolving(&r->shape, L.b, extent_b, pixel, r->beta_max, image_limit);
    }
    L.inv_texel_a = 1.0 / L.texel_a, L.inv_texel_b = 1.0 / L.texel_b;
    L.w = (int)ceil(extent_a * L.inv_texel_a - 1e-9);
    L.h = (int)ceil(extent_b * L.inv_texel_b - 1e-9);
    if (L.w < 1) L.w = 1;
    if (L.h < 1) L.h = 1;
  }
  const sl_light_model *m = &r->model;
  const int nwl = m->nwl, nf = m->nf;
  const int acc_stride = nwl + 2; /* radiance per wavelength, transparency, depth numerator */
  L.stride = nwl + 1;
  const size_t nl = (size_t)L.w * L.h, np = (size_t)img->width * img->height;
  const int spans_kept = texel_spans_hold(&r->texel_spans, prop, &L);
  if (!spans_kept && texel_spans_prepare(&r->texel_spans, prop, &L)) {
    free(suntab);
    return sl_fail(err, SL_ERR_NOMEM, "render: out of memory for the light buffer");
  }
  L.u_in = r->texel_spans.u_in, L.u_out = r->texel_spans.u_out, L.u_entry = r->texel_spans.u_entry;
  L.state = malloc(nl * L.stride * sizeof(float));
  /* The entry kink (light_kink) where flat tops meet the sunlight at a grazing angle: under a sun
   * below KINK_SUN_ELEVATION. Where it runs it costs up to half an eye pass (docs/PERFORMANCE.md,
   * session 17), which a higher sun's frames need not pay. */
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
      tiles_init(&eye_tiles, img->width, img->height, threads) && tiles_init(&light_tiles, L.w, L.h, threads);
  const int kink_ok = !kink || (L.entry_state && L.entry_g && L.cell_gmin && L.cell_gmax);
  if (!L.state || !L.h_origin || !L.k_lo || !L.k_hi || !kink_ok || !acc || !ray || !pk || !angle_index ||
      !angle_weight || !tiles_ok) {
    free(L.state), free(L.h_origin), free(L.k_lo), free(L.k_hi);
    free(L.entry_state), free(L.entry_g), free(L.cell_gmin), free(L.cell_gmax);
    free(acc), free(ray), free(pk), free(suntab), free(angle_index), free(angle_weight);
    tiles_free(&eye_tiles), tiles_free(&light_tiles);
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
                    .texel_entry = r->texel_spans.u_entry, .spans_kept = spans_kept, .kink = kink};
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
  tiles_free(&eye_tiles), tiles_free(&light_tiles);
  return SL_OK;
}

int sl_renderer_background(const sl_renderer *r, const sl_camera *cam, sl_image *img, sl_error *err)
{
  if (!cam || cam->width != img->width || cam->height != img->height)
    return sl_fail(err, SL_ERR_ARG, "background: the image is not the camera's size");
  const sl_scene *sc = &r->scene;
  sl_sky_view view;
  if (sc->atmosphere && sl_sky_view_init(&view, sc->atmosphere, cam->position, sc->sun_direction, err))
    return err->code;
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up))
    return sl_fail(err, SL_ERR_ARG, "background: camera position equals the target, or up is parallel to the view");
  const double tan_half = tan(0.5 * cam->fov_deg * M_PI / 180.0);
  const double aspect = (double)img->width / img->height;
  const size_t n = (size_t)img->width * img->height;
  const int nwl = r->model.nwl;
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < n; ++i) {
    double L[SL_MAX_WAVELENGTHS], rgb[3], ground_depth = INFINITY;
    if (sc->atmosphere) {
      double d[3], sun_disk[SL_MAX_WAVELENGTHS];
      sl_camera_pixel_ray(fwd, right, up, tan_half, aspect, img->width, img->height, (int)(i % img->width),
                (int)(i / img->width), d);
      sl_sky_view_segment(&view, d, 0.0, INFINITY, L, NULL);
      if (sl_sky_sun_disk_radiance(sc->atmosphere, cam->position, d, sc->sun_direction, sun_disk))
        for (int c = 0; c < nwl; ++c) L[c] += sun_disk[c];
      sl_cie_apply(r->to_rgb, nwl, L, rgb);
      /* Where the ray meets the ground (plane or sphere), as distance along the view axis. */
      double up_eye[3];
      const double h = sl_sky_altitude(sc->atmosphere, cam->position, up_eye);
      const double t = sl_sky_ground_distance(h, sl_dot3(d, up_eye), sc->atmosphere->ground_radius);
      ground_depth = t * sl_dot3(d, fwd);
    } else {
      for (int c = 0; c < SL_CHANNELS; ++c) rgb[c] = sc->sky_radiance[c];
    }
    for (int c = 0; c < SL_CHANNELS; ++c) img->rgba[4 * i + c] = (float)rgb[c];
    img->rgba[4 * i + 3] = 1.0f;
    img->depth[i] = (float)ground_depth;
    img->transparency[i] = 0.0f;
  }
  return SL_OK;
}

void sl_renderer_content_bounds(const sl_renderer *r, double lo[3], double hi[3])
{
  const sl_volume *v = &r->shape;
  int mn[3] = {v->nx, v->ny, v->nz}, mx[3] = {-1, -1, -1};
  for (int k = 0; k < v->nz; ++k)
    for (int j = 0; j < v->ny; ++j)
      for (int i = 0; i < v->nx; ++i) {
        if (!(r->beta[sl_volume_index(v, i, j, k)] > 0.0f)) continue;
        const int idx[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          if (idx[a] < mn[a]) mn[a] = idx[a];
          if (idx[a] > mx[a]) mx[a] = idx[a];
        }
      }
  if (mx[0] < 0) {
    memcpy(lo, r->lo, sizeof r->lo);
    memcpy(hi, r->hi, sizeof r->hi);
    return;
  }
  for (int a = 0; a < 3; ++a) {
    lo[a] = fmax(r->lo[a], v->origin[a] + (mn[a] - 1) * v->spacing[a]);
    hi[a] = fmin(r->hi[a], v->origin[a] + (mx[a] + 1) * v->spacing[a]);
  }
}

void sl_camera_ground_distance(const sl_camera *cam, const sl_atmosphere *atm, float *distance)
{
  double up[3];
  const double h = sl_sky_altitude(atm, cam->position, up);
#pragma omp parallel for schedule(static)
  for (int py = 0; py < cam->height; ++py)
    for (int px = 0; px < cam->width; ++px) {
      double d[3];
      if (sl_camera_ray(cam, px, py, d)) continue;
      const double t = sl_sky_ground_distance(h, sl_dot3(d, up), atm->ground_radius);
      float *q = distance + (size_t)py * cam->width + px;
      if (t < *q) *q = (float)t;
    }
}
