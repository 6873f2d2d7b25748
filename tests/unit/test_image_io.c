/* EXR round trips (float exactly, half within half precision), tone mapping limits, and the
 * comparison metric on images with known differences. */
#include <math.h>
#include <stdlib.h>
#include <unistd.h>

#include "sl_image_io.h"
#include "sl_testing.h"

int main(void)
{
  sl_error err = {0};
  sl_image a, b;
  CHECK(sl_image_alloc(&a, 37, 23, &err) == SL_OK);
  for (int i = 0; i < 37 * 23; ++i) {
    for (int c = 0; c < 4; ++c) a.rgba[4 * i + c] = (float)(0.001 * (i + 1) * (c + 1));
    a.depth[i] = i % 5 ? (float)(10.0 * i) : INFINITY;
  }
  char path[] = "/tmp/sl_test_image_XXXXXX.exr";
  int fd = mkstemps(path, 4);
  close(fd);
  CHECK(sl_write_exr(path, &a, SL_EXR_FLOAT, &err) == SL_OK);
  CHECK(sl_read_exr(path, &b, &err) == SL_OK);
  CHECK(b.width == 37 && b.height == 23);
  sl_image_metrics m;
  CHECK(sl_image_compare(&b, &a, &m, &err) == SL_OK);
  CHECK_CLOSE(m.relative_rmse, 0.0, 0.0, 0.0);
  int depth_ok = 1;
  for (int i = 0; i < 37 * 23; ++i) depth_ok &= (a.depth[i] == b.depth[i]) || (isinf(a.depth[i]) && isinf(b.depth[i]));
  CHECK_MSG(depth_ok, "float depth round-trips exactly, +inf included");
  sl_image_free(&b);
  CHECK(sl_write_exr(path, &a, SL_EXR_HALF, &err) == SL_OK);
  CHECK(sl_read_exr(path, &b, &err) == SL_OK);
  CHECK(sl_image_compare(&b, &a, &m, &err) == SL_OK);
  /* Half floats carry 11 significant bits: relative rounding error at most 2^-11. */
  CHECK(m.relative_rmse < 4.9e-4 && m.relative_rmse > 0.0);
  sl_image_free(&b);
  /* A truncated file is an error, not an image. */
  FILE *f = fopen(path, "r+b");
  fseek(f, 0, SEEK_END);
  const long size = ftell(f);
  fclose(f);
  CHECK(truncate(path, size / 2) == 0);
  sl_error_clear(&err);
  CHECK(sl_read_exr(path, &b, &err) != SL_OK);
  CHECK(err.message[0] != '\0');
  unlink(path);
  /* Comparison: b = a * 1.01 has relative RMSE 0.01 exactly. */
  sl_image_alloc(&b, 37, 23, &err);
  for (int i = 0; i < 4 * 37 * 23; ++i) b.rgba[i] = a.rgba[i] * 1.01f;
  sl_image_compare(&b, &a, &m, &err);
  CHECK_CLOSE(m.relative_rmse, 0.01, 1e-5, 0.0);
  /* Tone mapping: black stays black, huge radiance saturates, the curve is monotonic. */
  CHECK_CLOSE(sl_tonemap(0.0f, 10.0f), 0.0, 0.0, 1e-7);
  CHECK_CLOSE(sl_tonemap(1e6f, 10.0f), 1.0, 1e-6, 0.0);
  CHECK(sl_tonemap(0.02f, 10.0f) < sl_tonemap(0.03f, 10.0f));
  sl_image_free(&a);
  sl_image_free(&b);
  return sl_test_finish("test_image_io");
}
