/* Grid shapes: 1x1x1, 1xNxN and very flat WRF-like aspect ratios render finite images that
 * agree with direct quadrature for a homogeneous medium. */
#include <math.h>
#include <string.h>

#include "homogeneous_reference.h"
#include "sl_testing.h"

static void check_shape(const char *name, int nx, int ny, int nz, const double lo[3], const double hi[3],
                        double beta, const double cam_pos[3], int texels)
{
  sl_volume v;
  CHECK(make_box_volume(&v, nx, ny, nz, lo, hi, beta) == 0);
  double sun[3] = {0.4, -0.3, 0.8};
  const double n = sqrt(sun[0] * sun[0] + sun[1] * sun[1] + sun[2] * sun[2]);
  for (int a = 0; a < 3; ++a) sun[a] /= n;
  sl_scene sc = {.volume = &v, .slices = 0, .light_resolution = texels};
  memcpy(sc.sun_direction, sun, sizeof sun);
  for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0, sc.sky_radiance[c] = 0.0;
  sl_camera cam = {.up = {0, 0, 1}, .fov_deg = 50, .width = 17, .height = 17};
  memcpy(cam.position, cam_pos, 3 * sizeof(double));
  for (int a = 0; a < 3; ++a) cam.target[a] = 0.5 * (lo[a] + hi[a]);
  sl_image img;
  CHECK(render_frame(&sc, &cam, &img) == 0);
  int finite = 1;
  for (size_t i = 0; i < 4 * (size_t)17 * 17; ++i) finite &= isfinite(img.rgba[i]);
  CHECK_MSG(finite, name);
  /* The centre pixel looks through the box's centre. */
  double d[3];
  for (int a = 0; a < 3; ++a) d[a] = cam.target[a] - cam.position[a];
  const double dn = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (int a = 0; a < 3; ++a) d[a] /= dn;
  box_medium m = {.beta = beta, .phase = 1.0 / (4.0 * M_PI), .albedo = 1.0};
  memcpy(m.lo, lo, sizeof m.lo);
  memcpy(m.hi, hi, sizeof m.hi);
  const double want = reference_radiance(&m, cam.position, d, sun, 0.0, 20000);
  const double got = img.rgba[4 * (8 * 17 + 8)];
  printf("%-28s centre radiance %.6e, quadrature %.6e, relative error %.2e\n", name, got, want,
         fabs(got - want) / want);
  CHECK_CLOSE(got, want, 0.02, 0.0);
  sl_image_free(&img);
  sl_volume_free(&v);
}

int main(void)
{
  {
    const double lo[3] = {-500, -500, 0}, hi[3] = {500, 500, 1000}, cam[3] = {-1500, -3000, 1800};
    check_shape("1x1x1", 1, 1, 1, lo, hi, 2e-3, cam, 2048);
  }
  {
    const double lo[3] = {-10, -4000, 0}, hi[3] = {10, 4000, 8000}, cam[3] = {-9000, -6000, 5000};
    check_shape("1xNxN (one cell thick)", 1, 40, 40, lo, hi, 5e-4, cam, 2048);
  }
  {
    /* 400 km x 400 km x 6 km, 48 x 48 x 14 cells: Katrina's shape. */
    const double lo[3] = {-200e3, -200e3, 0}, hi[3] = {200e3, 200e3, 6000}, cam[3] = {-30e3, -420e3, 60e3};
    check_shape("flat 48x48x14 (WRF-like)", 48, 48, 14, lo, hi, 1e-5, cam, 2048);
  }
  {
    /* 100 m thick and 100 km wide: a light texel of 2048 spans about half the layer's depth along
     * the sunlight, and ln I interpolated between a texel whose ray runs above the top and one
     * inside it (the light buffer's error at a surface the sun meets at 58 degrees) leaves the
     * slicer dark: at 4096 slices 2.5 % at 2048 texels and 0.85 % at 4096; at the automatic slices
     * 2.1 %, 0.73 % and 0.16 % at 2048, 4096 and 8192. At 4096 texels the case tests the grid's
     * shape, not the buffer. */
    const double lo[3] = {-50e3, -50e3, 1000}, hi[3] = {50e3, 50e3, 1100}, cam[3] = {0, -120e3, 20e3};
    check_shape("very flat 200x200x2", 200, 200, 2, lo, hi, 5e-3, cam, 4096);
  }
  return sl_test_finish("test_grids");
}
