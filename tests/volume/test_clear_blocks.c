/* Blocks of clear rays that the adaptive refinement fills without marching (clear_margin.h,
 * pixel_refine.h). The clearance bound against brute force: medium cells scattered in a box, rays
 * with the bound's checkpoints at the exact clearance, and every ray within the angle the ratio
 * allows sampled finely must stay out of every medium cell (and rays at four times that angle do
 * meet medium, so the sampling would see a violation). The refinement's rule on a clear field: the
 * clearance ratio against the spread decides the lattice marched. The march: a one-sample cloud
 * between the lattice rays of a far camera is not lost, and wherever the adaptive frame is clear a
 * ray per pixel is clear too. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "clear_margin.h"
#include "homogeneous_reference.h"
#include "pixel_refine.h"
#include "refine_lattice.h"
#include "sl_testing.h"
#include "sl_vec3.h"
#include "sl_volume.h"

enum { CELLS = 12 };

typedef struct medium {
  double inv[3];  /* cells per unit length */
  int cell[CELLS][3];
  double lo[3], hi[3]; /* the box holding the cells */
} medium;

/* Chebyshev distance in cells from x to the nearest medium cell (closed). */
static double clearance(const medium *m, const double x[3])
{
  double best = INFINITY;
  for (int c = 0; c < CELLS; ++c) {
    double gap = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double u = x[a] * m->inv[a];
      gap = fmax(gap, fmax(0.0, fmax(m->cell[c][a] - u, u - (m->cell[c][a] + 1))));
    }
    best = fmin(best, gap);
  }
  return best;
}

static double uniform(unsigned *s)
{
  *s = *s * 1664525u + 1013904223u;
  return (*s >> 8) / 16777216.0;
}

/* Whether a ray at `angle` from d (8 directions round it, 2000 points each over [0, t_far], finer
 * than a cell) enters a medium cell. */
static int neighbours_meet_medium(const medium *m, const double o[3], const double d[3], double angle, double t_far)
{
  double e1[3] = {-d[1], d[0], 0.0}, e2[3];
  sl_normalize3(e1);
  e2[0] = d[1] * e1[2] - d[2] * e1[1], e2[1] = d[2] * e1[0] - d[0] * e1[2], e2[2] = d[0] * e1[1] - d[1] * e1[0];
  for (int k = 0; k < 8; ++k) {
    const double phi = 2.0 * M_PI * k / 8.0;
    /* A chord of length `angle` on the unit sphere from d. */
    const double tilt = 2.0 * asin(0.5 * angle);
    double dd[3];
    for (int a = 0; a < 3; ++a) dd[a] = cos(tilt) * d[a] + sin(tilt) * (cos(phi) * e1[a] + sin(phi) * e2[a]);
    for (int i = 1; i <= 2000; ++i) {
      const double t = t_far * i / 2000.0;
      const double x[3] = {o[0] + t * dd[0], o[1] + t * dd[1], o[2] + t * dd[2]};
      if (clearance(m, x) <= 0.0) return 1;
    }
  }
  return 0;
}

static void test_bound_against_brute_force(void)
{
  unsigned seed = 12345u;
  int bounded = 0, violations = 0, wide_hits = 0;
  for (int trial = 0; trial < 30; ++trial) {
    medium m = {.inv = {1.0, 1.0 / 1.5, 1.0 / 0.7}};
    for (int a = 0; a < 3; ++a) m.lo[a] = INFINITY, m.hi[a] = -INFINITY;
    for (int c = 0; c < CELLS; ++c)
      for (int a = 0; a < 3; ++a) {
        m.cell[c][a] = (int)(30 * uniform(&seed));
        m.lo[a] = fmin(m.lo[a], m.cell[c][a] / m.inv[a]);
        m.hi[a] = fmax(m.hi[a], (m.cell[c][a] + 1) / m.inv[a]);
      }
    const double o[3] = {-40.0 + 20 * uniform(&seed), -30.0 * uniform(&seed), 60.0 * uniform(&seed)};
    double t_far = 0.0;
    for (int k = 0; k < 8; ++k) {
      const double c[3] = {k & 1 ? m.hi[0] : m.lo[0], k & 2 ? m.hi[1] : m.lo[1], k & 4 ? m.hi[2] : m.lo[2]};
      t_far = fmax(t_far, sqrt((c[0] - o[0]) * (c[0] - o[0]) + (c[1] - o[1]) * (c[1] - o[1]) + (c[2] - o[2]) * (c[2] - o[2])));
    }
    for (int ray = 0; ray < 25; ++ray) {
      double target[3], d[3], t0, t1;
      for (int a = 0; a < 3; ++a) target[a] = m.lo[a] + (m.hi[a] - m.lo[a]) * uniform(&seed);
      for (int a = 0; a < 3; ++a) d[a] = target[a] - o[a];
      sl_normalize3(d);
      if (!sl_ray_box(m.lo, m.hi, o, d, &t0, &t1) || t0 < 0.0) continue; /* the camera lies outside */
      double rate = 0.0, entry, exit;
      for (int a = 0; a < 3; ++a) rate = fmax(rate, fabs(d[a]) * m.inv[a]);
      sl__clear_box_rates(m.lo, m.hi, o, d, m.inv, &entry, &exit);
      sl__clear_margin margin;
      sl__clear_margin_begin(&margin, rate, t0, entry);
      /* Checkpoints a random 0.2 to 1.5 apart, at the exact clearance less up to half a cell. */
      for (double t = t0 + 0.2 * uniform(&seed); t < t1; t += 0.2 + 1.3 * uniform(&seed)) {
        const double x[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
        sl__clear_margin_point(&margin, t, clearance(&m, x) - 0.5 * uniform(&seed), rate);
      }
      const double ratio = sl__clear_margin_end(&margin, t1, exit, t_far);
      if (!(ratio > 0.0)) continue;
      const double cells_per_length = fmax(m.inv[0], fmax(m.inv[1], m.inv[2]));
      bounded++;
      violations += neighbours_meet_medium(&m, o, d, 0.999 * ratio / cells_per_length, t_far);
      wide_hits += neighbours_meet_medium(&m, o, d, 4.0 * ratio / cells_per_length, t_far);
    }
  }
  printf("clearance bound: %d rays bounded, %d with a ray inside the allowed angle meeting medium, %d meeting it at "
         "4x the angle\n", bounded, violations, wide_hits);
  CHECK_MSG(bounded >= 300, "the bound holds for a good share of the rays through the box");
  CHECK_MSG(violations == 0, "no ray within the allowed angle of a bounded ray meets a medium cell");
  CHECK_MSG(wide_hits > 0, "rays at four times the allowed angle do meet medium (the search would see it)");
}

enum { W = 41, H = 33, NC = 3 }; /* radiance, transparency, depth numerator */

/* The refinement on a clear field whose rays all carry clearance ratio `ratio`: returns the pixels
 * marched. */
static size_t run_clear(double spread, float ratio, int split_x, int split_y)
{
  sl__refine rf;
  CHECK(sl__refine_init(&rf, W, H, NC, 1, 0.1, spread));
  size_t marched = 0;
  for (size_t n = sl__refine_first(&rf); n; n = sl__refine_next(&rf)) {
    for (size_t i = 0; i < n; ++i) {
      const int q = rf.list[i];
      float *a = rf.acc + (size_t)q * NC;
      a[0] = 0.0f, a[1] = 1.0f, a[2] = 0.0f;
      rf.clear[q] = (q % W == split_x && q / W == split_y) ? 0.0f : ratio;
    }
    marched += n;
  }
  sl__refine_fill(&rf);
  int clear = 1;
  for (size_t q = 0; q < (size_t)W * H; ++q) clear &= rf.acc[q * NC] == 0.0f && rf.acc[q * NC + 1] == 1.0f;
  CHECK_MSG(clear, "a clear field is filled clear");
  sl__refine_free(&rf);
  return marched;
}

static size_t lattice_count(int step) { return refine_lattice_count(W, H, step); }

static void test_refine_rule(void)
{
  /* Spread 0.1 per pixel of spacing: blocks of 8 (rays 4 apart) need 0.4, blocks of 4 need 0.2. */
  const size_t n8 = run_clear(0.1, 0.5f, -1, -1), n4 = run_clear(0.1, 0.3f, -1, -1), n1 = run_clear(0.1, 0.15f, -1, -1);
  printf("clear field: ratio 0.5, 0.3, 0.15 against spread 0.1 march %zu, %zu, %zu pixels (lattices of 4, 2, 1: %zu, "
         "%zu, %zu)\n", n8, n4, n1, lattice_count(4), lattice_count(2), lattice_count(1));
  CHECK_MSG(n8 == lattice_count(4) && n4 == lattice_count(2) && n1 == lattice_count(1),
            "the clearance ratio against the spread times the rays' spacing decides the lattice marched");
  /* One ray without a bound at (12, 12): the blocks of 8 around it split, those of 4 holding it are
   * marched every pixel. */
  const size_t one = run_clear(0.1, 0.5f, 12, 12);
  CHECK_MSG(one > n8 && one < lattice_count(2), "a ray without a bound keeps only the blocks around it marched");
}

/* A large cloud and a one-sample cloud in a box seen from far: the lattice rays of a block of 8 lie
 * 2 to 3 cells apart there, so a one-sample cloud (2 cells across) may fall between them. */
static void test_march(void)
{
  const double lo[3] = {0, 0, 0}, hi[3] = {6400, 6400, 3200};
  sl_volume v;
  CHECK(make_box_volume(&v, 64, 64, 32, lo, hi, 1.0 / 1500.0) == 0);
  const double eta = 0.02 / sl_particle_properties(SL_CLOUD)->sigma_ext_m2;
  memset(v.eta[SL_CLOUD], 0, sl_volume_count(&v) * sizeof(float));
  for (int k = 4; k < 20; ++k)
    for (int j = 10; j < 30; ++j)
      for (int i = 8; i < 24; ++i) v.eta[SL_CLOUD][sl_volume_index(&v, i, j, k)] = (float)eta;
  const int small[][3] = {{45, 40, 12}, {50, 20, 20}, {38, 52, 8}, {56, 56, 24}};
  for (int s = 0; s < 4; ++s) v.eta[SL_CLOUD][sl_volume_index(&v, small[s][0], small[s][1], small[s][2])] = (float)eta;
  sl_scene sc = {.volume = &v, .light_volume = 1, .termination_transparency = 1e-6};
  sl_sun_direction(45.0, 210.0, sc.sun_direction);
  for (int c = 0; c < 3; ++c) sc.sun_irradiance[c] = 1.0;
  sl_camera cam = {.position = {3200, -30000, 1600}, .target = {3200, 3200, 1600}, .up = {0, 0, 1}, .fov_deg = 16,
                   .width = 161, .height = 129};
  sl_image every, adaptive;
  long n_every = 0, n_adaptive = 0;
  CHECK(render_counted(&sc, &cam, &every, &n_every) == 0);
  sc.march_refine_tolerance = 0.1;
  CHECK(render_counted(&sc, &cam, &adaptive, &n_adaptive) == 0);
  const size_t np = (size_t)cam.width * cam.height;
  size_t clear = 0, lost = 0, small_pixels = 0, small_same = 0;
  for (size_t q = 0; q < np; ++q) {
    if (adaptive.transparency[q] == 1.0f) {
      clear++;
      lost += every.transparency[q] != 1.0f;
    }
    /* The one-sample clouds stand alone: pixels whose ray per pixel meets medium, right of the big one. */
    if (every.transparency[q] < 1.0f && q % cam.width > 95) {
      small_pixels++;
      small_same += adaptive.transparency[q] == every.transparency[q];
    }
  }
  printf("march: %zu clear pixels, %zu of them with medium in a ray per pixel; the small clouds' %zu pixels, %zu the "
         "same; samples %ld against %ld\n", clear, lost, small_pixels, small_same, n_adaptive, n_every);
  CHECK_MSG(small_pixels > 0, "the small clouds show in a ray per pixel");
  CHECK_MSG(lost == 0, "wherever the adaptive frame is clear, a ray per pixel is clear");
  CHECK_MSG(small_same == small_pixels, "the small clouds' pixels are marched, as a ray per pixel marches them");
  CHECK_MSG(n_adaptive < n_every, "adaptive pixels take fewer samples");
  sl_image_free(&adaptive);
  sl_image_free(&every);
  sl_volume_free(&v);
}

int main(void)
{
  test_bound_against_brute_force();
  test_refine_rule();
  test_march();
  return sl_test_finish("test_clear_blocks");
}
