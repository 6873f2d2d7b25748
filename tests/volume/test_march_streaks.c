/* The light-volume march on a thick face: a dense core (mean free path 20 m, a fifth of a cell)
 * inside a box of thin air, seen obliquely, so that each ray's span through the box changes from
 * pixel to pixel and its step count changes every pixel or two. The faces' surfaces lie within a
 * step, so their brightness depends on where the samples fall: the samples must not move when the
 * span does (sl_march_step_end). The faces are lit smoothly at the pixel scale, so the median of a
 * row's relative second difference over them measures streaks. Measured 2.1e-5 at 2 samples per
 * cell and 2.5e-5 at 8; steps stretched to fit each span gave 1.4e-3 and 2.0e-4 (speckle along
 * the lower front face). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homogeneous_reference.h"
#include "sl_testing.h"

static int by_value(const void *a, const void *b)
{
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The median of |I[x-1] - 2 I[x] + I[x+1]| / I[x] over pixels whose row neighbours are all opaque
 * core (transparency below 1e-3): the median, so that the few pixels on the edges between faces
 * (a true kink) do not count, while streaks, which cross every row, do. */
static double face_structure(const sl_image *img, int *count)
{
  double *r = malloc((size_t)img->width * img->height * sizeof *r);
  int n = 0;
  for (int y = 0; y < img->height; ++y)
    for (int x = 1; x + 1 < img->width; ++x) {
      const size_t q = (size_t)y * img->width + x;
      if (!(img->transparency[q - 1] < 1e-3f && img->transparency[q] < 1e-3f && img->transparency[q + 1] < 1e-3f))
        continue;
      const double le = img->rgba[4 * (q - 1)], c = img->rgba[4 * q], ri = img->rgba[4 * (q + 1)];
      r[n++] = fabs(le - 2.0 * c + ri) / c;
    }
  qsort(r, n, sizeof *r, by_value);
  const double median = n ? r[n / 2] : INFINITY;
  free(r);
  *count = n;
  return median;
}

int main(void)
{
  const double lo[3] = {-2000, -1500, 500}, hi[3] = {2000, 1500, 2500};
  sl_volume v;
  CHECK(make_box_volume(&v, 40, 30, 20, lo, hi, 1.0 / 1500.0) == 0);
  const float air = v.eta[SL_CLOUD][0] * 0.1f, core = v.eta[SL_CLOUD][0] * 75.0f; /* 1/20 m^-1 */
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 30; ++j)
      for (int i = 0; i < 40; ++i)
        v.eta[SL_CLOUD][sl_volume_index(&v, i, j, k)] =
            i >= 12 && i < 28 && j >= 8 && j < 22 && k >= 4 && k < 16 ? core : air;
  sl_scene sc = {.volume = &v, .light_volume = 1, .termination_transparency = 1e-6};
  sl_sun_direction(40.0, 200.0, sc.sun_direction);
  for (int c = 0; c < 3; ++c) sc.sun_irradiance[c] = 1.0;
  sl_camera cam = {.position = {2500, -7000, 3500}, .target = {0, 0, 1500}, .up = {0, 0, 1}, .fov_deg = 24,
                   .width = 120, .height = 90};
  double structure[2];
  int count[2];
  const int samples[2] = {2, 8};
  for (int s = 0; s < 2; ++s) {
    sl_image img;
    long n = 0;
    sc.march_samples = samples[s];
    CHECK(render_counted(&sc, &cam, &img, &n) == 0);
    structure[s] = face_structure(&img, &count[s]);
    printf("%d samples per cell: %d face pixels, structure %.3e\n", samples[s], count[s], structure[s]);
    sl_image_free(&img);
  }
  CHECK_MSG(count[0] > 1500, "the core's faces fill much of the frame");
  CHECK_MSG(structure[0] < 1e-4, "no streaks on a thick face at 2 samples per cell");
  CHECK_MSG(structure[1] < 1e-4, "no streaks on a thick face at 8 samples per cell");
  sl_volume_free(&v);
  return sl_test_finish("test_march_streaks");
}
