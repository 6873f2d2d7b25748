/* A flat cloud top under a grazing sun (Katrina's lid at dawn; DESIGN-NOTES.md, "Light at a
 * surface between texels"): a WRF-like 400 km x 400 km x 6 km grid of 48 x 48 x 14 cells, an
 * optically thick deck (extinction 0.02 m^-1, a mean free path of 50 m in cells 8.3 km wide and
 * 430 m high), the sun 4.2 degrees high, seen from 1200 km at 22 degrees through a 3-degree view.
 *
 * The oracle is outside the renderer: single scattering (the low-albedo model: isotropic phase,
 * albedo 1) from a horizontally uniform, optically semi-infinite medium gives
 *   L = p F mu0 / (mu0 + mu)
 * whatever the vertical profile of its extinction (substitute the optical depth for height), with
 * mu0 and mu the cosines of the sun's and the view's zenith angles. The deck is also the same at
 * every horizontal position, so its image can vary only with the view direction, which changes
 * slowly across the view: nothing in the physics varies at the scale of a pixel.
 *
 * The slicer's light-buffer rows meet such a top one after another, each kilometres further
 * downwind than the last; ln I interpolated between a row still above the top and one far inside
 * it drew a stripe per row and put the top's light 4-16x too dark. Two decks: one whose top is the
 * box's face (its medium homogeneous up to it), and one whose density ramps from zero over the
 * grid level above its last cloudy one, as the Katrina sample's does, the top's light then decided
 * within the first 130 m of the ramp. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "homogeneous_reference.h"
#include "sl_optics.h"
#include "sl_testing.h"

#define NX 48
#define NY 48
#define NZ 14
#define SIDE 96

static const double kSunAzimuth = 81.3, kSunElevation = 4.2, kBeta = 0.02;

/* The deck: extinction kBeta in the cell layers below `layers` (NZ: the whole box), zero above. */
static int make_deck(sl_volume *v, int layers)
{
  const double lo[3] = {-200e3, -200e3, 0}, hi[3] = {200e3, 200e3, 6000};
  if (make_box_volume(v, NX, NY, NZ, lo, hi, kBeta)) return 1;
  for (int k = layers; k < NZ; ++k)
    for (int j = 0; j < NY; ++j)
      for (int i = 0; i < NX; ++i) v->eta[SL_CLOUD][((size_t)k * NY + j) * NX + i] = 0.0f;
  return 0;
}

#define WINDOW (SIDE / 2)

typedef struct deck_result {
  float window[WINDOW * WINDOW]; /* channel 0 over the image's middle half */
  double mean_error;  /* mean over the window of rendered / closed form - 1 */
  double worst_error; /* largest |rendered / closed form - 1| */
  double structure;   /* RMS of the second differences down the columns over the mean */
} deck_result;

/* Renders the deck and measures the image's middle half (all of it on the deck's top). */
static void render_deck(const sl_volume *v, const sl_optics_tables *optics, int slices, int light_resolution,
                        deck_result *res)
{
  res->mean_error = res->worst_error = res->structure = INFINITY;
  sl_scene sc = {.volume = v, .slices = slices, .light_resolution = light_resolution, .optics = optics,
                 .lighting = optics ? SL_LIGHTING_MULTIPLE : SL_LIGHTING_LOW_ALBEDO};
  sl_sun_direction(kSunElevation, kSunAzimuth, sc.sun_direction);
  for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0, sc.sky_radiance[c] = 0.0;
  const double top = v->origin[2] + (NZ - 0.5) * v->spacing[2];
  sl_camera cam = {.position = {-431796, -1023292, 454341 + top}, .target = {0, 0, top}, .up = {0, 0, 1},
                   .fov_deg = 3, .width = SIDE, .height = SIDE};
  sl_image img;
  if (!CHECK(render_frame(&sc, &cam, &img) == 0)) return;
  const double mu0 = sc.sun_direction[2], p = 1.0 / (4.0 * M_PI);
  double sum = 0.0, sum_rel = 0.0, worst = 0.0, sum2 = 0.0;
  int count = 0;
  for (int y = SIDE / 4; y < 3 * SIDE / 4; ++y)
    for (int x = SIDE / 4; x < 3 * SIDE / 4; ++x) {
      double d[3];
      sl_camera_ray(&cam, x, y, d);
      const double want = p * mu0 / (mu0 - d[2]);
      const double got = img.rgba[4 * ((size_t)y * SIDE + x)];
      const double above = img.rgba[4 * ((size_t)(y - 1) * SIDE + x)];
      const double below = img.rgba[4 * ((size_t)(y + 1) * SIDE + x)];
      res->window[(y - SIDE / 4) * WINDOW + (x - SIDE / 4)] = (float)got;
      sum += got, sum_rel += got / want - 1.0, worst = fmax(worst, fabs(got / want - 1.0));
      sum2 += (above - 2.0 * got + below) * (above - 2.0 * got + below);
      count++;
    }
  res->mean_error = sum_rel / count;
  res->worst_error = worst;
  res->structure = sqrt(sum2 / count) / (sum / count);
  sl_image_free(&img);
}

/* The relative RMS difference of two renders' windows. */
static double window_difference(const deck_result *a, const deck_result *b)
{
  double d2 = 0.0, b2 = 0.0;
  for (int i = 0; i < WINDOW * WINDOW; ++i) {
    const double d = a->window[i] - b->window[i];
    d2 += d * d, b2 += (double)b->window[i] * b->window[i];
  }
  return sqrt(d2 / b2);
}

/* Multiple scattering has no closed form here; its light on a planar top must not depend on where
 * the texel rows fall: the deck at the default buffer and at 128 texels, their relative RMS
 * difference (at the default slices the eye's own slicing leaves structure of its own, the same at
 * any buffer). */
static double texel_rows_difference(const sl_volume *v, const sl_optics_tables *optics, const char *name)
{
  static deck_result fine, coarse;
  render_deck(v, optics, 0, 0, &fine);
  render_deck(v, optics, 0, 128, &coarse);
  const double diff = window_difference(&coarse, &fine);
  printf("%s, multiple scattering: 128 texels against the default buffer %.4f\n", name, diff);
  return diff;
}

static void report(const char *name, const deck_result *r)
{
  printf("%-44s mean error %+.4f, worst %.4f, pixel-scale structure %.4f\n", name, r->mean_error, r->worst_error,
         r->structure);
}

int main(void)
{
  static deck_result face, face_coarse, ramp, ramp_coarse;
  sl_volume v;
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.particles = 1u << SL_CLOUD;
  sl_error err = {0};
  sl_optics_tables *optics = sl_optics_build(&req, &err);
  CHECK_MSG(optics != NULL, err.message);

  /* The box's top face, the medium homogeneous up to it: the slicer's default slices and light
   * buffer, and a buffer of 128 texels (11 rows across the deck's height, 44 km apart along the
   * sunlight). The closed form within 1 % on average, and no structure. */
  CHECK(make_deck(&v, NZ) == 0);
  render_deck(&v, NULL, 0, 0, &face);
  render_deck(&v, NULL, 0, 128, &face_coarse);
  report("top at the box's face", &face);
  report("top at the box's face, 128 texels", &face_coarse);
  /* Cells whose texels' ln I differ by less than a quarter e-fold keep the bilinear value
   * (renderer.c, KINK_MIN_FALL), which is then off by at most that: e^0.25 - 1. */
  CHECK_MSG(fabs(face.mean_error) < 0.01 && face.worst_error < 0.284, "face: the closed form");
  CHECK_MSG(fabs(face_coarse.mean_error) < 0.01 && face_coarse.worst_error < 0.02, "face, 128 texels: the closed form");
  CHECK_MSG(face.structure < 0.01 && face_coarse.structure < 0.01, "face: no stripes");
  if (optics)
    CHECK_MSG(texel_rows_difference(&v, optics, "top at the box's face") < 0.01,
              "face, multiple scattering: the light does not depend on the texel rows");
  sl_volume_free(&v);

  /* The ramped top. Its lit layer (130 m) is thinner than the default slabs (about 1 km along the
   * view), which leaves the eye's own slicing bands (DESIGN-NOTES.md, "slicing bands on optically
   * thick surfaces"); 4096 slices bring those to a tenth, and the mean within that of the closed
   * form. */
  CHECK(make_deck(&v, 10) == 0);
  render_deck(&v, NULL, 4096, 0, &ramp);
  render_deck(&v, NULL, 4096, 128, &ramp_coarse);
  report("ramped top, 4096 slices", &ramp);
  report("ramped top, 4096 slices, 128 texels", &ramp_coarse);
  CHECK_MSG(fabs(ramp.mean_error) < 0.15 && fabs(ramp_coarse.mean_error) < 0.15, "ramp: the closed form");
  CHECK_MSG(ramp.structure < 0.15 && ramp_coarse.structure < 0.15, "ramp: no stripes");
  const double diff = window_difference(&ramp_coarse, &ramp);
  printf("ramped top: 128 texels against the default buffer %.4f\n", diff);
  CHECK_MSG(diff < 0.01, "ramp: the light does not depend on the texel rows");
  if (optics)
    CHECK_MSG(texel_rows_difference(&v, optics, "ramped top") < 0.01,
              "ramp, multiple scattering: the light does not depend on the texel rows");
  sl_optics_free(optics);
  sl_volume_free(&v);
  return sl_test_finish("test_flat_top");
}
