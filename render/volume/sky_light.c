/* The diffuse light on the volume: the lattice of the sky dome's diffuse radiance M and of the
 * diffuse sunlight D (sky_light.h states both models).
 *
 * The dome is split into SKY_DIRECTIONS cells around Fibonacci-sphere directions; each cell's
 * radiance is the mean of the sky model over SKY_CELL_SAMPLES finer directions that fall in it
 * (so the sun's aureole is averaged into its cell, not sampled or missed), as the sky seen from
 * where that direction leaves the grid's box: the air inside the box scatters nothing (as in the
 * Monte Carlo reference, whose scattered paths collect the sky where they leave the box), so a
 * direction down to the ground sees the black ground, one up through the top the thin air above
 * it, one out through a side the sky from that height.
 * The transport optical depth toward each direction is swept plane by plane across the lattice
 * as the light volume's sweep carries the sunlight (sl_sweep_geometry), one direction per task,
 * so threads never wait on each other; the directions are summed in their order afterwards, so
 * the result does not depend on the thread count. */
#include "sky_light.h"
#include "renderer_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "sl_sample_physics.h"
#include "sl_sweep_geometry.h"
#include "sun_table.h"
#include "vector_math.h"

#define SKY_DIRECTIONS 24
#define SKY_CELL_SAMPLES 48
#define SKY_CHUNK 4 /* directions swept at once (a divisor of SKY_DIRECTIONS) */
/* Altitudes over the grid's height at which the dome is tabulated, linear in between. */
#define SKY_ALTITUDES 16
/* The lattice's largest sample count: the grid's own when it has fewer, else every f-th sample
 * (the diffuse light varies over the transport mean free path, several cells in a storm). */
#define SKY_LATTICE_MAX 100000
/* Two-stream diffuse transmittance of a slab of transport optical depth tau: 1 / (1 + 3/4 tau). */
#define SKY_TWO_STREAM 0.75
/* The look-up's weight floor against the lattice's largest transport extinction. */
#define SKY_WEIGHT_FLOOR 1e-6

/* The sunlight's diffuse share D / E (sky_light.h) at a sample whose transport depth toward the sun
 * is tau_sun and whose dome weight is sum_k Omega_k w_k (1/sr). */
static double diffuse_sunlight_share(double tau_sun, double dome_weight)
{
  const double total = 1.0 / (1.0 + SKY_TWO_STREAM * tau_sun) / dome_weight;
  const double beam = exp(-tau_sun) / (4.0 * M_PI);
  return total > beam ? total - beam : 0.0;
}

void sl__sky_light_free(sl__sky_light *s)
{
  free(s->radiance);
  s->radiance = NULL;
}

/* Unit vector i of n on the Fibonacci sphere (equal areas, no pole cluster). */
static void fibonacci_direction(int i, int n, double d[3])
{
  const double z = 1.0 - (2.0 * i + 1.0) / n, rho = sqrt(fmax(0.0, 1.0 - z * z));
  const double phi = i * M_PI * (3.0 - sqrt(5.0));
  d[0] = rho * cos(phi), d[1] = rho * sin(phi), d[2] = z;
}

/* The sky's radiance per wavelength seen from `at` along the unit d: the atmosphere's whole ray
 * (to the top of the air, or down to the ground), or the scene's constant sky without air. */
static void sky_radiance(const sl_renderer *r, const sl_sky_view *view, const double d[3], double *out)
{
  if (view) {
    sl_sky_view_segment(view, d, 0.0, INFINITY, out, NULL);
    return;
  }
  for (int c = 0; c < r->model.nwl; ++c) out[c] = r->scene.sky_radiance[c];
}

/* The transport optical depth from every lattice sample toward direction d (unit, toward the
 * sky) to the box's edge, into tau: the planes across d's dominant axis in the light's order. A
 * sample's ray toward d crosses the previous plane at the same in-plane offset (g.shift) for every
 * sample, so its depth there and the extinction there are one bilinear stencil; the path between
 * the planes adds the trapezoid of the extinction at its two ends. A ray that enters through a side
 * face starts there with depth 0 over the path from that face; between the outermost samples and
 * the faces the entering (zero) depth blends in (sl_sweep_fresh_weight), as in the light volume's
 * sweep. */
static void sweep_direction(const sl__sky_light *s, const float *beta_tr, const double d[3], float *tau)
{
  sl_sweep_geometry g;
  sl_sweep_geometry_init(s->n, s->spacing, d, &g);
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = s->origin[a], hi[a] = s->origin[a] + (s->n[a] - 1) * s->spacing[a];
  sl__box_exit exit;
  sl__box_exit_init(&exit, lo, hi, d);
  const ptrdiff_t stride[3] = {1, s->n[0], (ptrdiff_t)s->n[0] * s->n[1]};
  const int n1 = s->n[g.a1], n2 = s->n[g.a2];
  const ptrdiff_t s1 = n1 > 1 ? stride[g.a1] : 0, s2 = n2 > 1 ? stride[g.a2] : 0;
  const int i_shift = (int)floor(g.shift[0]), j_shift = (int)floor(g.shift[1]);
  const double fu = g.shift[0] - i_shift, fw = g.shift[1] - j_shift;
  const double w00 = (1 - fu) * (1 - fw), w10 = fu * (1 - fw), w01 = (1 - fu) * fw, w11 = fu * fw;
  for (int kk = 0; kk < s->n[g.axis]; ++kk) {
    const int k = g.first + kk * g.step;
    const ptrdiff_t plane = (ptrdiff_t)k * stride[g.axis], before = plane - (ptrdiff_t)g.step * stride[g.axis];
    for (int jj = 0; jj < n2; ++jj)
      for (int ii = 0; ii < n1; ++ii) {
        const ptrdiff_t q = plane + ii * stride[g.a1] + jj * stride[g.a2];
        const double u = ii + g.shift[0], w = jj + g.shift[1];
        double depth = 0.0;
        if (kk > 0 && sl_sweep_in_plane(u, w, n1, n2)) {
          int i = ii + i_shift, j = jj + j_shift;
          double tau_before, beta_before;
          if (i >= 0 && j >= 0 && i < n1 - 1 && j < n2 - 1) {
            const ptrdiff_t p = before + i * stride[g.a1] + j * stride[g.a2];
            tau_before = w00 * tau[p] + w10 * tau[p + s1] + w01 * tau[p + s2] + w11 * tau[p + s1 + s2];
            beta_before = w00 * beta_tr[p] + w10 * beta_tr[p + s1] + w01 * beta_tr[p + s2] + w11 * beta_tr[p + s1 + s2];
          } else {
            /* At the plane's rim: clamped corners, and the entering light's weight. */
            const double uc = u < 0.0 ? 0.0 : u > n1 - 1 ? n1 - 1 : u, wc = w < 0.0 ? 0.0 : w > n2 - 1 ? n2 - 1 : w;
            i = (int)uc, j = (int)wc;
            if (i > n1 - 2) i = n1 > 1 ? n1 - 2 : 0;
            if (j > n2 - 2) j = n2 > 1 ? n2 - 2 : 0;
            const double a = n1 > 1 ? uc - i : 0.0, b = n2 > 1 ? wc - j : 0.0;
            const ptrdiff_t p = before + i * stride[g.a1] + j * stride[g.a2];
            const double v00 = (1 - a) * (1 - b), v10 = a * (1 - b), v01 = (1 - a) * b, v11 = a * b;
            const double kept = 1.0 - sl_sweep_fresh_weight(u, w, n1, n2);
            tau_before = kept * (v00 * tau[p] + v10 * tau[p + s1] + v01 * tau[p + s2] + v11 * tau[p + s1 + s2]);
            beta_before = v00 * beta_tr[p] + v10 * beta_tr[p + s1] + v01 * beta_tr[p + s2] + v11 * beta_tr[p + s1 + s2];
          }
          depth = tau_before + 0.5 * g.path * (beta_tr[q] + beta_before);
        } else if (kk > 0) {
          /* Entered through a side face: the path from it, at this sample's extinction. */
          double x[3];
          int idx[3];
          idx[g.axis] = k, idx[g.a1] = ii, idx[g.a2] = jj;
          for (int a = 0; a < 3; ++a) x[a] = s->origin[a] + idx[a] * s->spacing[a];
          depth = sl__min(g.path, sl__box_exit_distance(&exit, x)) * beta_tr[q];
        }
        tau[q] = (float)depth;
      }
  }
}

/* The lattice over the content box: the grid's samples, every f-th along each axis with f the
 * smallest that keeps it within SKY_LATTICE_MAX. */
static int lattice_init(const sl_renderer *r, sl__sky_light *s, int first[3])
{
  const sl_volume *v = &r->shape;
  const int n[3] = {v->nx, v->ny, v->nz};
  int last[3];
  for (int a = 0; a < 3; ++a) {
    const double u0 = (r->clo[a] - v->origin[a]) / v->spacing[a], u1 = (r->chi[a] - v->origin[a]) / v->spacing[a];
    first[a] = (int)floor(u0), last[a] = (int)ceil(u1);
    first[a] = first[a] < 0 ? 0 : first[a] > n[a] - 1 ? n[a] - 1 : first[a];
    last[a] = last[a] < first[a] ? first[a] : last[a] > n[a] - 1 ? n[a] - 1 : last[a];
  }
  int f = 1;
  for (;; ++f) {
    double count = 1.0;
    for (int a = 0; a < 3; ++a) count *= (last[a] - first[a] + f - 1) / f + 1;
    if (count <= SKY_LATTICE_MAX) break;
  }
  for (int a = 0; a < 3; ++a) {
    s->n[a] = (last[a] - first[a] + f - 1) / f + 1;
    s->spacing[a] = f * v->spacing[a];
    s->origin[a] = v->origin[a] + first[a] * v->spacing[a];
    s->view.n[a] = s->n[a], s->view.origin[a] = s->origin[a], s->view.inv_spacing[a] = 1.0 / s->spacing[a];
    s->view.lo[a] = s->origin[a], s->view.hi[a] = s->origin[a] + (s->n[a] - 1) * s->spacing[a];
  }
  s->view.data = NULL;
  return f;
}

/* The transport extinction beta (1 - omega g) per field, summed, averaged over each lattice
 * sample's footprint on the grid (the grid's samples within half a lattice step). */
static void lattice_transport_extinction(const sl_renderer *r, const sl__sky_light *s, const int first[3], int f,
                                         float *out)
{
  const sl_volume *v = &r->shape;
  const sl_light_model *m = &r->model;
  const int n[3] = {v->nx, v->ny, v->nz}, nf = m->nf, h = f / 2;
  double scale[SL_MAX_FIELDS];
  for (int j = 0; j < nf; ++j) {
    double g = 0.0;
    for (int c = 0; c < m->nwl; ++c) g += m->table[j][c] ? m->table[j][c]->asymmetry : 0.0;
    scale[j] = 1.0 - m->albedo_mean[j] * g / m->nwl;
  }
#pragma omp parallel for schedule(static)
  for (int K = 0; K < s->n[2]; ++K)
    for (int J = 0; J < s->n[1]; ++J)
      for (int I = 0; I < s->n[0]; ++I) {
        const int c[3] = {first[0] + f * I, first[1] + f * J, first[2] + f * K};
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
          lo[a] = c[a] - h < 0 ? 0 : c[a] - h;
          hi[a] = c[a] + h > n[a] - 1 ? n[a] - 1 : c[a] + h;
        }
        /* The footprint spans at most two 8^3 bricks per axis: empty when its corners' bricks are. */
        int occupied = 0;
        for (int corner = 0; corner < 8 && !occupied; ++corner) {
          const int i0[3] = {corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2]};
          int cell[3];
          for (int a = 0; a < 3; ++a) cell[a] = i0[a] > n[a] - 2 ? (n[a] > 1 ? n[a] - 2 : 0) : i0[a];
          occupied = sl__brick_occupied(r, cell);
        }
        if (!occupied) {
          out[((size_t)K * s->n[1] + J) * s->n[0] + I] = 0.0f;
          continue;
        }
        double sum = 0.0;
        long count = 0;
        for (int k = lo[2]; k <= hi[2]; ++k)
          for (int j = lo[1]; j <= hi[1]; ++j)
            for (int i = lo[0]; i <= hi[0]; ++i, ++count) {
              const float *p = r->fields + sl_volume_index(v, i, j, k) * nf;
              for (int q = 0; q < nf; ++q) sum += p[q] * scale[q];
            }
        out[((size_t)K * s->n[1] + J) * s->n[0] + I] = count ? (float)(sum / count) : 0.0f;
      }
}

#define SKY_FINE (SKY_DIRECTIONS * SKY_CELL_SAMPLES)

/* The dome's cells: each fine direction's nearest sky direction (cell[i]) and each cell's solid
 * angle. */
static void dome_partition(const double dirs[][3], int cell[SKY_FINE], double omega[SKY_DIRECTIONS])
{
  int count[SKY_DIRECTIONS] = {0};
  for (int i = 0; i < SKY_FINE; ++i) {
    double d[3];
    fibonacci_direction(i, SKY_FINE, d);
    int best = 0;
    for (int k = 1; k < SKY_DIRECTIONS; ++k)
      if (sl_dot3(d, dirs[k]) > sl_dot3(d, dirs[best])) best = k;
    cell[i] = best;
    count[best]++;
  }
  for (int k = 0; k < SKY_DIRECTIONS; ++k) omega[k] = 4.0 * M_PI * count[k] / SKY_FINE;
}

/* The sky's mean radiance over each cell at altitude z. */
static int dome_cells(const sl_renderer *r, const int cell[SKY_FINE], double z,
                      double radiance[SKY_DIRECTIONS][SL_MAX_WAVELENGTHS], int *night, sl_error *err)
{
  const int nwl = r->model.nwl;
  sl_sky_view view;
  const sl_sky_view *vp = NULL;
  *night = 0;
  if (r->scene.atmosphere) {
    const double at[3] = {r->content_center[0], r->content_center[1], z};
    if (sl_sky_view_init(&view, r->scene.atmosphere, at, r->scene.sun_direction, err)) return err->code;
    if (view.night) {
      *night = 1;
      return SL_OK;
    }
    vp = &view;
  }
  int count[SKY_DIRECTIONS] = {0};
  memset(radiance, 0, sizeof(double) * SKY_DIRECTIONS * SL_MAX_WAVELENGTHS);
  /* Without skylight the lattice carries the diffuse sunlight alone: a black dome. */
  for (int i = 0; r->scene.skylight && i < SKY_FINE; ++i) {
    double d[3], rad[SL_MAX_WAVELENGTHS];
    fibonacci_direction(i, SKY_FINE, d);
    sky_radiance(r, vp, d, rad);
    for (int c = 0; c < nwl; ++c) radiance[cell[i]][c] += rad[c];
    count[cell[i]]++;
  }
  for (int k = 0; k < SKY_DIRECTIONS; ++k)
    for (int c = 0; c < nwl; ++c) radiance[k][c] = count[k] ? radiance[k][c] / count[k] : 0.0;
  return SL_OK;
}

int sl__sky_light_build(sl_renderer *r, sl_error *err)
{
  sl__sky_light *s = &r->sky;
  sl__sky_light_free(s);
  const int nwl = r->model.nwl;
  s->nwl = nwl, s->stride = (nwl + 4) / 4 * 4;
  int first[3];
  const int f = lattice_init(r, s, first);
  const size_t count = (size_t)s->n[0] * s->n[1] * s->n[2];
  double dirs[SKY_DIRECTIONS][3];
  for (int k = 0; k < SKY_DIRECTIONS; ++k) fibonacci_direction(k, SKY_DIRECTIONS, dirs[k]);
  int cell[SKY_FINE];
  double omega[SKY_DIRECTIONS];
  dome_partition((const double(*)[3])dirs, cell, omega);
  /* The dome seen from SKY_ALTITUDES heights over the grid's box, from its bottom to its top. */
  const int nalt = SKY_ALTITUDES;
  double(*cells)[SKY_DIRECTIONS][SL_MAX_WAVELENGTHS] = malloc(sizeof *cells * nalt);
  float *beta_tr = malloc(count * sizeof(float));
  float *tau = malloc(count * sizeof(float) * SKY_CHUNK);
  s->radiance = sl__huge_alloc(count * s->stride * sizeof(float));
  if (!cells || !beta_tr || !tau || !s->radiance) {
    free(cells), free(beta_tr), free(tau);
    sl__sky_light_free(s);
    return sl_fail(err, SL_ERR_NOMEM, "skylight: out of memory for a %dx%dx%d lattice", s->n[0], s->n[1], s->n[2]);
  }
  const double bottom = r->lo[2], top = r->hi[2];
  for (int a = 0; a < nalt; ++a) {
    const double z = bottom + (top - bottom) * a / (nalt - 1);
    int night = 0;
    if (dome_cells(r, cell, z, cells[a], &night, err)) {
      free(cells), free(beta_tr), free(tau);
      sl__sky_light_free(s);
      return err->code;
    }
    if (night) { /* no sun, no sky: the term is off */
      free(cells), free(beta_tr), free(tau);
      sl__sky_light_free(s);
      return SL_OK;
    }
  }
  lattice_transport_extinction(r, s, first, f, beta_tr);
  /* M = sum_k Omega_k w_k L_k / sum_k Omega_k w_k, L_k from the height where direction k leaves the
   * grid's box. The directions are swept SKY_CHUNK at a time, one per task, and each chunk is
   * added to the sums (kept in the output) in the directions' order, whatever the threads. */
  sl__box_exit exits[SKY_DIRECTIONS];
  for (int k = 0; k < SKY_DIRECTIONS; ++k) sl__box_exit_init(&exits[k], r->lo, r->hi, dirs[k]);
  const double rows_per_m = top > bottom ? (nalt - 1) / (top - bottom) : 0.0;
  const int stride = s->stride;
  float *acc = s->radiance; /* sum_k w_k L_k per wavelength, then sum_k w_k in slot nwl */
  memset(acc, 0, count * stride * sizeof(float));
  for (int k0 = 0; k0 < SKY_DIRECTIONS; k0 += SKY_CHUNK) {
#pragma omp parallel for schedule(dynamic, 1)
    for (int k = k0; k < k0 + SKY_CHUNK; ++k) sweep_direction(s, beta_tr, dirs[k], tau + (size_t)(k - k0) * count);
#pragma omp parallel for schedule(static)
    for (int K = 0; K < s->n[2]; ++K)
      for (int J = 0; J < s->n[1]; ++J)
        for (int I = 0; I < s->n[0]; ++I) {
          const size_t q = ((size_t)K * s->n[1] + J) * s->n[0] + I;
          const double x[3] = {s->origin[0] + I * s->spacing[0], s->origin[1] + J * s->spacing[1],
                               s->origin[2] + K * s->spacing[2]};
          double sum[SL_MAX_WAVELENGTHS + 1] = {0};
          for (int k = k0; k < k0 + SKY_CHUNK; ++k) {
            const double w = omega[k] / (1.0 + SKY_TWO_STREAM * tau[(size_t)(k - k0) * count + q]);
            double u = (x[2] + sl__box_exit_distance(&exits[k], x) * dirs[k][2] - bottom) * rows_per_m;
            u = u < 0.0 ? 0.0 : u > nalt - 1 ? nalt - 1 : u;
            const int a = u < nalt - 2 ? (int)u : nalt - 2;
            const double fa = u - a;
            const double *lo = cells[a][k], *hi = cells[a + 1][k];
            for (int c = 0; c < nwl; ++c) sum[c] += w * (lo[c] + fa * (hi[c] - lo[c]));
            sum[nwl] += w;
          }
          float *out = acc + q * stride;
          for (int c = 0; c <= nwl; ++c) out[c] += (float)sum[c];
        }
  }
  /* The diffuse sunlight: the transport depth toward the sun, and the sunlight at each height. */
  const int diffuse_sun = sl__diffuse_sunlight_on(&r->scene);
  sun_table *suntab = diffuse_sun ? malloc(sizeof *suntab) : NULL;
  if (diffuse_sun) {
    sl_sky_view view = {0};
    if (!suntab || (r->scene.atmosphere &&
                    sl_sky_view_init(&view, r->scene.atmosphere, r->content_center, r->scene.sun_direction, err))) {
      free(cells), free(beta_tr), free(tau), free(suntab);
      sl__sky_light_free(s);
      return suntab ? err->code : sl_fail(err, SL_ERR_NOMEM, "skylight: out of memory");
    }
    sl__sun_table_init(suntab, &r->scene, &view, r->clo, r->chi);
    sweep_direction(s, beta_tr, r->scene.sun_direction, tau);
  }
  /* M, premultiplied by the lattice's extinction, which then takes slot nwl (sky_light_gather.h).
   * The weight has a floor a millionth of the largest extinction, so that a look-up among clear
   * samples only still takes their M (the diffuse light beside the cloud, for a part whose middle
   * lies there) and a grid whose clear air holds a trace of condensate gives the same frame. */
  float most = 0.0f;
  for (size_t q = 0; q < count; ++q) most = beta_tr[q] > most ? beta_tr[q] : most;
  const double floor_weight = SKY_WEIGHT_FLOOR * most;
  const sl__sun_lane lane = diffuse_sun ? sl__sun_table_lane(suntab) : (sl__sun_lane){0};
#pragma omp parallel for schedule(static)
  for (size_t q = 0; q < count; ++q) {
    float *out = acc + q * stride;
    double sun[SL_MAX_WAVELENGTHS] = {0};
    if (diffuse_sun) {
      const size_t I = q % s->n[0], J = q / s->n[0] % s->n[1], K = q / ((size_t)s->n[0] * s->n[1]);
      const double x[3] = {s->origin[0] + I * s->spacing[0], s->origin[1] + J * s->spacing[1],
                           s->origin[2] + K * s->spacing[2]};
      double e[SL_MAX_WAVELENGTHS];
      sl__sun_at(suntab, &lane, x, e);
      const double share = diffuse_sunlight_share(tau[q], out[nwl]);
      for (int c = 0; c < nwl; ++c) sun[c] = e[c] * share;
    }
    const double inv_weight = 1.0 / out[nwl];
    const double weight = beta_tr[q] + floor_weight;
    for (int c = 0; c < nwl; ++c) out[c] = (float)((out[c] * inv_weight + sun[c]) * weight);
    out[nwl] = (float)weight;
  }
  free(cells), free(beta_tr), free(tau), free(suntab);
  return SL_OK;
}
