/* Output does not depend on the number of threads: every pixel and light texel is computed by
 * one thread from shared read-only data, so images must be bitwise identical. The skylight's lattice
 * (built by each thread count anew: one renderer per count) sums its directions in their order. */
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "sl_renderer.h"
#include "sl_storm.h"
#include "sl_testing.h"

int main(void)
{
  const char *dir = getenv("SL_DATASETS_DIR");
  char path[4096];
  snprintf(path, sizeof path, "%s/cumulonimbus.nc", dir ? dir : "datasets");
  sl_error err = {0};
  sl_storm_frame frame;
  sl_load_options lo = {.time_index = 0};
  if (!CHECK(sl_storm_load(path, &lo, &frame, &err) == SL_OK)) {
    fprintf(stderr, "%s\n", err.message);
    return sl_test_finish("test_threads");
  }
  sl_scene sc = {.volume = &frame.volume, .slices = 96, .skylight = 1};
  sl_sun_direction(35.0, 240.0, sc.sun_direction);
  for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0, sc.sky_radiance[c] = 0.1 * (c + 1);
  sl_renderer *r = sl_renderer_create(&sc, &err);
  CHECK(r != NULL);
  double blo[3], bhi[3];
  sl_renderer_content_bounds(r, blo, bhi);
  sl_renderer_destroy(r);
  sl_camera cam;
  sl_camera_frame(blo, bhi, 200.0, 12.0, 40.0, 96, 80, &cam);
  /* 8 threads on this project's 2 cores: most are descheduled at any time, and their tiles taken
   * by the others (tiles.h), differently from run to run. */
  sl_image img[4];
  const int threads[4] = {1, 2, 3, 8};
  for (int i = 0; i < 4; ++i) {
    omp_set_num_threads(threads[i]);
    sl_image_alloc(&img[i], cam.width, cam.height, &err);
    r = sl_renderer_create(&sc, &err);
    CHECK(r != NULL && sl_renderer_render(r, &cam, &img[i], NULL, &err) == SL_OK);
    sl_renderer_destroy(r);
  }
  const size_t n = (size_t)cam.width * cam.height;
  CHECK_MSG(memcmp(img[0].rgba, img[1].rgba, 4 * n * sizeof(float)) == 0, "1 and 2 threads give the same image");
  CHECK_MSG(memcmp(img[0].rgba, img[2].rgba, 4 * n * sizeof(float)) == 0, "1 and 3 threads give the same image");
  CHECK_MSG(memcmp(img[0].rgba, img[3].rgba, 4 * n * sizeof(float)) == 0, "1 and 8 threads give the same image");
  CHECK_MSG(memcmp(img[0].depth, img[1].depth, n * sizeof(float)) == 0, "depth does not depend on threads");
  double sum = 0.0;
  for (size_t i = 0; i < n; ++i) sum += img[0].rgba[4 * i + 3];
  CHECK_MSG(sum > 0.05 * n, "the storm covers part of the frame");
  for (int i = 0; i < 4; ++i) sl_image_free(&img[i]);
  sl_storm_frame_free(&frame);
  return sl_test_finish("test_threads");
}
