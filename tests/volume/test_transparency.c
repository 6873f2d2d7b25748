/* Transparency through a homogeneous slab against exp(-tau) for tau from 1e-6 to 1e3, along the
 * axis and along oblique perspective rays. The sun is off and the sky is 1, so a pixel is the
 * volume's transparency along its ray. */
#include <math.h>

#include "homogeneous_reference.h"
#include "sl_testing.h"

int main(void)
{
  const double lo[3] = {-5000.0, -5000.0, 1000.0}, hi[3] = {5000.0, 5000.0, 1500.0};
  const double taus[] = {1e-6, 1e-4, 1e-2, 1.0, 10.0, 50.0, 1e3};
  for (size_t it = 0; it < sizeof taus / sizeof taus[0]; ++it) {
    const double tau = taus[it];
    const double beta = tau / (hi[2] - lo[2]);
    sl_volume v;
    CHECK(make_box_volume(&v, 8, 8, 3, lo, hi, beta) == 0);
    sl_scene sc = {.volume = &v, .sun_direction = {0.3, 0.2, 0.9}, .slices = 64};
    for (int c = 0; c < SL_CHANNELS; ++c) sc.sky_radiance[c] = 1.0;
    /* Camera 6 km above the slab looking straight down. */
    sl_camera cam = {.position = {0, 0, 7500}, .target = {0, 0, 0}, .up = {0, 1, 0}, .fov_deg = 60, .width = 9,
                     .height = 9};
    sl_image img;
    CHECK(render_frame(&sc, &cam, &img) == 0);
    box_medium m = {.beta = beta, .phase = 0.0, .albedo = 0.0};
    for (int a = 0; a < 3; ++a) m.lo[a] = lo[a], m.hi[a] = hi[a];
    const double tan_half = tan(30.0 * M_PI / 180.0);
    for (int py = 0; py < 9; py += 4)
      for (int px = 0; px < 9; px += 4) {
        /* The same pinhole model as the renderer: pixel centres on the image plane at distance 1. */
        const double sx = (2.0 * (px + 0.5) / 9 - 1.0) * tan_half, sy = (1.0 - 2.0 * (py + 0.5) / 9) * tan_half;
        double d[3] = {sx, -sy, -1.0}; /* right = +x, up = -(-y)... camera looks down -z with up +y */
        d[1] = sy;
        const double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int a = 0; a < 3; ++a) d[a] /= n;
        const double want = reference_transparency(&m, cam.position, d);
        const float got = img.rgba[4 * ((size_t)py * 9 + px)];
        if (tau >= 1e3) {
          CHECK_MSG(got < 1e-30f, "tau = 1e3 leaves no light");
        } else if (tau <= 1.0) {
          CHECK_CLOSE(got, want, 2e-6, 0.0);
        } else {
          /* Float accumulation: the optical depth is right to float precision, so exp(-tau) carries
           * a relative error of about tau * 1e-7. Compare optical depths. */
          CHECK_CLOSE(-log(got), -log(want), 2e-7, 0.0);
        }
      }
    sl_image_free(&img);
    sl_volume_free(&v);
  }
  return sl_test_finish("test_transparency");
}
