/* The renderer with the atmosphere (render/sky): distant cloud turns blue, low sun turns cloud
 * red, night gives darkness without NaN, and an empty or vanishing volume shows exactly the sky
 * (the front/back split at the midplane is seamless). */
#include <math.h>
#include <string.h>

#include "homogeneous_reference.h"
#include "sl_testing.h"

static sl_atmosphere atm;

/* Centre pixel's radiance for a 2 km cube of optical depth ~2, camera `distance` away looking
 * horizontally from the south at 3 km height, sun at `sun_el` degrees behind the camera. */
static void centre_pixel(double distance, double sun_el, double beta, double out[3], int *night)
{
  const double lo[3] = {-1000, -1000, 2000}, hi[3] = {1000, 1000, 4000};
  sl_volume v;
  make_box_volume(&v, 4, 4, 4, lo, hi, beta);
  sl_scene sc = {.volume = &v, .atmosphere = &atm, .slices = 128};
  sl_sun_direction(sun_el, 200.0, sc.sun_direction);
  sl_camera cam = {.position = {0, -distance, 3000}, .target = {0, 0, 3000}, .up = {0, 0, 1}, .fov_deg = 20,
                   .width = 9, .height = 9};
  sl_error err = {0};
  sl_renderer *r = sl_renderer_create(&sc, &err);
  sl_image layer, bg, frame;
  sl_image_alloc(&layer, 9, 9, &err);
  sl_image_alloc(&bg, 9, 9, &err);
  sl_image_alloc(&frame, 9, 9, &err);
  sl_render_stats st;
  sl_renderer_render(r, &cam, &layer, &st, &err);
  sl_renderer_background(r, &cam, &bg, &err);
  sl_image_over(&layer, &bg, &frame);
  for (int c = 0; c < 3; ++c) out[c] = frame.rgba[4 * (4 * 9 + 4) + c];
  *night = st.night;
  int finite = 1;
  for (int i = 0; i < 4 * 81; ++i) finite &= isfinite(frame.rgba[i]);
  CHECK_MSG(finite, "every pixel finite");
  sl_image_free(&layer);
  sl_image_free(&bg);
  sl_image_free(&frame);
  sl_renderer_destroy(r);
  sl_volume_free(&v);
}

int main(void)
{
  sl_error err = {0};
  CHECK(sl_atmosphere_init(&atm, sl_sky_rgb_wavelengths_nm, SL_SKY_RGB_COUNT, SL_EARTH_ROUND,
                           SL_RAYLEIGH_BODHAINE1999, &err) == SL_OK);
  int night;
  double near[3], far[3];
  centre_pixel(5e3, 40.0, 1e-3, near, &night);
  centre_pixel(80e3, 40.0, 1e-3, far, &night);
  printf("cloud at 5 km: rgb %.4g %.4g %.4g (B/R %.3f); at 80 km: %.4g %.4g %.4g (B/R %.3f)\n", near[0], near[1],
         near[2], near[2] / near[0], far[0], far[1], far[2], far[2] / far[0]);
  CHECK_MSG(far[2] / far[0] > 1.2 * near[2] / near[0], "aerial perspective: distant cloud is bluer");

  double low[3], high[3];
  centre_pixel(10e3, 2.0, 1e-3, low, &night);
  CHECK(!night);
  centre_pixel(10e3, 60.0, 1e-3, high, &night);
  printf("sun at 2 deg: R/B %.3f; at 60 deg: R/B %.3f\n", low[0] / low[2], high[0] / high[2]);
  CHECK_MSG(low[0] / low[2] > 1.5 * high[0] / high[2], "low sun reddens the sunlit cloud");

  double dark[3];
  centre_pixel(10e3, -5.0, 1e-3, dark, &night);
  CHECK(night);
  CHECK_CLOSE(dark[0] + dark[1] + dark[2], 0.0, 0.0, 0.0);

  /* An empty box and a vanishing one show the whole-ray sky: no seam at the midplane split. */
  double empty[3], faint[3];
  centre_pixel(10e3, 30.0, 0.0, empty, &night);
  centre_pixel(10e3, 30.0, 1e-12, faint, &night);
  double sky[3];
  sl_sky_view view;
  const double eye[3] = {0, -10e3, 3000}, dir[3] = {0, 1, 0};
  double sun[3];
  sl_sun_direction(30.0, 200.0, sun);
  sl_sky_view_init(&view, &atm, eye, sun, &err);
  sl_sky_view_segment(&view, dir, 0.0, INFINITY, sky, NULL);
  for (int c = 0; c < 3; ++c) {
    CHECK_CLOSE(empty[c], sky[c], 1e-6, 0.0);
    CHECK_CLOSE(faint[c], sky[c], 1e-5, 0.0);
  }
  return sl_test_finish("test_aerial");
}
