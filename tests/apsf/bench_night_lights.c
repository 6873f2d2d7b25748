/* Benchmark (issue 8, night scenes): a town of 2500 lamps on a 1920 x 1080 frame, what the lamps
 * themselves cost (projection, ray stops, drawing) against what their glow costs, and the glow of
 * the lamps at their own depths (layers spread over the town) against the same lamps put at one
 * depth (one layer), measured in the same run. Prints numbers and ratios; never fails. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sl_glow.h"
#include "sl_point_lights.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static double glow_seconds(sl_glow_workspace *ws, const sl_glow_params *p, const sl_image *in, sl_image *out,
                           sl_glow_stats *st)
{
  sl_error err = {0};
  const double t0 = now();
  if (sl_glow_apply(ws, p, in, out, st, &err)) fprintf(stderr, "glow: %s\n", err.message);
  return now() - t0;
}

int main(int argc, char **argv)
{
  const int W = argc > 2 ? atoi(argv[1]) : 1920, H = argc > 2 ? atoi(argv[2]) : 1080, reps = 5;
  sl_error err = {0};
  sl_camera cam;
  memset(&cam, 0, sizeof cam);
  const double eye[3] = {10000, -10000, 1200}, target[3] = {0, 0, 2500};
  memcpy(cam.position, eye, sizeof eye);
  memcpy(cam.target, target, sizeof target);
  cam.up[2] = 1.0;
  cam.fov_deg = 50.0;
  cam.width = W, cam.height = H;
  sl_light_grid g = {{0, 0}, {50, 50}, 200.0, 10.0, 0.6, 1000.0, {1.0, 0.29, 0.01}, 1};
  const int n = g.count[0] * g.count[1];
  sl_point_light *lights = malloc(sizeof *lights * n);
  sl_light_pixel *lp = malloc(sizeof *lp * n);
  float *opaque = malloc(sizeof(float) * W * H);
  unsigned char *mask = calloc((size_t)W * H, 1);
  sl_image in = {0}, out = {0};
  if (!lights || !lp || !opaque || !mask || sl_image_alloc(&in, W, H, &err) || sl_image_alloc(&out, W, H, &err)) {
    fprintf(stderr, "out of memory\n");
    return 0;
  }
  for (int i = 0; i < W * H; ++i) {
    for (int c = 0; c < 3; ++c) in.rgba[4 * i + c] = 1e-8f;
    in.rgba[4 * i + 3] = 0.0f;
    in.depth[i] = INFINITY;
    in.transparency[i] = 1.0f;
  }
  /* The lamps: grid, projection, ray stops, drawing (best of reps). */
  int m = 0;
  double t_lamps = 1e30;
  for (int r = 0; r < reps; ++r) {
    for (int i = 0; i < W * H; ++i) opaque[i] = INFINITY;
    const double t0 = now();
    sl_light_grid_build(&g, lights, &err);
    sl_point_lights_project(&cam, lights, n, lp, &m, &err);
    sl_point_lights_stop_rays(lp, m, opaque);
    sl_point_lights_draw(lp, m, in.transparency, &in, mask);
    t_lamps = fmin(t_lamps, now() - t0);
  }
  sl_glow_params p;
  sl_glow_params_defaults(&p);
  p.medium.q = 0.65;
  p.medium.albedo = 0.94;
  p.sigma = 3.912 / 25000.0;
  p.bank_depth = 12000.0;
  p.sky_distance = 12000.0;
  p.fov_y_deg = cam.fov_deg;
  p.threshold = 1.0;
  p.source_mask = mask;
  sl_glow_workspace *ws = sl_glow_workspace_create(W, H, 0, 0, &err);
  if (!ws) {
    fprintf(stderr, "%s\n", err.message);
    return 0;
  }
  sl_glow_stats st_depths, st_one;
  double t_depths = 1e30, t_one = 1e30;
  for (int r = 0; r < 2; ++r) t_depths = fmin(t_depths, glow_seconds(ws, &p, &in, &out, &st_depths));
  /* Peer: the same lamps all at one distance (the town's middle, 9 km): one layer. */
  sl_glow_params one = p;
  one.fixed_T = p.sigma * 9000.0;
  for (int r = 0; r < 2; ++r) t_one = fmin(t_one, glow_seconds(ws, &one, &in, &out, &st_one));
  printf("night lights, %d x %d, %d lamps (%d in the frame)\n", W, H, n, m);
  printf("  lamps (grid, projection, ray stops, drawing): %.3f ms\n", 1e3 * t_lamps);
  printf("  glow at their own depths: %.3f s, %d layers (T %.3f..%.3f), kernels %.3f s, FFT %.3f s\n", t_depths,
         st_depths.layers_used, st_depths.T_min, st_depths.T_max, st_depths.kernel_seconds, st_depths.convolve_seconds);
  printf("  glow at one depth (peer): %.3f s, %d layer\n", t_one, st_one.layers_used);
  printf("  ratio depths / one depth: %.2f; lamps / glow at their depths: %.2e\n", t_depths / t_one, t_lamps / t_depths);
  sl_glow_workspace_free(ws);
  sl_image_free(&in);
  sl_image_free(&out);
  free(lights);
  free(lp);
  free(opaque);
  free(mask);
  return 0;
}
