/* Hard cases of the multiple-scattering lighting: no NaN, no black frames, nothing brighter than
 * the sun itself, and an empty volume that shows exactly the sky. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homogeneous_reference.h"
#include "sl_sample_physics.h"
#include "sl_testing.h"

static sl_optics_tables *opt;
static sl_atmosphere atm;

/* Renders and checks: every value finite, radiance never above the sun disk's (E / solid angle),
 * and (unless allow_black) some pixel lit. */
static void check_frame(const char *name, const sl_volume *v, const double sun[3], const sl_camera *cam, int slices,
                        int light_resolution)
{
  sl_scene sc = {.volume = v, .optics = opt, .atmosphere = &atm, .lighting = SL_LIGHTING_MULTIPLE, .slices = slices,
                 .light_resolution = light_resolution};
  memcpy(sc.sun_direction, sun, 3 * sizeof(double));
  sl_image img;
  const int rc = render_frame(&sc, cam, &img);
  CHECK_MSG(rc == 0, name);
  if (rc) return;
  int finite = 1;
  double brightest = 0.0, lit = 0.0;
  const size_t n = (size_t)cam->width * cam->height;
  for (size_t i = 0; i < 4 * n; ++i) finite &= isfinite(img.rgba[i]) != 0;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      brightest = fmax(brightest, img.rgba[4 * i + c]);
      lit = fmax(lit, img.rgba[4 * i + c] * (1.0 - img.transparency[i]));
    }
  printf("%-40s brightest %.4g, volume-lit maximum %.4g\n", name, brightest, lit);
  CHECK_MSG(finite, name);
  CHECK_MSG(brightest <= 1.0 / sl_sun_disk_solid_angle(), name);
  CHECK_MSG(brightest > 0.0, name);
  sl_image_free(&img);
}

/* An eye segment whose light grows by hundreds of e-folds from a shadowed near end to a lit far
 * one (a thick slab at a low sun): the gather beta int_0^len exp(near - beta rate u) du with a
 * rate far below 0, by the closed form that takes exp(near) and exp(near - beta rate len), against
 * composite Simpson quadrature in the log domain. Taken as exp(near) times the moment, e^-x
 * overflowed while exp(near) underflowed: inf times 0, NaN pixels (Katrina's lid at 64 slices). */
static void check_growing_light(void)
{
  const double cases[][4] = {/* beta, len, rate, near */ {0.02, 10e3, -4.0, -900.0},
                             {0.02, 10e3, -4.5, -1000.0},
                             {1e-3, 2e3, -0.5, -3.0},
                             {0.05, 4e3, 3.0, -2.0}};
  double worst = 0.0;
  int finite = 1;
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    const double beta = cases[i][0], len = cases[i][1], rate = cases[i][2], near = cases[i][3];
    const double x = beta * rate * len;
    const double got = sl_segment_scatter_moment_scaled(0, beta, len, rate, exp(near), exp(near - x));
    const int n = 20000;
    const double h = len / n;
    double want = 0.0;
    for (int k = 0; k <= n; ++k)
      want += (k == 0 || k == n ? 1.0 : k % 2 ? 4.0 : 2.0) * beta * exp(near - beta * rate * k * h);
    want *= h / 3.0;
    finite &= isfinite(got) != 0;
    worst = fmax(worst, fabs(got / want - 1.0));
  }
  printf("light growing along a thick eye segment (up to e^800): worst relative error %.2e\n", worst);
  CHECK_MSG(finite, "growing light: finite");
  CHECK_MSG(worst < 1e-6, "growing light: the closed form against quadrature");
}

int main(void)
{
  check_growing_light();
  sl_error err = {0};
  sl_atmosphere_init(&atm, sl_sky_rgb_wavelengths_nm, 3, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, &err);
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.particles = 1u << SL_CLOUD;
  opt = sl_optics_build(&req, &err);
  if (!CHECK(opt != NULL)) return sl_test_finish("test_hard_cases");
  double sigma = 0.0;
  for (int c = 0; c < 3; ++c) sigma += sl_optics_table(opt, SL_CLOUD, c)->sigma_ext / 3.0;
  double sun[3];
  sl_sun_direction(35.0, 230.0, sun);
  const double lo[3] = {-2000, -2000, 1000}, hi[3] = {2000, 2000, 3000};
  sl_camera cam = {.position = {-1000, -9000, 2500}, .target = {0, 0, 2000}, .up = {0, 0, 1}, .fov_deg = 40,
                   .width = 48, .height = 36};
  /* Optical depth per slice from 1e-6 to 1e4 (64 slices across a ~6 km deep box). */
  const double per_slice[] = {1e-6, 1e-3, 1.0, 1e2, 1e4};
  for (size_t i = 0; i < sizeof per_slice / sizeof per_slice[0]; ++i) {
    sl_volume v;
    const double beta = per_slice[i] / 100.0;
    make_box_volume(&v, 8, 8, 4, lo, hi, beta);
    char name[64];
    snprintf(name, sizeof name, "tau per slice %g", per_slice[i]);
    check_frame(name, &v, sun, &cam, 64, 0);
    sl_volume_free(&v);
  }
  sl_volume v;
  make_box_volume(&v, 8, 8, 4, lo, hi, 2e-3);
  /* The sun exactly behind and exactly ahead of the camera. */
  {
    double d[3];
    for (int a = 0; a < 3; ++a) d[a] = cam.target[a] - cam.position[a];
    const double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double behind[3], ahead[3];
    for (int a = 0; a < 3; ++a) behind[a] = -d[a] / n, ahead[a] = d[a] / n;
    check_frame("sun exactly behind the camera", &v, behind, &cam, 0, 0);
    /* Looking straight up at the sun through the cloud from below. */
    sl_camera up_cam = {.position = {0, 0, 200}, .target = {0, 0, 2000}, .up = {0, 1, 0}, .fov_deg = 40, .width = 48, .height = 36};
    const double zenith[3] = {0, 0, 1};
    check_frame("sun exactly ahead (overhead, seen from below)", &v, zenith, &up_cam, 0, 0);
    (void)ahead;
  }
  /* The camera inside the cloud. */
  {
    sl_camera inside = {.position = {0, 0, 2000}, .target = {1000, 500, 2200}, .up = {0, 0, 1}, .fov_deg = 60, .width = 48, .height = 36};
    check_frame("camera inside the cloud", &v, sun, &inside, 0, 0);
  }
  sl_volume_free(&v);
  /* One voxel thick. */
  {
    const double l1[3] = {-10, -3000, 1000}, h1[3] = {10, 3000, 4000};
    make_box_volume(&v, 1, 30, 30, l1, h1, 5e-3);
    sl_camera side = {.position = {-8000, -2000, 2500}, .target = {0, 0, 2500}, .up = {0, 0, 1}, .fov_deg = 50, .width = 48, .height = 36};
    check_frame("one voxel thick", &v, sun, &side, 0, 0);
    sl_volume_free(&v);
  }
  /* WRF-like flat grid: 500 x 500 x 40 samples of 3 km x 3 km x 250 m. */
  {
    const double lw[3] = {-750e3, -750e3, 0}, hw[3] = {750e3, 750e3, 10000};
    make_box_volume(&v, 500, 500, 40, lw, hw, 1e-5);
    /* A cloud layer in the middle third only. */
    for (int k = 0; k < 40; ++k)
      if (k < 12 || k > 26)
        for (int j = 0; j < 500; ++j)
          for (int i = 0; i < 500; ++i) v.eta[SL_CLOUD][sl_volume_index(&v, i, j, k)] = 0.0f;
    sl_camera wide = {.position = {0, -900e3, 60e3}, .target = {0, 0, 5000}, .up = {0, 0, 1}, .fov_deg = 50, .width = 48, .height = 36};
    check_frame("WRF-like 500x500x40, 3 km x 3 km x 250 m", &v, sun, &wide, 256, 256);
    sl_volume_free(&v);
  }
  /* Zero density everywhere: exactly the sky. */
  {
    make_box_volume(&v, 4, 4, 4, lo, hi, 0.0);
    sl_scene sc = {.volume = &v, .optics = opt, .atmosphere = &atm, .lighting = SL_LIGHTING_MULTIPLE};
    memcpy(sc.sun_direction, sun, sizeof sun);
    sl_renderer *r = sl_renderer_create(&sc, &err);
    sl_image layer, bg;
    sl_image_alloc(&layer, cam.width, cam.height, &err);
    sl_image_alloc(&bg, cam.width, cam.height, &err);
    sl_renderer_render(r, &cam, &layer, NULL, &err);
    sl_renderer_background(r, &cam, &bg, &err);
    double worst = 0.0;
    for (size_t i = 0; i < (size_t)cam.width * cam.height; ++i) {
      worst = fmax(worst, fabs(layer.rgba[4 * i]) + fabs(layer.rgba[4 * i + 3]));
      worst = fmax(worst, fabs(layer.transparency[i] - 1.0));
    }
    CHECK_MSG(worst == 0.0, "an empty volume adds nothing and hides nothing: the frame is the sky");
    sl_image_free(&layer);
    sl_image_free(&bg);
    sl_renderer_destroy(r);
    sl_volume_free(&v);
  }
  sl_optics_free(opt);
  return sl_test_finish("test_hard_cases");
}
