/* The ground under the storm (render/volume/ground_shadow.c, sl_sky_ground_irradiance):
 *  - a flat Lambertian ground of albedo a under a clear sky, seen from 50 m, has radiance
 *    a E / pi behind the air in front of it, E the sun's irradiance on it (the sky module's
 *    sunlight times the cosine) plus the sky's, here by an independent quadrature (the midpoint
 *    rule over zenith and azimuth, 180 x 360 directions), within 1 %;
 *  - with albedo 0 the ground is black (only the air shines);
 *  - a thick cloud's shadow lies where the sun puts it: the darkness-weighted centroid of the ground
 *    seen from straight above within one grid cell of the cloud's centre carried along the sunlight. */
#include <math.h>

#include "homogeneous_reference.h"
#include "sl_sky.h"
#include "sl_testing.h"

static const double kAlbedo = 0.2;

static int background(const sl_scene *sc, const sl_camera *cam, sl_image *img)
{
  sl_error err = {0};
  sl_renderer *r = sl_renderer_create(sc, &err);
  if (!r) return 1;
  sl_image layer;
  int rc = sl_image_alloc(&layer, cam->width, cam->height, &err) || sl_image_alloc(img, cam->width, cam->height, &err);
  /* The frame first (it prepares the sky's light), then the background. */
  if (!rc) rc = sl_renderer_render(r, cam, &layer, NULL, &err) || sl_renderer_background(r, cam, img, &err);
  sl_image_free(&layer);
  sl_renderer_destroy(r);
  return rc;
}

/* E_sky on the horizontal ground by the midpoint rule in zenith angle and azimuth. */
static void sky_irradiance(const sl_atmosphere *atm, const double sun[3], double out[3])
{
  sl_error err = {0};
  const double origin[3] = {0, 0, 0};
  sl_sky_view view;
  sl_sky_view_init(&view, atm, origin, sun, &err);
  const int nt = 180, np = 360;
  for (int c = 0; c < 3; ++c) out[c] = 0.0;
  for (int i = 0; i < nt; ++i) {
    const double th = 0.5 * M_PI * (i + 0.5) / nt;
    for (int j = 0; j < np; ++j) {
      const double ph = 2.0 * M_PI * (j + 0.5) / np;
      const double d[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
      double L[SL_SKY_MAX_WAVELENGTHS];
      sl_sky_view_segment(&view, d, 0.0, INFINITY, L, NULL);
      for (int c = 0; c < 3; ++c) out[c] += L[c] * cos(th) * sin(th) * (0.5 * M_PI / nt) * (2.0 * M_PI / np);
    }
  }
}

static void clear_sky_ground(const sl_atmosphere *atm)
{
  /* A small cloud far from where the camera looks, so the ground there is in the open. */
  const double lo[3] = {40000, 40000, 2000}, hi[3] = {41000, 41000, 3000};
  sl_volume v;
  CHECK(make_box_volume(&v, 4, 4, 4, lo, hi, 0.01) == 0);
  sl_scene sc = {.volume = &v, .atmosphere = atm, .ground_albedo = kAlbedo, .slices = 32};
  sl_sun_direction(35.0, 150.0, sc.sun_direction);
  const sl_camera cam = {.position = {0, 0, 50}, .target = {0, 30, 0}, .up = {0, 0, 1}, .fov_deg = 20, .width = 9,
                         .height = 9};
  sl_image img;
  CHECK(background(&sc, &cam, &img) == 0);
  double E_sun[SL_SKY_MAX_WAVELENGTHS], E_sky[3];
  int night = 0;
  sl_error err = {0};
  const double origin[3] = {0, 0, 0};
  CHECK(sl_sky_sunlight(atm, origin, sc.sun_direction, E_sun, &night, &err) == 0 && !night);
  sky_irradiance(atm, sc.sun_direction, E_sky);
  sl_sky_view view;
  sl_sky_view_init(&view, atm, cam.position, sc.sun_direction, &err);
  for (int py = 0; py < 9; py += 4)
    for (int px = 0; px < 9; px += 4) {
      double d[3], air[SL_SKY_MAX_WAVELENGTHS], T[SL_SKY_MAX_WAVELENGTHS];
      CHECK(sl_camera_ray(&cam, px, py, d) == 0);
      sl_sky_view_segment(&view, d, 0.0, INFINITY, air, T);
      for (int c = 0; c < 3; ++c) {
        const double ground = kAlbedo / M_PI * (E_sun[c] * sc.sun_direction[2] + E_sky[c]);
        CHECK_CLOSE(img.rgba[4 * (py * 9 + px) + c] - air[c], T[c] * ground, 0.01, 0.0);
      }
    }
  sl_image_free(&img);
  /* Albedo 0: only the air between the camera and the ground. */
  sc.ground_albedo = 0.0;
  CHECK(background(&sc, &cam, &img) == 0);
  double d[3], air[SL_SKY_MAX_WAVELENGTHS];
  CHECK(sl_camera_ray(&cam, 4, 4, d) == 0);
  sl_sky_view_segment(&view, d, 0.0, INFINITY, air, NULL);
  CHECK_CLOSE(img.rgba[4 * (4 * 9 + 4)], air[0], 1e-6, 0.0);
  sl_image_free(&img);
  sl_volume_free(&v);
}

static void shadow_centroid(const sl_atmosphere *atm)
{
  /* A thick cloud 2 km wide at 3-5 km over (5 km, -3 km), the sun 40 degrees up in the south-east. */
  const double lo[3] = {4000, -4000, 3000}, hi[3] = {6000, -2000, 5000};
  sl_volume v;
  CHECK(make_box_volume(&v, 8, 8, 8, lo, hi, 0.02) == 0);
  sl_scene sc = {.volume = &v, .atmosphere = atm, .ground_albedo = kAlbedo, .slices = 32};
  sl_sun_direction(40.0, 135.0, sc.sun_direction);
  const double *s = sc.sun_direction;
  const double c[3] = {5000, -3000, 4000};
  const double want[2] = {c[0] - c[2] / s[2] * s[0], c[1] - c[2] / s[2] * s[1]};
  /* Straight down from 30 km over the expected shadow, 40 m per pixel. */
  const int n = 200;
  sl_camera cam = {.position = {want[0], want[1], 30000}, .target = {want[0], want[1], 0}, .up = {0, 1, 0},
                   .width = n, .height = n};
  cam.fov_deg = 2.0 * atan(0.5 * n * 40.0 / 30000.0) * 180.0 / M_PI;
  sl_image img;
  CHECK(background(&sc, &cam, &img) == 0);
  double lit = 0.0;
  for (int q = 0; q < n * n; ++q) lit = fmax(lit, img.rgba[4 * q + 1]);
  double sum = 0.0, sx = 0.0, sy = 0.0, dark_pixels = 0.0;
  for (int py = 0; py < n; ++py)
    for (int px = 0; px < n; ++px) {
      double d[3];
      sl_camera_ray(&cam, px, py, d);
      const double t = -cam.position[2] / d[2];
      const double w = lit - img.rgba[4 * (py * n + px) + 1];
      sum += w, sx += w * (cam.position[0] + t * d[0]), sy += w * (cam.position[1] + t * d[1]);
      dark_pixels += w > 0.5 * lit * 0.3;
    }
  CHECK_MSG(dark_pixels > 100, "the cloud casts a shadow on the ground");
  const double cell = v.spacing[0];
  CHECK_CLOSE(sx / sum, want[0], 0.0, cell);
  CHECK_CLOSE(sy / sum, want[1], 0.0, cell);
  sl_image_free(&img);
  sl_volume_free(&v);
}

int main(void)
{
  sl_atmosphere atm;
  sl_error err = {0};
  CHECK(sl_atmosphere_init(&atm, sl_sky_rgb_wavelengths_nm, 3, SL_EARTH_FLAT, SL_RAYLEIGH_BODHAINE1999, &err) == 0);
  clear_sky_ground(&atm);
  shadow_centroid(&atm);
  return sl_test_finish("test_ground");
}
