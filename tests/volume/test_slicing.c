/* Slicing geometry and compositing order for eye-sun angles 0, 45, 90, 135, 179.9 and exactly
 * 180 degrees: the half vector, the order, and the rendered single scattering of a homogeneous
 * box against direct quadrature along each pixel's ray (homogeneous_reference.c). */
#include <math.h>
#include <string.h>

#include "homogeneous_reference.h"
#include "sl_testing.h"

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Worst relative error over a grid of pixels that see the box, for a sun at `angle` degrees from
 * the view direction (rotated about the camera's up axis). */
static double render_error(double angle_deg, int slices, int *back_to_front)
{
  const double lo[3] = {-2000, -1500, 500}, hi[3] = {2000, 1500, 2500};
  const double beta = 1.0 / 1500.0; /* optical depth of order one across the box */
  sl_volume v;
  make_box_volume(&v, 6, 5, 4, lo, hi, beta);
  const double view[3] = {0.0, 1.0, 0.0};
  const double a = angle_deg * M_PI / 180.0;
  /* Toward the sun: the view direction rotated by `angle` toward +x and lifted a little in z so the
   * light enters through the top as well as the sides (except at exactly 0 and 180 degrees). */
  double sun[3] = {sin(a), cos(a), 0.0};
  if (angle_deg > 0.0 && angle_deg < 180.0) {
    sun[2] = 0.25 * sin(a);
    const double n = sqrt(dot(sun, sun));
    for (int i = 0; i < 3; ++i) sun[i] /= n;
  }
  sl_slicing sl;
  sl_choose_slicing(view, sun, &sl);
  *back_to_front = sl.back_to_front;
  sl_scene sc = {.volume = &v, .slices = slices, .light_resolution = 512};
  memcpy(sc.sun_direction, sun, sizeof sun);
  for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0;
  sl_camera cam = {.position = {0, -9000, 1500}, .target = {0, 0, 1500}, .up = {0, 0, 1}, .fov_deg = 30, .width = 33,
                   .height = 33};
  sl_image img;
  render_frame(&sc, &cam, &img);
  box_medium m = {.beta = beta, .phase = 1.0 / (4.0 * M_PI), .albedo = 1.0};
  memcpy(m.lo, lo, sizeof lo);
  memcpy(m.hi, hi, sizeof hi);
  const double right[3] = {1, 0, 0}, up[3] = {0, 0, 1};
  const double tan_half = tan(15.0 * M_PI / 180.0);
  double worst = 0.0;
  for (int py = 2; py < 33; py += 5)
    for (int px = 2; px < 33; px += 5) {
      const double sx = (2.0 * (px + 0.5) / 33 - 1.0) * tan_half, sy = (1.0 - 2.0 * (py + 0.5) / 33) * tan_half;
      double d[3];
      for (int i = 0; i < 3; ++i) d[i] = view[i] + sx * right[i] + sy * up[i];
      const double n = sqrt(dot(d, d));
      for (int i = 0; i < 3; ++i) d[i] /= n;
      const double want = reference_radiance(&m, cam.position, d, sun, 0.0, 4000);
      const double got = img.rgba[4 * ((size_t)py * 33 + px)];
      if (want < 1e-4 * m.phase) continue; /* a pixel beside the box */
      const double e = fabs(got - want) / want;
      if (e > worst) worst = e;
    }
  sl_image_free(&img);
  sl_volume_free(&v);
  return worst;
}

int main(void)
{
  const double angles[] = {0.0, 45.0, 90.0, 135.0, 179.9, 180.0};
  const double view[3] = {0.0, 1.0, 0.0};
  for (size_t i = 0; i < sizeof angles / sizeof angles[0]; ++i) {
    const double a = angles[i] * M_PI / 180.0;
    double sun[3] = {sin(a), cos(a), 0.0};
    /* Exact zeros where the angle makes them (cos(pi/2) is 6e-17 in floating point). */
    for (int k = 0; k < 3; ++k)
      if (fabs(sun[k]) < 1e-15) sun[k] = 0.0;
    sl_slicing sl;
    sl_choose_slicing(view, sun, &sl);
    const double p[3] = {-sun[0], -sun[1], -sun[2]};
    CHECK_CLOSE(dot(sl.half_vector, sl.half_vector), 1.0, 1e-12, 0.0);
    /* Slices advance with the light: the half vector has a positive component along it. */
    CHECK(dot(sl.half_vector, p) > 0.5);
    CHECK_CLOSE(sl.eye_sun_angle_deg, angles[i], 1e-9, 1e-9);
    /* Looking toward the sun (eye-sun angle below 90) flips the view vector: back to front. */
    CHECK(sl.back_to_front == (angles[i] < 90.0));
    /* The half vector bisects the (possibly flipped) view vector and the light direction. */
    const double sign = sl.back_to_front ? -1.0 : 1.0;
    const double hv = sign * dot(sl.half_vector, view), hp = dot(sl.half_vector, p);
    CHECK_CLOSE(hv, hp, 1e-12, 1e-12);
  }
  /* Rendered radiance against quadrature, and convergence as slices double. */
  for (size_t i = 0; i < sizeof angles / sizeof angles[0]; ++i) {
    int b2f_coarse, b2f_fine;
    const double coarse = render_error(angles[i], 128, &b2f_coarse);
    const double fine = render_error(angles[i], 512, &b2f_fine);
    printf("eye-sun angle %6.1f deg (%s): worst relative error %.3e at 128 slices, %.3e at 512\n", angles[i],
           b2f_fine ? "back to front" : "front to back", coarse, fine);
    CHECK(b2f_coarse == b2f_fine);
    CHECK_MSG(fine < 0.02, "within 2% of quadrature at 512 slices");
    /* Below 1e-3 the error is the light buffer's interpolation floor (fixed 512 texels), not the
     * slicing, and need not shrink further with slices. */
    CHECK_MSG(fine <= coarse * 1.05 || fine < 1e-3, "error does not grow with more slices");
  }
  return sl_test_finish("test_slicing");
}
