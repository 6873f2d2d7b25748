/* The renderer keeps each field's extinction and no total: the total (Riley et al. 2004, eq. 3)
 * is summed where it is read. Checked against each field's own grid of eta sigma (eq. 2, the
 * paper's cross-sections from sl_particle_properties), sampled by sl_grid_sample and added:
 * - at random points inside the box, near its faces and outside it (zero there), for three
 *   fields and for one (where the look-up is sl_grid_sample on the one field: bitwise equal);
 * - the optical depth of short segments (sl__segment_optical_depth, the two-point Gauss rule
 *   between node planes) against a 20000-point midpoint sum of that reference total;
 * - each occupied brick's largest total (brick_beta_max) against the largest sum of any sample
 *   its cells read. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "renderer_internal.h"
#include "sl_renderer.h"
#include "sl_testing.h"

enum { NX = 19, NY = 13, NZ = 11 };

static unsigned rng = 2024u;
static double uniform(void)
{
  rng = rng * 1664525u + 1013904223u;
  return (rng >> 8) / 16777216.0;
}

/* The reference total at x: each field's extinction grid sampled alone, summed. */
static double reference_total(const sl_grid_view *views, int n, const double x[3])
{
  double sum = 0.0;
  for (int j = 0; j < n; ++j) sum += sl_grid_sample(&views[j], x);
  return sum;
}

static void check_volume(const sl_particle *types, int n)
{
  sl_error err = {0};
  sl_volume v;
  const double spacing[3] = {150.0, 110.0, 60.0}, origin[3] = {-1000.0, 500.0, 300.0};
  if (!CHECK(sl_volume_init(&v, NX, NY, NZ, origin, spacing, &err) == SL_OK)) return;
  float *ext[3] = {NULL, NULL, NULL};
  sl_grid_view views[3];
  const size_t count = sl_volume_count(&v);
  for (int j = 0; j < n; ++j) {
    CHECK(sl_volume_add_field(&v, types[j], &err) == SL_OK);
    float *eta = v.eta[types[j]];
    ext[j] = malloc(count * sizeof(float));
    const double sigma = sl_particle_properties(types[j])->sigma_ext_m2;
    /* Each field in blobs of its own, half the samples clear: the fields overlap in places. */
    for (size_t i = 0; i < count; ++i) {
      const double u = uniform();
      eta[i] = u < 0.5 ? 0.0f : (float)((u - 0.5) * 2e-3 / sigma); /* extinction up to 1e-3 per metre */
      ext[j][i] = (float)(eta[i] * sigma);
    }
    sl_grid_view_init(&views[j], ext[j], &v);
  }
  sl_scene sc = {.volume = &v, .slices = 64, .lighting = SL_LIGHTING_LOW_ALBEDO};
  sl_sun_direction(40.0, 200.0, sc.sun_direction);
  for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0;
  sl_renderer *r = sl_renderer_create(&sc, &err);
  if (!CHECK_MSG(r != NULL, err.message)) goto done;
  CHECK(r->model.nf == n);
  double lo[3], hi[3];
  sl_volume_bounds(&v, lo, hi);
  double worst = 0.0;
  int outside_nonzero = 0, unequal_one = 0;
  for (int k = 0; k < 4000; ++k) {
    double x[3];
    /* A tenth of the box beyond each face on every axis: some points fall outside. */
    for (int a = 0; a < 3; ++a) x[a] = lo[a] + (hi[a] - lo[a]) * (1.2 * uniform() - 0.1);
    const int inside = x[0] >= lo[0] && x[0] <= hi[0] && x[1] >= lo[1] && x[1] <= hi[1] && x[2] >= lo[2] && x[2] <= hi[2];
    const double got = sl__total_extinction(r, x), want = reference_total(views, n, x);
    if (!inside) outside_nonzero += got != 0.0;
    if (n == 1) unequal_one += got != want;
    worst = fmax(worst, fabs(got - want));
  }
  char what[160];
  /* Float trilinear weights and lanes against the reference's double ones: a few float epsilons
   * of the largest extinction (2e-3 per metre summed over three fields). */
  snprintf(what, sizeof what, "%d fields: total within 1e-9 per metre of the fields' sum (worst %.3g)", n, worst);
  CHECK_MSG(worst < 1e-9, what);
  CHECK_MSG(outside_nonzero == 0, "the total is zero outside the box");
  if (n == 1) CHECK_MSG(unequal_one == 0, "one field: the total is sl_grid_sample of that field, bitwise");

  /* Short segments (a few cells): the Gauss rule between node planes against a fine midpoint sum. */
  double worst_tau = 0.0;
  for (int k = 0; k < 300; ++k) {
    double a[3], b[3];
    for (int ax = 0; ax < 3; ++ax) {
      a[ax] = lo[ax] + (hi[ax] - lo[ax]) * uniform();
      b[ax] = fmin(fmax(a[ax] + spacing[ax] * (4.0 * uniform() - 2.0), lo[ax]), hi[ax]);
    }
    const double got = sl__segment_optical_depth(r, n, a, b);
    const double len = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
    const int m = 20000;
    double sum = 0.0;
    for (int i = 0; i < m; ++i) {
      const double l = (i + 0.5) / m;
      const double x[3] = {a[0] + l * (b[0] - a[0]), a[1] + l * (b[1] - a[1]), a[2] + l * (b[2] - a[2])};
      sum += reference_total(views, n, x);
    }
    const double want = sum * len / m;
    worst_tau = fmax(worst_tau, fabs(got - want) / fmax(want, 1e-6));
  }
  snprintf(what, sizeof what, "%d fields: segment optical depths within 1e-5 of a midpoint sum (worst %.3g)", n,
           worst_tau);
  CHECK_MSG(worst_tau < 1e-5, what);

  /* Each brick's largest total: samples 8b .. 8b + 8 (the cells with a lower corner in it). */
  int brick_wrong = 0;
  for (int bz = 0; bz < r->bricks[2]; ++bz)
    for (int by = 0; by < r->bricks[1]; ++by)
      for (int bx = 0; bx < r->bricks[0]; ++bx) {
        float most = 0.0f;
        for (int k = 8 * bz; k <= 8 * bz + 8 && k < NZ; ++k)
          for (int j = 8 * by; j <= 8 * by + 8 && j < NY; ++j)
            for (int i = 8 * bx; i <= 8 * bx + 8 && i < NX; ++i) {
              float s = 0.0f;
              for (int f = 0; f < n; ++f) s += ext[f][sl_volume_index(&v, i, j, k)];
              most = fmaxf(most, s);
            }
        const size_t b = ((size_t)bz * r->bricks[1] + by) * r->bricks[0] + bx;
        brick_wrong += fabsf(r->brick_beta_max[b] - most) > 1e-6f * most;
      }
  CHECK_MSG(brick_wrong == 0, "each brick's largest total is the largest sum of the fields its cells read");
  sl_renderer_destroy(r);
done:
  for (int j = 0; j < n; ++j) free(ext[j]);
  sl_volume_free(&v);
}

int main(void)
{
  const sl_particle three[3] = {SL_CLOUD, SL_RAIN, SL_ICE}, one[1] = {SL_SNOW};
  check_volume(three, 3);
  check_volume(one, 1);
  return sl_test_finish("test_total_extinction");
}
