/* Adaptive pixels (render/volume/pixel_refine.h, sl_scene.march_refine_tolerance). The schedule on
 * fields whose curvature is known: a bilinear field is interpolated exactly from every fourth pixel;
 * on a paraboloid a(x^2 + y^2) a block's centre misses its corners' mean by a S^2 / 2, so the
 * tolerance decides the lattice that is marched and the fill's error is at most a h^2 / 2 at the
 * marched spacing h. A dim bowl is judged against the frame's scale: split alone, interpolated
 * beside bright cloud. A clear ray, an opaque surface and a NaN keep their blocks marched; the
 * blocks ending on the image's edges are judged and filled as the others. Then the light-volume
 * march through a thin homogeneous box: within the tolerance of a ray per pixel, fewer samples, the
 * same image on one thread and two, and tolerances outside 0..1 refused. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "homogeneous_reference.h"
#include "pixel_refine.h"
#include "refine_lattice.h"
#include "sl_testing.h"

enum { W = 67, H = 45, NC = 3 }; /* radiance, transparency, depth numerator */

enum { NO_DIM, DIM_ALONE, DIM_BESIDE_BRIGHT };

typedef struct field {
  double a;         /* the paraboloid's curvature (0: the bilinear field) */
  int dim;          /* a dim paraboloid 0.01 (1 + a r^2) about (48, 20): alone, or right of a
                       plateau of 1 (x <= 32) */
  int clear_x, clear_y, nan_x, nan_y; /* a ray that met nothing, a NaN (-1: none) */
} field;

static void field_at(const field *fd, int x, int y, float *out)
{
  const double dx = x - 30, dy = y - 20;
  double value = fd->a > 0 ? 1.0 + fd->a * (dx * dx + dy * dy) : 1.0 + 0.01 * x + 0.02 * y + 3e-4 * x * y;
  if (fd->dim) {
    const double ex = x - 48;
    value = fd->dim == DIM_BESIDE_BRIGHT && x <= 32 ? 1.0 : 0.01 * (1.0 + fd->a * (ex * ex + dy * dy));
  }
  out[0] = (float)value;
  out[1] = 0.5f;
  out[2] = (float)(1000.0 * value);
  if (x == fd->clear_x && y == fd->clear_y) out[0] = 0.0f, out[1] = 1.0f, out[2] = 0.0f;
  if (x == fd->nan_x && y == fd->nan_y) out[0] = NAN;
}

/* Runs the schedule as the march does, the "march" being the field; returns the pixels marched. */
static size_t run(sl__refine *rf, const field *fd)
{
  size_t marched = 0;
  for (size_t n = sl__refine_first(rf); n; n = sl__refine_next(rf)) {
    for (size_t i = 0; i < n; ++i) {
      const int q = rf->list[i];
      field_at(fd, q % W, q / W, rf->acc + (size_t)q * NC);
    }
    marched += n;
  }
  sl__refine_fill(rf);
  return marched;
}

static size_t lattice_count(int step) { return refine_lattice_count(W, H, step); }

static double worst_fill_error(const sl__refine *rf, const field *fd)
{
  double worst = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      float want[NC];
      field_at(fd, x, y, want);
      worst = fmax(worst, fabs(rf->acc[((size_t)y * W + x) * NC] - want[0]));
    }
  return worst;
}

int main(void)
{
  sl__refine rf;
  CHECK(sl__refine_init(&rf, W, H, NC, 1, 1e-4, 0.0));
  CHECK_MSG(rf.x.n == 9 && rf.x.origin[7] == 56 && rf.x.origin[8] == 58 && rf.y.n == 6 && rf.y.origin[4] == 32 &&
                rf.y.origin[5] == 36,
            "67 x 45: blocks of 8 from 0, then a last column and row of blocks ending on the image's edges");

  /* A bilinear field: every block's halfway points lie on its corners' interpolation. */
  field bilinear = {.a = 0, .clear_x = -1, .clear_y = -1, .nan_x = -1, .nan_y = -1};
  size_t n = run(&rf, &bilinear);
  printf("bilinear: %zu of %d marched (every 4th pixel: %zu), worst fill error %.2e\n", n, W * H, lattice_count(4),
         worst_fill_error(&rf, &bilinear));
  CHECK_MSG(n == lattice_count(4), "a bilinear field: only every fourth pixel (the edges' blocks too) is marched");
  CHECK_MSG(worst_fill_error(&rf, &bilinear) < 1e-5, "a bilinear field is filled exactly (float rounding)");
  sl__refine_free(&rf);

  /* The paraboloid 1 + a r^2 (values 1..2): a block of S misses at its centre by a S^2 / 2 and at
   * its edges by a S^2 / 4, relative to values between 1 and 2. */
  const double a = 1.0 / 2000.0;
  field bowl = {.a = a, .clear_x = -1, .clear_y = -1, .nan_x = -1, .nan_y = -1};
  const struct {
    double tol;
    int step; /* the lattice marched */
  } cases[] = {{0.02, 4},   /* S 8: centre 0.016 relative at most: smooth */
               {0.005, 2},  /* S 8: 0.008 at least, splits; S 4: 0.004 at most, smooth */
               {0.001, 1}}; /* S 4: edges 0.001..0.002, centre 0.002..0.004: splits */
  for (int c = 0; c < 3; ++c) {
    CHECK(sl__refine_init(&rf, W, H, NC, 1, cases[c].tol, 0.0));
    n = run(&rf, &bowl);
    const double h = cases[c].step, err = worst_fill_error(&rf, &bowl);
    printf("paraboloid, tolerance %g: %zu marched (lattice of %d: %zu), worst fill error %.3e (bound a h^2/2 = "
           "%.3e)\n", cases[c].tol, n, cases[c].step, lattice_count(cases[c].step), err, 0.5 * a * h * h);
    CHECK_MSG(n == lattice_count(cases[c].step), "the tolerance against the known curvature decides the lattice");
    CHECK_MSG(err <= 0.5 * a * h * h * 1.001 + 1e-6, "the fill's error is the bilinear bound a h^2 / 2");
    sl__refine_free(&rf);
  }

  /* The frame's scale. A dim paraboloid of the same curvature relative to its values, 1 % of the
   * bright one's: alone, at 0.005, its blocks of 8 split (0.016 relative at S 8, as above). Right of
   * a plateau of 1, the frame's scale (the mean of the first list's rays) is about half the
   * plateau, against which the same misses are tiny: its blocks of 8 (x 40..64) are interpolated
   * from every fourth pixel, within 1 % of the bright bowl's bound, far inside the tolerance
   * against the scale. */
  for (int beside = 0; beside < 2; ++beside) {
    field dim = {.a = a, .dim = beside ? DIM_BESIDE_BRIGHT : DIM_ALONE, .clear_x = -1, .clear_y = -1, .nan_x = -1,
                 .nan_y = -1};
    CHECK(sl__refine_init(&rf, W, H, NC, 1, 0.005, 0.0));
    run(&rf, &dim);
    int off_lattice = 0;
    double err = 0.0;
    for (int y = 0; y <= 40; ++y)
      for (int x = 41; x < 64; ++x) {
        off_lattice += rf.marched[y * W + x] && !(refine_on_lattice(x, W, 4) && refine_on_lattice(y, H, 4));
        float want[NC];
        field_at(&dim, x, y, want);
        err = fmax(err, fabs(rf.acc[((size_t)y * W + x) * NC] - want[0]));
      }
    const double bound = 0.01 * 0.5 * a * 16;
    printf("dim paraboloid %s: %d pixels off the 4-lattice marched in x 41..63, worst fill error %.2e (bound "
           "0.01 a 4^2/2 = %.2e)\n", beside ? "beside a plateau of 1" : "alone", off_lattice, err, bound);
    if (beside)
      CHECK_MSG(off_lattice == 0 && err <= bound * 1.001 + 1e-7,
                "dim cloud beside bright: judged against the frame's scale, interpolated from every 4th pixel");
    else CHECK_MSG(off_lattice > 0, "the same dim bowl alone: its own scale, so its blocks of 8 split");
    sl__refine_free(&rf);
  }

  /* A clear ray at (16, 16) and a NaN at (44, 28): every block holding one splits down to its
   * pixels; an opaque surface at (13, 10) likewise. */
  field marks = {.a = 0, .clear_x = 16, .clear_y = 16, .nan_x = 44, .nan_y = 28};
  CHECK(sl__refine_init(&rf, W, H, NC, 1, 1e-4, 0.0));
  rf.hard[10 * W + 13] = 1;
  run(&rf, &marks);
  int kept = 1;
  for (int y = 12; y <= 20; ++y)
    for (int x = 12; x <= 20; ++x) kept &= rf.marched[y * W + x]; /* the 4-blocks around the clear ray */
  for (int y = 24; y <= 32; ++y)
    for (int x = 40; x <= 48; ++x) kept &= rf.marched[y * W + x];
  for (int y = 8; y <= 12; ++y)
    for (int x = 12; x <= 16; ++x) kept &= rf.marched[y * W + x];
  CHECK_MSG(kept, "blocks holding a clear ray, a NaN or an opaque surface have every pixel marched");
  CHECK_MSG(!rf.marched[2 * W + 2] && !rf.marched[30 * W + 3],
            "blocks away from them are interpolated (a bilinear field)");
  CHECK_MSG(!rf.marched[2 * W + 65] && !rf.marched[42 * W + 2] && !rf.marched[43 * W + 65],
            "the blocks ending on the image's edges are interpolated as the others (a bilinear field)");
  sl__refine_free(&rf);

  /* The march through a thin homogeneous box (test_thin_steps's), a ray per pixel against adaptive
   * pixels. */
  const double lo[3] = {-2000, -1500, 500}, hi[3] = {2000, 1500, 2500};
  sl_volume v;
  CHECK(make_box_volume(&v, 40, 30, 20, lo, hi, 1.0 / 1500.0) == 0);
  sl_scene sc = {.volume = &v, .light_volume = 1, .termination_transparency = 1e-6};
  sl_sun_direction(45.0, 210.0, sc.sun_direction);
  for (int c = 0; c < 3; ++c) sc.sun_irradiance[c] = 1.0;
  /* Face on, every pixel inside the box's front face. */
  sl_camera cam = {.position = {0, -8000, 1500}, .target = {0, 0, 1500}, .up = {0, 0, 1}, .fov_deg = 16,
                   .width = 81, .height = 61};
  sl_image every, adaptive, one;
  long n_every = 0, n_adaptive = 0, n_one = 0;
  CHECK(render_counted(&sc, &cam, &every, &n_every) == 0);
  const double tol = 0.02;
  sc.march_refine_tolerance = tol;
  CHECK(render_counted(&sc, &cam, &adaptive, &n_adaptive) == 0);
  double worst = 0.0, worst_t = 0.0;
  const size_t np = (size_t)cam.width * cam.height;
  for (size_t q = 0; q < np; ++q) {
    worst_t = fmax(worst_t, fabs(adaptive.transparency[q] - every.transparency[q]));
    for (int c = 0; c < 3; ++c) {
      const double want = every.rgba[4 * q + c];
      if (want > 0) worst = fmax(worst, fabs(adaptive.rgba[4 * q + c] - want) / want);
    }
  }
  printf("thin box, tolerance %g: worst relative difference %.3e, transparency %.3e; samples %ld against %ld\n", tol,
         worst, worst_t, n_adaptive, n_every);
  /* Measured 5.6e-3 and 2.3e-5: the test at the coarser spacing is about four times the fill's error. */
  CHECK_MSG(worst <= tol && worst_t <= tol, "adaptive pixels within the tolerance of a ray per pixel");
  CHECK_MSG(3 * n_adaptive < n_every, "adaptive pixels take under a third of the samples through a smooth box");
  /* (Measured 28 %; at 0.05 the sixteenth of the rays on the coarsest lattice, 14 %.) */
  omp_set_num_threads(1);
  CHECK(render_counted(&sc, &cam, &one, &n_one) == 0);
  omp_set_num_threads(2);
  CHECK_MSG(n_one == n_adaptive && memcmp(one.rgba, adaptive.rgba, 4 * np * sizeof(float)) == 0,
            "adaptive pixels: one thread and two give the same image");
  sl_image_free(&one);
  sl_image_free(&adaptive);
  sl_image_free(&every);

  const double tols[] = {-0.1, 0.0, 0.5, 1.0, 1.5, NAN};
  for (int i = 0; i < 6; ++i) {
    sl_scene bad = sc;
    bad.march_refine_tolerance = tols[i];
    CHECK_MSG(renderer_accepts(&bad) == (tols[i] >= 0.0 && tols[i] <= 1.0), "refinement tolerances are taken in 0..1 only");
  }
  sl_volume_free(&v);
  return sl_test_finish("test_pixel_refine");
}
