/* EXR round trips (float exactly, half within half precision), tone mapping limits, and the
 * comparison metric on images with known differences. */
#include <math.h>
#include <stdlib.h>
#include <unistd.h>

#include <openexr.h>

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
  /* Camera matrices: the target lands at NDC (0, 0) in front of the camera, a point on the upper
   * edge of the field of view at y = 1, and the matrices are written into the header. */
  {
    sl_exr_metadata meta = {0};
    const double pos[3] = {100, -2000, 300}, target[3] = {100, 0, 300}, up[3] = {0, 0, 1};
    sl_exr_camera_matrices(pos, target, up, 40.0, 1.5, 1.0, 1e6, &meta);
    const double pts[2][3] = {{100, 0, 300}, {100, 0, 300 + 2000 * tan(20 * M_PI / 180)}};
    for (int k = 0; k < 2; ++k) {
      double h[4] = {0};
      const double p4[4] = {pts[k][0], pts[k][1], pts[k][2], 1.0};
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) h[j] += p4[i] * meta.world_to_ndc[4 * i + j];
      CHECK_CLOSE(h[0] / h[3], 0.0, 0.0, 1e-6);
      CHECK_CLOSE(h[1] / h[3], k == 0 ? 0.0 : 1.0, 1e-5, 1e-6);
      double zc = 0.0;
      for (int i = 0; i < 4; ++i) zc += p4[i] * meta.world_to_camera[4 * i + 2];
      CHECK_CLOSE(zc, -2000.0, 1e-6, 0.0);
    }
    meta.has_sun = 1;
    meta.sun_direction[2] = 1.0f;
    meta.scene = "{\"test\":1}";
    CHECK(sl_write_exr_meta(path, &a, SL_EXR_HALF, &meta, &err) == SL_OK);
    exr_context_t ctx;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    CHECK(exr_start_read(&ctx, path, &init) == EXR_ERR_SUCCESS);
    exr_attr_m44f_t m;
    CHECK(exr_attr_get_m44f(ctx, 0, "worldToNDC", &m) == EXR_ERR_SUCCESS);
    CHECK_CLOSE(m.m[5], meta.world_to_ndc[5], 0.0, 0.0);
    exr_attr_v3f_t v;
    CHECK(exr_attr_get_v3f(ctx, 0, "sunDirection", &v) == EXR_ERR_SUCCESS);
    CHECK_CLOSE(v.z, 1.0, 0.0, 0.0);
    exr_finish(&ctx);
    unlink(path);
  }
  sl_image_free(&a);
  sl_image_free(&b);
  return sl_test_finish("test_image_io");
}
