/* The round ground of the sky (sl_atmosphere.ground_radius, `--curvature drop`) against geometry
 * computed here: where a ray meets the sphere (the quadratic solved on vectors in long double),
 * the horizon's dip acos(R / (R + h)) found in a rendered background as the sky/ground step in
 * each column, the flat-plane limit, a cloud beyond the horizon hidden, and the frame's Z where
 * rays stop at a flat terrain or the ground (sl_image_opaque_depth, sl_image_depth_over), and a
 * dropped cloud's sunlight taken at its altitude above the sphere (the volume's sun table). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homogeneous_reference.h"
#include "renderer_internal.h"
#include "sl_testing.h"

static const double kR = 6370000.0; /* WRF's sphere, as sl_curvature_drop */

static unsigned long long rng = 987654321;
static double uniform(void)
{
  rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(rng >> 11) / 9007199254740992.0;
}

/* First hit of eye + t d with |x - centre| = R, centre (0, 0, -R): +inf when none. */
static double sphere_hit(const double eye[3], const double d[3])
{
  const long double o[3] = {eye[0], eye[1], (long double)eye[2] + kR};
  const long double b = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
  const long double c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - (long double)kR * kR;
  const long double disc = b * b - c;
  if (disc < 0 || b >= 0) return INFINITY;
  return (double)(-b - sqrtl(disc));
}

static void random_direction_down(double d[3], double max_elevation_deg)
{
  const double el = -(max_elevation_deg * uniform()) * M_PI / 180.0, az = 2 * M_PI * uniform();
  d[0] = cos(el) * sin(az), d[1] = cos(el) * cos(az), d[2] = sin(el);
}

static void test_ground_distance(sl_atmosphere *atm)
{
  atm->ground_radius = kR;
  double worst = 0.0;
  int agree_on_miss = 1, n = 0;
  for (int k = 0; k < 20000; ++k) {
    /* eyes up to 500 km from the origin (the sphere's vertical tilts there) and 1 m - 20 km up */
    const double r = 5e5 * uniform(), a = 2 * M_PI * uniform(), h = pow(10.0, 4.3 * uniform());
    const double drop = r * r / (kR + sqrt(kR * kR - r * r));
    const double eye[3] = {r * cos(a), r * sin(a), h - drop};
    double d[3];
    random_direction_down(d, k % 2 ? 90.0 : 6.0);
    double up[3];
    const double z = sl_sky_altitude(atm, eye, up);
    const double got = sl_sky_ground_distance(z, d[0] * up[0] + d[1] * up[1] + d[2] * up[2], kR);
    const double want = sphere_hit(eye, d);
    if (isinf(want) || isinf(got)) {
      /* near-grazing rays may go either way: check only clear cases */
      if (isinf(want) != isinf(got) && fabs(got - want) > 0) {
        const double other = isinf(want) ? got : want;
        if (other < 0.9 * sqrt(2 * kR * h)) agree_on_miss = 0;
      }
      continue;
    }
    worst = fmax(worst, fabs(got - want) / want), ++n;
  }
  printf("sphere: %d hits, worst relative difference from the vector quadratic %.2e\n", n, worst);
  CHECK_MSG(worst < 1e-9, "ground distance = the sphere intersection");
  CHECK_MSG(agree_on_miss, "misses agree away from grazing");

  /* The horizon's dip: rays just above acos(R/(R+h)) below the horizontal miss, just below hit. */
  for (double h = 10.0; h < 3e4; h *= 3.0) {
    const double dip = acos(kR / (kR + h));
    const double above = sl_sky_ground_distance(h, -sin(dip * (1 - 1e-8)), kR);
    const double below = sl_sky_ground_distance(h, -sin(dip * (1 + 1e-8)), kR);
    CHECK_MSG(isinf(above) && isfinite(below), "horizon at acos(R/(R+h))");
    /* the tangent point lies sqrt(h (2R + h)) away */
    if (isfinite(below)) CHECK_CLOSE(below, sqrt(h * (2 * kR + h)), 1e-3, 0.0);
  }

  /* Flat limit: a huge sphere is the plane; the earth's is within the sagitta for short rays. */
  double worst_huge = 0.0, worst_short = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const double h = 1.0 + 2000.0 * uniform(), mu = -(0.05 + 0.95 * uniform());
    const double plane = h / -mu;
    worst_huge = fmax(worst_huge, fabs(sl_sky_ground_distance(h, mu, 1e15) - plane) / plane);
    /* the ground has fallen by the sagitta s^2 / 2R at the hit's horizontal distance s */
    const double sphere = sl_sky_ground_distance(h, mu, kR);
    const double s = sphere * sqrt(1 - mu * mu), fallen = sphere * -mu - h;
    if (s > 100.0) worst_short = fmax(worst_short, fabs(fallen - s * s / (2 * kR)) / (s * s / (2 * kR)));
    CHECK(sphere >= plane);
  }
  printf("flat limit: R = 1e15 m within %.1e of h/-mu; R = earth's: the hit lies the sagitta s^2/2R below the plane within %.1e\n", worst_huge,
         worst_short);
  CHECK_MSG(worst_huge < 1e-8, "a huge sphere is the plane");
  CHECK_MSG(worst_short < 1e-3, "the earth's sphere sags by s^2/2R");
  CHECK(sl_sky_ground_distance(100.0, -0.5, 0.0) == 200.0);
}

/* A background frame from height h looking at the horizon; the row of the sky/ground step in
 * every column, as an elevation angle, against -acos(R/(R+h)). */
static void test_rendered_horizon(sl_atmosphere *atm)
{
  const int W = 6, H = 500;
  const double fov = 5.0; /* 0.01 degree per row */
  const double lo[3] = {-1000, -1000, 1000}, hi[3] = {1000, 1000, 2000};
  sl_volume v;
  make_box_volume(&v, 4, 4, 4, lo, hi, 0.0);
  sl_scene sc = {.volume = &v, .atmosphere = atm, .slices = 8};
  sl_sun_direction(40.0, 180.0, sc.sun_direction);
  sl_error err = {0};
  sl_renderer *r = sl_renderer_create(&sc, &err);
  CHECK(r != NULL);
  sl_image bg;
  CHECK(sl_image_alloc(&bg, W, H, &err) == SL_OK);
  const double heights[] = {300.0, 1000.0, 3000.0};
  for (int k = 0; k < 3; ++k) {
    const double h = heights[k], dip = acos(kR / (kR + h)) * 180.0 / M_PI;
    /* looking north, the view axis 1.2 degrees down: the horizon lies in the frame */
    const double el = -1.2 * M_PI / 180.0;
    sl_camera cam = {.position = {0, 0, h}, .target = {0, 1e5 * cos(el), h + 1e5 * sin(el)}, .up = {0, 0, 1},
                     .fov_deg = fov, .width = W, .height = H};
    CHECK(sl_renderer_background(r, &cam, &bg, &err) == SL_OK);
    double worst = 0.0;
    for (int px = 0; px < W; ++px) {
      int step_row = -1;
      double biggest = 0.0;
      for (int py = 0; py + 1 < H; ++py) {
        /* green: the sky above is brighter than the air in front of the black ground below */
        const double jump = bg.rgba[4 * (py * W + px) + 1] - bg.rgba[4 * ((py + 1) * W + px) + 1];
        if (jump > biggest) biggest = jump, step_row = py;
      }
      double d0[3], d1[3];
      sl_camera_ray(&cam, px, step_row, d0);
      sl_camera_ray(&cam, px, step_row + 1, d1);
      const double found = 0.5 * (asin(d0[2]) + asin(d1[2])) * 180.0 / M_PI;
      worst = fmax(worst, fabs(found + dip));
    }
    printf("h = %4.0f m: horizon found at most %.4f deg from the dip -%.4f deg (a row is %.4f deg)\n", h, worst,
           dip, fov / H);
    CHECK_MSG(worst <= 1.0 * fov / H, "rendered horizon at -acos(R/(R+h)) within a row");
    /* Z of the ground rows: the sphere's distance along the view axis */
    double worst_z = 0.0;
    for (int py = 0; py < H; ++py) {
      double d[3], fwd[3] = {0, cos(el), sin(el)};
      sl_camera_ray(&cam, 2, py, d);
      const double t = sphere_hit(cam.position, d);
      const float z = bg.depth[py * W + 2];
      if (isinf(t)) {
        CHECK(isinf(z) || fabs(asin(d[2]) * 180 / M_PI + dip) < 2e-3);
        continue;
      }
      const double want = t * (d[0] * fwd[0] + d[1] * fwd[1] + d[2] * fwd[2]);
      worst_z = fmax(worst_z, fabs(z - want) / want);
    }
    printf("  ground Z within %.2e of the sphere's view-axis distance\n", worst_z);
    CHECK_MSG(worst_z < 1e-5, "background Z = the sphere's view-axis distance");
  }
  sl_image_free(&bg);
  sl_renderer_destroy(r);
  sl_volume_free(&v);
}

/* A cloud 400 km away with its top 3 km above the ground, seen from 1 km: the geometric horizon
 * hides everything below (d - sqrt(2 R h))^2 / 2R ~ 6.5 km there, so the round earth hides it all;
 * 150 km away (hidden below ~0.1 km) it shows. The cloud is placed as `--curvature drop` does. */
/* The volume layer of a uniform box [lo, hi] (extinction beta) under the sun at `sun_elevation`
 * due south, seen by cam (a 16 x 16 frame), summed over the pixels: RGB radiance and coverage. */
static void render_box(sl_atmosphere *atm, const double lo[3], const double hi[3], double beta, double sun_elevation,
                       const sl_camera *cam, double sum[4])
{
  sl_volume v;
  make_box_volume(&v, 8, 8, 8, lo, hi, beta);
  sl_scene sc = {.volume = &v, .atmosphere = atm, .slices = 64};
  sl_sun_direction(sun_elevation, 180.0, sc.sun_direction);
  sl_error err = {0};
  sl_renderer *r = sl_renderer_create(&sc, &err);
  sl_image layer;
  sl_image_alloc(&layer, cam->width, cam->height, &err);
  sl_render_stats st;
  CHECK(sl_renderer_render(r, cam, &layer, &st, &err) == SL_OK);
  for (int k = 0; k < 4; ++k) sum[k] = 0.0;
  for (int i = 0; i < cam->width * cam->height; ++i)
    for (int k = 0; k < 4; ++k) sum[k] += layer.rgba[4 * i + k];
  sl_image_free(&layer);
  sl_renderer_destroy(r);
  sl_volume_free(&v);
}

static double cloud_coverage(sl_atmosphere *atm, double distance, int round)
{
  /* the flat earth: placed on the tangent plane, nothing stops the rays (render's default) */
  const double drop = round ? distance * distance / (kR + sqrt(kR * kR - distance * distance)) : 0.0;
  const double lo[3] = {-20000, distance - 20000, 500 - drop}, hi[3] = {20000, distance + 20000, 3000 - drop};
  atm->ground_radius = round ? kR : 0.0;
  const int W = 16, H = 16;
  sl_camera cam = {.position = {0, 0, 1000}, .target = {0, distance, 1000 - drop}, .up = {0, 0, 1}, .fov_deg = 2,
                   .width = W, .height = H};
  float *opaque = malloc(sizeof(float) * W * H);
  for (int i = 0; i < W * H; ++i) opaque[i] = INFINITY;
  if (round) sl_camera_ground_distance(&cam, atm, opaque);
  cam.opaque_distance = opaque;
  double sum[4];
  render_box(atm, lo, hi, 1e-3, 50.0, &cam, sum);
  free(opaque);
  return sum[3] / (W * H);
}

/* Z where eye rays stop at a flat terrain 250 m high: the ray-plane distance along the view axis,
 * then a half-covering cloud layer in front weights its own depth and the terrain's. */
static void test_terrain_depth(void)
{
  const int W = 12, H = 10;
  sl_camera cam = {.position = {100, -300, 1450}, .target = {400, 5000, 200}, .up = {0, 0, 1}, .fov_deg = 30,
                   .width = W, .height = H};
  const double ground = 250.0;
  float *opaque = malloc(sizeof(float) * W * H);
  sl_image bg, layer, out;
  sl_error err = {0};
  sl_image_alloc(&bg, W, H, &err);
  sl_image_alloc(&layer, W, H, &err);
  sl_image_alloc(&out, W, H, &err);
  double fwd[3] = {cam.target[0] - cam.position[0], cam.target[1] - cam.position[1], cam.target[2] - cam.position[2]};
  const double n = sqrt(fwd[0] * fwd[0] + fwd[1] * fwd[1] + fwd[2] * fwd[2]);
  for (int a = 0; a < 3; ++a) fwd[a] /= n;
  for (int py = 0; py < H; ++py)
    for (int px = 0; px < W; ++px) {
      double d[3];
      sl_camera_ray(&cam, px, py, d);
      const int q = py * W + px;
      opaque[q] = d[2] < 0 ? (float)((ground - cam.position[2]) / d[2]) : INFINITY;
      bg.depth[q] = INFINITY;
      layer.depth[q] = px < W / 2 ? 800.0f : INFINITY;
      layer.transparency[q] = px < W / 2 ? 0.5f : 1.0f;
    }
  sl_image_opaque_depth(&cam, opaque, &bg);
  sl_image_depth_over(&layer, &bg, &out);
  double worst = 0.0;
  int ground_pixels = 0;
  for (int py = 0; py < H; ++py)
    for (int px = 0; px < W; ++px) {
      double d[3];
      sl_camera_ray(&cam, px, py, d);
      const int q = py * W + px;
      if (!(d[2] < 0)) {
        CHECK(px < W / 2 ? out.depth[q] == 800.0f : isinf(out.depth[q]));
        continue;
      }
      /* ray-plane distance, projected on the view axis */
      const double z_ground = (ground - cam.position[2]) / d[2] * (d[0] * fwd[0] + d[1] * fwd[1] + d[2] * fwd[2]);
      const double want = px < W / 2 ? 0.5 * 800.0 + 0.5 * z_ground : z_ground;
      worst = fmax(worst, fabs(out.depth[q] - want) / want), ++ground_pixels;
    }
  printf("terrain Z: %d ground pixels within %.1e of the ray-plane distance (and the 50/50 mix)\n", ground_pixels,
         worst);
  CHECK(ground_pixels > W * H / 3);
  CHECK_MSG(worst < 1e-6, "Z = ray-plane distance along the view axis");
  free(opaque);
  sl_image_free(&bg), sl_image_free(&layer), sl_image_free(&out);
}

/* World position of a point s metres along the sphere's surface from the origin (toward +x) at
 * altitude h above it: where `--curvature drop` puts it. */
static void on_sphere(double s, double h, double x[3])
{
  const double th = s / kR;
  x[0] = (kR + h) * sin(th), x[1] = 0.0, x[2] = (kR + h) * cos(th) - kR;
}

/* The volume's sunlight at a cloud 300 km from the origin, dropped onto the sphere, equals the
 * sunlight of the same altitude at the origin on the flat ground, and both equal Riley eq. 12's
 * closed form E0 exp(-beta0 H exp(-h/H) m) (m: the view's air mass) written out here: the table
 * is indexed by the altitude above the sphere, not by world z (7.07 km lower there). */
static void test_sun_at_altitude(const sl_atmosphere *base)
{
  sl_atmosphere flat = *base, round = *base;
  flat.ground_radius = 0.0, round.ground_radius = kR;
  double sun[3];
  sl_sun_direction(30.0, 180.0, sun);
  const double eye[3] = {0, 0, 1000};
  sl_sky_view vf, vr;
  sl_error err = {0};
  CHECK(sl_sky_view_init(&vf, &flat, eye, sun, &err) == SL_OK);
  CHECK(sl_sky_view_init(&vr, &round, eye, sun, &err) == SL_OK);
  sl_scene sf = {.atmosphere = &flat}, sr = {.atmosphere = &round};
  const double flo[3] = {-5000, -5000, 0}, fhi[3] = {5000, 5000, 15000};
  double far[3];
  on_sphere(3e5, 15000, far);
  const double rlo[3] = {-5000, -5000, -8000}, rhi[3] = {far[0] + 5000, 5000, 15000};
  sun_table *tf = malloc(sizeof *tf), *tr = malloc(sizeof *tr);
  sl__sun_table_init(tf, &sf, &vf, flo, fhi);
  sl__sun_table_init(tr, &sr, &vr, rlo, rhi);
  const double H = base->scale_height;
  double worst_flat = 0.0, worst_drop = 0.0, old_way = 0.0;
  for (double h = 500.0; h <= 14000.0; h += 500.0) {
    double at_origin[3] = {0, 0, h}, dropped[3], ef[SL_MAX_WAVELENGTHS], er[SL_MAX_WAVELENGTHS];
    on_sphere(3e5, h, dropped);
    const sl__sun_lane lf = sl__sun_table_lane(tf), lr = sl__sun_table_lane(tr);
    sl__sun_at(tf, &lf, at_origin, ef);
    sl__sun_at(tr, &lr, dropped, er);
    for (int c = 0; c < base->count; ++c) {
      /* the two views' air masses agree: the eye is the same */
      const double want = base->sun_irradiance[c] * exp(-base->beta_sea_level[c] * H * exp(-h / H) * vf.airmass);
      const double want_low = base->sun_irradiance[c] *
                              exp(-base->beta_sea_level[c] * H * exp(-dropped[2] / H) * vf.airmass);
      worst_flat = fmax(worst_flat, fabs(ef[c] / want - 1.0));
      worst_drop = fmax(worst_drop, fabs(er[c] / want - 1.0));
      old_way = fmax(old_way, fabs(want_low / want - 1.0));
    }
  }
  printf("sun table against eq. 12 at 0.5-14 km: flat %.2e, dropped 300 km away %.2e (by world z it would be %.2f)\n",
         worst_flat, worst_drop, old_way);
  CHECK_CLOSE(vr.airmass, vf.airmass, 1e-12, 0);
  CHECK_MSG(worst_flat < 1e-5 && worst_drop < 1e-5, "sunlight at the cloud's altitude, flat or dropped");
  CHECK_MSG(old_way > 0.05, "the test tells altitude from world z");
  free(tf);
  free(tr);
}

/* The same small cloud rendered at the origin (flat ground) and 300 km away on the sphere
 * (dropped, camera moved with it): the same sunlight reaches it, so the volume layer's radiance
 * agrees up to the tilt of the local vertical (2.7 degrees: the eye's air mass and the air
 * between eye and cloud). */
static void test_dropped_cloud_render(sl_atmosphere *atm)
{
  double rad[2][3] = {{0}};
  for (int round = 0; round < 2; ++round) {
    double c[3] = {0, 0, 3000};
    if (round) on_sphere(3e5, 3000, c);
    const double lo[3] = {c[0] - 1000, c[1] - 1000, c[2] - 1000}, hi[3] = {c[0] + 1000, c[1] + 1000, c[2] + 1000};
    atm->ground_radius = round ? kR : 0.0;
    const sl_camera cam = {.position = {c[0], c[1] - 4000, c[2]}, .target = {c[0], c[1], c[2]}, .up = {0, 0, 1},
                           .fov_deg = 40, .width = 16, .height = 16};
    double sum[4];
    render_box(atm, lo, hi, 5e-4, 30.0, &cam, sum);
    for (int k = 0; k < 3; ++k) rad[round][k] = sum[k];
  }
  double worst = 0.0;
  for (int k = 0; k < 3; ++k) worst = fmax(worst, fabs(rad[1][k] / rad[0][k] - 1.0));
  printf("a cloud at 3 km rendered at the origin and 300 km away on the sphere: radiance R %.4g/%.4g G %.4g/%.4g "
         "B %.4g/%.4g, worst %.2e\n",
         rad[0][0], rad[1][0], rad[0][1], rad[1][1], rad[0][2], rad[1][2], worst);
  CHECK_MSG(rad[0][2] > 0.0 && worst < 5e-3, "a dropped cloud is lit as at its altitude");
}

int main(void)
{
  sl_atmosphere atm;
  sl_error err = {0};
  CHECK(sl_atmosphere_init(&atm, sl_sky_rgb_wavelengths_nm, SL_SKY_RGB_COUNT, SL_EARTH_ROUND,
                           SL_RAYLEIGH_BODHAINE1999, &err) == SL_OK);
  CHECK(atm.ground_radius == 0.0);
  test_ground_distance(&atm);
  atm.ground_radius = kR;
  test_rendered_horizon(&atm);
  const double far_round = cloud_coverage(&atm, 4e5, 1), far_flat = cloud_coverage(&atm, 4e5, 0);
  const double near_round = cloud_coverage(&atm, 1.5e5, 1);
  printf("cloud 400 km away: coverage %.3f on the round earth, %.3f on the flat; 150 km away (round) %.3f\n",
         far_round, far_flat, near_round);
  CHECK_MSG(far_round < 1e-3, "a cloud beyond the horizon is hidden");
  CHECK_MSG(far_flat > 0.05 && near_round > 0.05, "and shows where the horizon does not hide it");
  test_terrain_depth();
  test_sun_at_altitude(&atm);
  test_dropped_cloud_render(&atm);
  return sl_test_finish("test_horizon");
}
