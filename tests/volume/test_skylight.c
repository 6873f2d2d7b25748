/* Skylight on the volume (render/volume/sky_light.h) against closed forms, with the sun off and a
 * constant sky of radiance L in every direction (no atmosphere), in both eye passes:
 *  - an optically thin isotropic cloud scatters L omega (1 - e^-tau) -> L tau omega toward the eye
 *    (single scattering of a uniform radiance field with any normalised phase function), to 1 %;
 *  - a conservative cloud of any optical depth inside a uniform sky is invisible: the frame is L
 *    on and off the cloud (the radiance field L everywhere solves the transfer equation), to 1 %;
 *  - with skylight off the volume sends nothing (the paper's model: the sun alone). */
#include <math.h>

#include "homogeneous_reference.h"
#include "sl_testing.h"

static const double kSky[3] = {0.2, 0.5, 1.0};

/* The volume layer (radiance premultiplied, transparency) and the frame over the sky. */
static int render_layers(const sl_scene *sc, const sl_camera *cam, sl_image *layer, sl_image *frame)
{
  sl_error err = {0};
  sl_renderer *r = sl_renderer_create(sc, &err);
  if (!r) return 1;
  sl_image bg;
  int rc = sl_image_alloc(layer, cam->width, cam->height, &err) || sl_image_alloc(&bg, cam->width, cam->height, &err) ||
           sl_image_alloc(frame, cam->width, cam->height, &err);
  if (!rc) rc = sl_renderer_render(r, cam, layer, NULL, &err) || sl_renderer_background(r, cam, &bg, &err);
  if (!rc) sl_image_over(layer, &bg, frame);
  sl_image_free(&bg);
  sl_renderer_destroy(r);
  return rc;
}

static void unit_ray(const sl_camera *cam, int px, int py, double d[3])
{
  double f[3], rt[3], up[3];
  sl_camera_basis(cam, f, rt, up);
  sl_camera_pixel_ray(f, rt, up, tan(0.5 * cam->fov_deg * M_PI / 180.0), (double)cam->width / cam->height,
                      cam->width, cam->height, px, py, d);
}

static void check_case(double tau, int light_volume, int skylight, const sl_camera *cam)
{
  const double lo[3] = {-4000.0, -4000.0, 1000.0}, hi[3] = {4000.0, 4000.0, 3000.0};
  const double beta = tau / (hi[2] - lo[2]);
  sl_volume v;
  CHECK(make_box_volume(&v, 12, 12, 6, lo, hi, beta) == 0);
  sl_scene sc = {.volume = &v, .sun_direction = {0.3, 0.2, 0.9}, .slices = 128, .light_volume = light_volume,
                 .skylight = skylight, .lighting = SL_LIGHTING_LOW_ALBEDO};
  for (int c = 0; c < SL_CHANNELS; ++c) sc.sky_radiance[c] = kSky[c]; /* the sun's irradiance stays 0 */
  sl_image layer, frame;
  CHECK(render_layers(&sc, cam, &layer, &frame) == 0);
  box_medium m = {.beta = beta};
  for (int a = 0; a < 3; ++a) m.lo[a] = lo[a], m.hi[a] = hi[a];
  int through = 0;
  for (int py = 1; py < cam->height; py += 3)
    for (int px = 1; px < cam->width; px += 3) {
      double d[3];
      unit_ray(cam, px, py, d);
      const double t = reference_transparency(&m, cam->position, d);
      if (!(t < 1.0 - 1e-9)) continue; /* misses the box */
      ++through;
      const size_t q = (size_t)py * cam->width + px;
      for (int c = 0; c < 3; ++c) {
        const double got = layer.rgba[4 * q + c];
        if (!skylight) {
          CHECK_MSG(got == 0.0, "skylight off, sun off: the volume sends nothing");
        } else if (tau < 0.05) {
          /* Albedo 1 (the low-albedo model's Table 2), tau along the ray from the box's chord:
           * L omega (1 - e^-tau), which is L tau omega to tau / 2 (here under 1.5 %). */
          const double want = kSky[c] * -expm1(log(t));
          CHECK_CLOSE(got, want, 0.01, 0.0); /* thin cloud: L tau omega */
        } else {
          const double whole = frame.rgba[4 * q + c];
          CHECK_CLOSE(whole, kSky[c], 0.01, 0.0); /* a conservative cloud in a uniform sky: the sky */
        }
      }
    }
  CHECK_MSG(through > 10, "the camera sees the box");
  sl_image_free(&layer), sl_image_free(&frame);
  sl_volume_free(&v);
}

int main(void)
{
  /* From above, and from the side at a grazing 10 degrees (long chords through the slab). */
  const sl_camera above = {.position = {0, 0, 9000}, .target = {0, 0, 0}, .up = {0, 1, 0}, .fov_deg = 50,
                           .width = 24, .height = 24};
  const sl_camera side = {.position = {-15000, -3000, 3500}, .target = {0, 0, 2000}, .up = {0, 0, 1}, .fov_deg = 50,
                          .width = 32, .height = 24};
  for (int lv = 0; lv < 2; ++lv) {
    for (int k = 0; k < 2; ++k) {
      const sl_camera *cam = k ? &side : &above;
      check_case(1e-3, lv, 1, cam);
      check_case(1e-2, lv, 1, cam);
      check_case(3.0, lv, 1, cam);
      check_case(40.0, lv, 1, cam);
      check_case(1e-2, lv, 0, cam);
    }
  }
  return sl_test_finish("test_skylight");
}
