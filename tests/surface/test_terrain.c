/* The ground under the storm, against outside facts: rays hit planes where geometry says; the
 * cloud's transmittance toward the sun is exp(-tau) with tau from the closed-form integral; a
 * Lambertian plane under a known sun and sky has rho (E_sun sin(e) + pi L_sky) / pi; a wall's
 * shadow is as long as its height over tan(elevation); and the renderer's eye rays stop at the
 * ground: a cloud half below a plane shows exactly the coverage of its part above the plane, and
 * a cloud behind a mountain is hidden where the mountain is in front. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homogeneous_reference.h"
#include "sl_particles.h"
#include "sl_renderer.h"
#include "sl_terrain.h"
#include "sl_testing.h"

static unsigned long long rng = 12345;
static double uniform(void)
{
  rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(rng >> 11) / 9007199254740992.0;
}

/* A plane z = a x + b y + c is exact on any triangulation: ray hits against the closed form. */
static void test_plane_hits(void)
{
  const int nx = 21, ny = 17;
  const double origin[2] = {-10000, -8000}, spacing[2] = {1000, 1000};
  const double a = 0.05, b = -0.03, c = 700.0;
  float *h = malloc(sizeof(float) * nx * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) h[j * nx + i] = (float)(a * (origin[0] + i * spacing[0]) + b * (origin[1] + j * spacing[1]) + c);
  sl_heightfield hf;
  sl_heightfield_init(&hf, nx, ny, origin, spacing, h);
  double worst = 0.0;
  int hits = 0, misses_right = 1;
  for (int r = 0; r < 2000; ++r) {
    const double o[3] = {-12000 + 24000 * uniform(), -10000 + 20000 * uniform(), 3000 + 5000 * uniform()};
    double d[3] = {uniform() - 0.5, uniform() - 0.5, -uniform()};
    const double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k) d[k] /= n;
    /* o + t d on the plane: o_z + t d_z = a (o_x + t d_x) + b (o_y + t d_y) + c. */
    const double t = (a * o[0] + b * o[1] + c - o[2]) / (d[2] - a * d[0] - b * d[1]);
    const double x = o[0] + t * d[0], y = o[1] + t * d[1];
    const int inside = t > 0 && x >= origin[0] && x <= origin[0] + (nx - 1) * spacing[0] && y >= origin[1] &&
                       y <= origin[1] + (ny - 1) * spacing[1];
    double got;
    const int hit = sl_heightfield_ray(&hf, o, d, INFINITY, &got);
    /* Points within a millimetre of the lattice's edge may go either way. */
    const double margin = fmin(fmin(x - origin[0], origin[0] + (nx - 1) * spacing[0] - x),
                               fmin(y - origin[1], origin[1] + (ny - 1) * spacing[1] - y));
    if (fabs(margin) < 1e-3) continue;
    if (inside) {
      if (!hit) misses_right = 0;
      else worst = fmax(worst, fabs(got - t) / t), ++hits;
    } else if (hit) {
      misses_right = 0;
    }
  }
  printf("plane: %d hits, worst relative error of the hit distance %.2e\n", hits, worst);
  CHECK(hits > 300);
  CHECK_MSG(misses_right, "rays hit exactly when the plane's closed form lands inside the lattice");
  CHECK(worst < 1e-9);
  /* t_max: a hit beyond it is none. */
  const double o[3] = {0, 0, 5000}, d[3] = {0, 0, -1};
  double t;
  CHECK(sl_heightfield_ray(&hf, o, d, INFINITY, &t) && fabs(t - (5000 - c)) < 1e-6);
  CHECK(!sl_heightfield_ray(&hf, o, d, 4000.0, &t));
  const double up[3] = {0, 0, 1};
  CHECK(!sl_heightfield_ray(&hf, o, up, INFINITY, &t));
  free(h);
}

/* A volume of uniform extinction over [lo, hi] from the cloud field with a chosen cross-section. */
static void uniform_volume(sl_volume *v, const double lo[3], const double hi[3], int nx, int ny, int nz, double eta)
{
  const double spacing[3] = {(hi[0] - lo[0]) / nx, (hi[1] - lo[1]) / ny, (hi[2] - lo[2]) / nz};
  const double origin[3] = {lo[0] + 0.5 * spacing[0], lo[1] + 0.5 * spacing[1], lo[2] + 0.5 * spacing[2]};
  sl_error err;
  sl_volume_init(v, nx, ny, nz, origin, spacing, &err);
  sl_volume_add_field(v, SL_CLOUD, &err);
  for (size_t i = 0; i < sl_volume_count(v); ++i) v->eta[SL_CLOUD][i] = (float)eta;
}

static void test_cloud_shadow(void)
{
  /* Flat ground at z = 0 under a uniform layer from 500 to 1500 m wide enough that the sun's ray
   * from the centre leaves through the top: tau = beta * 1000 / sin(elevation). */
  const double lo[3] = {-20000, -20000, 500}, hi[3] = {20000, 20000, 1500};
  sl_volume v;
  uniform_volume(&v, lo, hi, 40, 40, 10, 1e7);
  const int n = 5;
  float h[25] = {0};
  sl_heightfield hf;
  const double origin[2] = {-2000, -2000}, spacing[2] = {1000, 1000};
  sl_heightfield_init(&hf, n, n, origin, spacing, h);
  float albedo[25];
  for (int i = 0; i < 25; ++i) albedo[i] = 0.15f;
  sl_terrain_light_params p = {.terrain = &hf, .volume = &v, .albedo = albedo};
  p.sigma_ext[SL_CLOUD] = 1e-9; /* beta = 0.01 per metre */
  p.asymmetry[SL_CLOUD] = 0.87;
  for (int k = 0; k < 3; ++k) p.sun_irradiance[k] = 1.0, p.sky_radiance[k] = 0.0;
  const double elevations[] = {90, 60, 35, 20};
  for (int e = 0; e < 4; ++e) {
    sl_sun_direction(elevations[e], 130.0, p.sun_direction);
    double radiance[25 * 3];
    float trans[25];
    sl_error err;
    CHECK(sl_terrain_light(&p, radiance, trans, &err) == SL_OK);
    const double tau = 0.01 * 1000.0 / sin(elevations[e] * M_PI / 180.0);
    const float got = trans[2 * n + 2];
    printf("cloud shadow, sun %2.0f deg: transmittance %.6e, exp(-tau) %.6e (tau %.4f)\n", elevations[e], got, exp(-tau),
           tau);
    CHECK_CLOSE(-log(got), tau, 1e-5, 0.0);
    /* Lambert with the sky off: direct sun through the cloud plus the diffusely transmitted
     * part, mu0 (T_d(tau (1 - g)) - exp(-tau)), T_d = 1 / (1 + 3/4 tau'). */
    const double mu0 = sin(elevations[e] * M_PI / 180.0);
    const double diffuse = mu0 * (1.0 / (1.0 + 0.75 * 0.13 * tau) - exp(-tau));
    CHECK_CLOSE(radiance[(2 * n + 2) * 3], 0.15 / M_PI * (mu0 * exp(-tau) + diffuse), 1e-4, 0.0);
  }
  sl_volume_free(&v);
}

/* A plane in the open: L = rho (E_sun cos(incidence) + pi L_sky) / pi (no air, no cloud). */
static void test_lambert(void)
{
  float h[9] = {0};
  sl_heightfield hf;
  const double origin[2] = {0, 0}, spacing[2] = {100, 100};
  sl_heightfield_init(&hf, 3, 3, origin, spacing, h);
  float albedo[9];
  for (int i = 0; i < 9; ++i) albedo[i] = 0.06f;
  sl_terrain_light_params p = {.terrain = &hf, .albedo = albedo,
                               .sun_irradiance = {1.0, 0.8, 0.6}, .sky_radiance = {0.02, 0.03, 0.05}};
  sl_sun_direction(30.0, 200.0, p.sun_direction);
  double radiance[27];
  sl_error err;
  CHECK(sl_terrain_light(&p, radiance, NULL, &err) == SL_OK);
  for (int c = 0; c < 3; ++c)
    CHECK_CLOSE(radiance[4 * 3 + c], 0.06f / M_PI * (p.sun_irradiance[c] * 0.5 + M_PI * p.sky_radiance[c]), 1e-9, 0.0);
  /* With air: the hemisphere quadrature of the sky converges (16 x 32 against 128 x 256). */
  sl_atmosphere atm;
  CHECK(sl_atmosphere_init(&atm, sl_sky_rgb_wavelengths_nm, 3, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, &err) == 0);
  double coarse[3], fine[3];
  CHECK(sl_sky_irradiance(&atm, p.sun_direction, 0.0, 16, 32, NULL, coarse, &err) == 0);
  CHECK(sl_sky_irradiance(&atm, p.sun_direction, 0.0, 128, 256, NULL, fine, &err) == 0);
  printf("clear-sky irradiance at sea level, sun 30 deg: %.5f %.5f %.5f (fine %.5f %.5f %.5f)\n", coarse[0], coarse[1],
         coarse[2], fine[0], fine[1], fine[2]);
  for (int c = 0; c < 3; ++c) CHECK_CLOSE(coarse[c], fine[c], 5e-3, 0.0);
  CHECK(coarse[2] > coarse[0]); /* the sky is blue */
}

/* A wall of height H along y: behind it (away from the sun) the ground is in shadow for a
 * distance H / tan(elevation). */
static void test_wall_shadow(void)
{
  const int nx = 61, ny = 5;
  const double spacing[2] = {50, 50}, origin[2] = {0, 0};
  float *h = calloc(nx * ny, sizeof(float));
  const int wall = 10;
  const double H = 400.0;
  for (int j = 0; j < ny; ++j) h[j * nx + wall] = (float)H;
  sl_heightfield hf;
  sl_heightfield_init(&hf, nx, ny, origin, spacing, h);
  float *albedo = malloc(sizeof(float) * nx * ny);
  for (int i = 0; i < nx * ny; ++i) albedo[i] = 0.2f;
  sl_terrain_light_params p = {.terrain = &hf, .albedo = albedo, .sun_irradiance = {1, 1, 1}};
  const double elevation = 30.0;
  sl_sun_direction(elevation, 270.0, p.sun_direction); /* sun in the west: shadows fall east */
  double *radiance = malloc(sizeof(double) * nx * ny * 3);
  sl_error err;
  CHECK(sl_terrain_light(&p, radiance, NULL, &err) == SL_OK);
  const double length = H / tan(elevation * M_PI / 180.0);
  int wrong = 0;
  for (int i = wall + 2; i < nx; ++i) {
    const double x = (i - wall) * spacing[0];
    if (fabs(x - length) < 1.5 * spacing[0]) continue; /* the wall's slope spans a cell */
    const int lit = radiance[(2 * nx + i) * 3] > 0.0;
    if (lit != (x > length)) ++wrong;
  }
  printf("wall shadow: %.0f m long, %d points on the wrong side\n", length, wrong);
  CHECK(wrong == 0);
  free(h), free(albedo), free(radiance);
}

/* Eye rays stop at the ground. A uniform box of cloud from z = 0 to 2000 m under flat ground at
 * 1000 m: the coverage is 1 - exp(-beta L) with L the chord of the box above the ground alone. */
static void test_rays_stop_at_ground(int light_volume)
{
  const double lo[3] = {-3000, -3000, 0}, hi[3] = {3000, 3000, 2000};
  const double beta = 1.0 / 800.0;
  sl_volume v;
  make_box_volume(&v, 30, 30, 20, lo, hi, beta);
  sl_scene sc = {.volume = &v, .light_volume = light_volume, .slices = 400};
  sl_sun_direction(50.0, 150.0, sc.sun_direction);
  for (int c = 0; c < 3; ++c) sc.sun_irradiance[c] = 1.0;
  sl_camera cam = {.position = {0, -9000, 6000}, .target = {0, 0, 1000}, .up = {0, 0, 1}, .fov_deg = 45,
                   .width = 48, .height = 48};
  const int nx = 41;
  float *h = malloc(sizeof(float) * nx * nx);
  for (int i = 0; i < nx * nx; ++i) h[i] = 1000.0f;
  sl_heightfield hf;
  const double origin[2] = {-20000, -20000}, spacing[2] = {1000, 1000};
  sl_heightfield_init(&hf, nx, nx, origin, spacing, h);
  float *opaque = malloc(sizeof(float) * 48 * 48);
  double worst_t = 0.0;
  for (int q = 0; q < 48 * 48; ++q) {
    double d[3], t;
    sl_camera_ray(&cam, q % 48, q / 48, d);
    const int hit = sl_heightfield_ray(&hf, cam.position, d, INFINITY, &t);
    opaque[q] = hit ? (float)t : INFINITY;
    if (hit) worst_t = fmax(worst_t, fabs(t - (1000.0 - cam.position[2]) / d[2]));
  }
  CHECK(worst_t < 1e-6);
  cam.opaque_distance = opaque;
  sl_image img;
  sl_error err;
  sl_renderer *r = sl_renderer_create(&sc, &err);
  CHECK(r != NULL);
  sl_image_alloc(&img, 48, 48, &err);
  CHECK(sl_renderer_render(r, &cam, &img, NULL, &err) == 0);
  const box_medium above = {.lo = {lo[0], lo[1], 1000}, .hi = {hi[0], hi[1], hi[2]}, .beta = beta};
  double worst = 0.0;
  int covered = 0;
  for (int q = 0; q < 48 * 48; ++q) {
    double d[3];
    sl_camera_ray(&cam, q % 48, q / 48, d);
    const double want = 1.0 - reference_transparency(&above, cam.position, d);
    worst = fmax(worst, fabs(img.rgba[4 * q + 3] - want));
    if (want > 0.01) ++covered;
  }
  printf("%s: coverage of a cloud half under the ground, worst error %.2e over %d covered pixels\n",
         light_volume ? "light volume" : "slicer", worst, covered);
  CHECK(covered > 200);
  CHECK(worst < 2e-3);
  /* A mountain between the camera and a cloud hides it. */
  for (int j = 0; j < nx; ++j)
    for (int i = 0; i < nx; ++i) {
      const double y = origin[1] + j * spacing[1];
      h[j * nx + i] = fabs(y + 5000.0) < 600.0 ? 1500.0f : 0.0f; /* a ridge along x at y = -5 km */
    }
  sl_heightfield_init(&hf, nx, nx, origin, spacing, h);
  cam.position[2] = 1200.0;
  cam.target[2] = 1200.0;
  int hidden = 0, seen = 0, leaks = 0;
  for (int q = 0; q < 48 * 48; ++q) {
    double d[3], t;
    sl_camera_ray(&cam, q % 48, q / 48, d);
    opaque[q] = sl_heightfield_ray(&hf, cam.position, d, INFINITY, &t) ? (float)t : INFINITY;
  }
  CHECK(sl_renderer_render(r, &cam, &img, NULL, &err) == 0);
  const box_medium box = {.lo = {lo[0], lo[1], lo[2]}, .hi = {hi[0], hi[1], hi[2]}, .beta = beta};
  for (int q = 0; q < 48 * 48; ++q) {
    double d[3];
    sl_camera_ray(&cam, q % 48, q / 48, d);
    /* Geometry: the ridge's crest (1500 m, from y = -5.6 to -4.4 km plus its slopes) stands
     * between the camera at y = -9 km and the cloud (y >= -3 km). A ray below the crest's
     * height where it crosses y = -4.4 km hits the ridge before the cloud. */
    const double t_crest = (-4400.0 - cam.position[1]) / d[1];
    const int behind_ridge = d[1] > 0 && cam.position[2] + t_crest * d[2] < 1500.0 - 1.0;
    const double cloud = 1.0 - reference_transparency(&box, cam.position, d);
    if (behind_ridge && cloud > 0.01) {
      ++hidden;
      if (img.rgba[4 * q + 3] != 0.0f) ++leaks;
    } else if (!behind_ridge && cloud > 0.01 && isinf(opaque[q]) && img.rgba[4 * q + 3] > 0.5 * cloud) {
      ++seen;
    }
  }
  printf("%s: behind the ridge %d cloud pixels (%d leak through), %d seen above it\n",
         light_volume ? "light volume" : "slicer", hidden, leaks, seen);
  CHECK(hidden > 100);
  CHECK(leaks == 0);
  CHECK(seen > 20);
  sl_image_free(&img);
  sl_renderer_destroy(r);
  sl_volume_free(&v);
  free(h), free(opaque);
}

int main(void)
{
  test_plane_hits();
  test_cloud_shadow();
  test_lambert();
  test_wall_shadow();
  test_rays_stop_at_ground(0);
  test_rays_stop_at_ground(1);
  return sl_test_finish("terrain");
}
