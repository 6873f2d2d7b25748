/* Sky benchmark (issue 5): per-sample in-scattering evaluations per second, the whole-frame sky
 * cost at 1024x1024 (three wavelengths plus the sun disk, one thread), the round-earth air mass
 * and the solar position. Prints numbers; never fails. Usage: bench_sky [size] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "quadrature.h"
#include "sl_sky.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char **argv)
{
  const int size = argc > 1 ? atoi(argv[1]) : 1024;
  const double kPi = 3.14159265358979323846;
  sl_atmosphere atm;
  sl_atmosphere_init(&atm, sl_sky_rgb_wavelengths_nm, 3, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, NULL);
  const double gamma = 1.0 / atm.scale_height, eye[3] = {0, 0, 1500.0};
  double sun[3];
  sl_sun_direction(8.0, 120.0, sun);

  /* 1. per-sample evaluations: varied rays so nothing is hoisted */
  const int n = 4000000;
  volatile double sink = 0.0;
  double t0 = now();
  double acc = 0.0;
  for (int i = 0; i < n; ++i) {
    double mu = -0.2 + 1.2 * (i % 1000) / 1000.0;
    double K = (i & 1) ? INFINITY : 1e3 + 37.0 * (i % 5000);
    acc += sl_sky_inscatter(atm.beta_sea_level[i % 3], gamma, 1500.0, mu, sl_sky_segment_length(1500.0, mu, K, 0.0),
                            1.0 / sun[2], 0.3);
  }
  double t1 = now();
  sink = acc;
  printf("sl_sky_inscatter: %.1f M evaluations/s (%.1f ns each, one thread)\n", n / (t1 - t0) * 1e-6,
         (t1 - t0) / n * 1e9);
  const double t_closed = (t1 - t0) / n;

  /* 1b. the peer: the same integral (eq. 8) by adaptive quadrature, as a renderer without the
   * closed form would have to */
  const int nq = 2000;
  t0 = now();
  acc = 0.0;
  for (int i = 0; i < nq; ++i) {
    double mu = -0.2 + 1.2 * (i % 1000) / 1000.0;
    double K = (i & 1) ? INFINITY : 1e3 + 37.0 * (i % 5000);
    ref_sky s = {atm.beta_sea_level[i % 3], gamma, 1500.0, mu, 1.0 / sun[2], sl_sky_rayleigh_phase(0.3)};
    acc += ref_sky_radiance(&s, K, 1e-6);
  }
  double tq = (now() - t0) / nq;
  sink = acc;
  printf("quadrature of eq. 8 to 1e-6: %.1f us each; closed form is %.0fx faster\n", tq * 1e6,
         tq / t_closed);

  /* 2. whole frame: panorama-like direction per pixel, 3 wavelengths + sun disk */
  float *rgb = malloc(sizeof(float) * 3 * (size_t)size * size);
  t0 = now();
  double airmass = sl_sky_airmass(&atm, eye[2], sun[2]);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      double az = 2.0 * kPi * (x + 0.5) / size, el = 0.5 * kPi - kPi * (y + 0.5) / size;
      double dir[3] = {cos(el) * sin(az), cos(el) * cos(az), sin(el)};
      double K = sl_sky_segment_length(eye[2], dir[2], INFINITY, 0.0);
      double cvs = dir[0] * sun[0] + dir[1] * sun[1] + dir[2] * sun[2];
      double disk[3];
      sl_sky_sun_disk_radiance(&atm, eye, dir, sun, disk);
      for (int c = 0; c < 3; ++c)
        rgb[3 * ((size_t)y * size + x) + c] =
            (float)(sl_sky_inscatter(atm.beta_sea_level[c], gamma, eye[2], dir[2], K, airmass, cvs) + disk[c]);
    }
  t1 = now();
  sink = rgb[size / 2 * 3];
  printf("whole-frame sky %dx%d, 3 wavelengths + sun disk: %.1f ms (one thread)\n", size, size, (t1 - t0) * 1e3);
  free(rgb);

  /* 2b. the renderer's use: front [0, t_mid] and back [t_mid, inf) per pixel through sl_sky_view */
  rgb = malloc(sizeof(float) * 3 * (size_t)size * size);
  t0 = now();
  sl_sky_view view;
  sl_sky_view_init(&view, &atm, eye, sun, NULL);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      double az = 2.0 * kPi * (x + 0.5) / size, el = 0.5 * kPi - kPi * (y + 0.5) / size;
      double dir[3] = {cos(el) * sin(az), cos(el) * cos(az), sin(el)};
      double front[3], tfront[3], back[3], disk[3];
      sl_sky_view_segment(&view, dir, 0.0, 2e4, front, tfront);
      sl_sky_view_segment(&view, dir, 2e4, INFINITY, back, NULL);
      sl_sky_sun_disk_radiance(&atm, eye, dir, sun, disk);
      for (int c = 0; c < 3; ++c) rgb[3 * ((size_t)y * size + x) + c] = (float)(front[c] + back[c] + disk[c]);
    }
  t1 = now();
  sink = rgb[size / 2 * 3];
  printf("whole-frame sky %dx%d split front/back at 20 km (sl_sky_view_segment x2 + disk): %.1f ms (one thread)\n",
         size, size, (t1 - t0) * 1e3);
  free(rgb);

  /* 3. round-earth air mass (Chapman quadrature), once per frame or per light column */
  const int nc = 20000;
  t0 = now();
  acc = 0.0;
  for (int i = 0; i < nc; ++i) acc += sl_chapman(796.0 + (i % 100) * 0.1, (i % 1000) / 1000.0);
  t1 = now();
  sink = acc;
  printf("sl_chapman: %.2f us per call\n", (t1 - t0) / nc * 1e6);

  /* 4. solar position */
  t0 = now();
  acc = 0.0;
  for (int i = 0; i < nc; ++i) {
    sl_utc t = {2024, 6, 21, i % 24, i % 60, 0.0};
    sl_solar_position p;
    sl_solar_position_compute(&t, 40.0, -105.0, NULL, &p, NULL);
    acc += p.elevation_deg;
  }
  t1 = now();
  sink = acc;
  printf("sl_solar_position_compute: %.2f us per call\n", (t1 - t0) / nc * 1e6);
  (void)sink;
  return 0;
}
