/* Benchmark (issue 8): glows on a 1920 x 1080 HDR frame with sources at 8 depths, FFT
 * convolution against direct spatial convolution measured in the same run, and APSF
 * evaluations per second. Prints numbers; never fails.
 *
 * Direct convolution of the whole frame with a whole-frame kernel is ~4e14 multiply-adds, so
 * it is measured two ways and extrapolated, as printed:
 *   dense:  every output pixel sums every source pixel, timed on a crop and scaled by the
 *           multiply-add count;
 *   sparse: only the source pixels are scattered into the frame (the best a direct method can
 *           do with few sources), timed on one layer's sources and scaled by the source count. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sl_glow.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static unsigned long long rng = 0x9E3779B97F4A7C15ULL;
static double uniform(void)
{
  rng ^= rng << 13;
  rng ^= rng >> 7;
  rng ^= rng << 17;
  return (rng >> 11) * (1.0 / 9007199254740992.0);
}

int main(int argc, char **argv)
{
  const int W = argc > 2 ? atoi(argv[1]) : 1920, H = argc > 2 ? atoi(argv[2]) : 1080;
  const int n_sources = 400, layers = 8;
  sl_error err = {0};
  sl_image in = {0}, out = {0};
  if (sl_image_alloc(&in, W, H, &err) || sl_image_alloc(&out, W, H, &err)) {
    fprintf(stderr, "%s\n", err.message);
    return 0;
  }
  sl_glow_params p;
  sl_glow_params_defaults(&p);
  p.sigma = 1.0 / 1000.0;
  p.medium.q = 0.9;
  p.medium.albedo = 0.95;
  p.fov_y_deg = 40.0;
  p.threshold = 10.0;
  p.n_layers = layers;
  const double f = sl_glow_focal_px(H, p.fov_y_deg * M_PI / 180.0);
  for (int i = 0; i < W * H; ++i) {
    for (int c = 0; c < 3; ++c) in.rgba[4 * i + c] = 0.02f;
    in.rgba[4 * i + 3] = 1.0f;
    in.depth[i] = 3000.0f;
  }
  /* 2 x 2 lamps at 8 distances (T = 1.2 .. 6, evenly in log T: each sits on a layer). */
  int placed = 0;
  for (int n = 0; n < n_sources; ++n) {
    const int x = 2 + (int)(uniform() * (W - 4)), y = 2 + (int)(uniform() * (H - 4)), layer = n % layers;
    const double T = 1.2 * pow(5.0, layer / (layers - 1.0));
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const int k = (y + j) * W + x + i;
        const double u = (x + i + 0.5 - 0.5 * W) / f, v = (y + j + 0.5 - 0.5 * H) / f;
        in.depth[k] = (float)(T / p.sigma / sqrt(1 + u * u + v * v));
        in.rgba[4 * k + 0] = 200.0f;
        in.rgba[4 * k + 1] = 150.0f;
        in.rgba[4 * k + 2] = 80.0f;
        ++placed;
      }
  }
  double t0 = now();
  sl_glow_workspace *ws = sl_glow_workspace_create(W, H, 0, 0, &err);
  const double t_plan = now() - t0;
  if (!ws) {
    fprintf(stderr, "%s\n", err.message);
    return 0;
  }
  int nx, ny;
  sl_glow_workspace_size(ws, &nx, &ny);
  sl_glow_stats st;
  double t_apply[2];
  for (int rep = 0; rep < 2; ++rep) {
    t0 = now();
    if (sl_glow_apply(ws, &p, &in, &out, &st, &err)) {
      fprintf(stderr, "%s\n", err.message);
      return 0;
    }
    t_apply[rep] = now() - t0;
  }
  printf("frame %d x %d, %d source pixels, %d layers used of %d, transforms %d x %d (double, FFTW_ESTIMATE)\n", W, H,
         st.sources, st.layers_used, layers, nx, ny);
  printf("FFT glow: plan %.3f s; apply %.3f s, again %.3f s (kernels %.3f s, convolutions %.3f s)\n", t_plan, t_apply[0],
         t_apply[1], st.kernel_seconds, st.convolve_seconds);
  for (int l = 0; l < st.layers_used; ++l) printf("  layer %d: T %.3f, %d series terms\n", l, st.layer_T[l], st.layer_terms[l]);

  /* Dense direct convolution on a crop with the crop's whole kernel: measured multiply-add rate. */
  const int cw = 160, ch = 90;
  sl_glow_kernel k;
  sl_glow_kernel_build(&k, &p.medium, 2.0, f, cw - 1, ch - 1, SL_GLOW_FLUENCE, p.tolerance, &err);
  float *crop = malloc(sizeof(float) * cw * ch);
  double *dense = malloc(sizeof(double) * cw * ch);
  for (int i = 0; i < cw * ch; ++i) crop[i] = (float)uniform();
  t0 = now();
  const int kw = 2 * k.rx + 1;
  for (int y = 0; y < ch; ++y)
    for (int x = 0; x < cw; ++x) {
      double s = 0.0;
      for (int sy = 0; sy < ch; ++sy) {
        const double *krow = k.w + (size_t)(y - sy + k.ry) * kw + k.rx + x;
        const float *srow = crop + sy * cw;
        for (int sx = 0; sx < cw; ++sx) s += srow[sx] * krow[-sx];
      }
      dense[y * cw + x] = s;
    }
  const double t_dense = now() - t0;
  const double macs_crop = (double)cw * ch * cw * ch, rate = macs_crop / t_dense;
  const double macs_frame = (double)W * H * W * H * 3.0 * st.layers_used;
  printf("dense direct: crop %d x %d in %.3f s = %.3g multiply-adds/s; whole frame (%.3g multiply-adds, 3 channels x %d "
         "layers) extrapolates to %.3g s\n",
         cw, ch, t_dense, rate, macs_frame, st.layers_used, macs_frame / rate);
  sl_glow_kernel_free(&k);
  free(crop);
  free(dense);

  /* Sparse direct: scatter one layer's source pixels with the whole-frame kernel of that layer. */
  sl_glow_kernel_build(&k, &p.medium, st.layer_T[0], f, W - 1, H - 1, SL_GLOW_FLUENCE, p.tolerance, &err);
  float *acc = calloc((size_t)W * H * 3, sizeof(float));
  int scattered = 0;
  t0 = now();
  const double T0 = st.layer_T[0];
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int i = y * W + x;
      if (in.rgba[4 * i] < p.threshold) continue;
      const double u = (x + 0.5 - 0.5 * W) / f, v = (y + 0.5 - 0.5 * H) / f;
      if (fabs(p.sigma * in.depth[i] * sqrt(1 + u * u + v * v) / T0 - 1.0) > 1e-4) continue;
      ++scattered;
      for (int yy = 0; yy < H; ++yy) {
        const double *krow = k.w + (size_t)(yy - y + k.ry) * (2 * k.rx + 1) + k.rx - x;
        for (int c = 0; c < 3; ++c) {
          const float s = in.rgba[4 * i + c];
          float *o = acc + (size_t)c * W * H + (size_t)yy * W;
          for (int xx = 0; xx < W; ++xx) o[xx] += (float)(s * krow[xx]);
        }
      }
    }
  const double t_sparse = now() - t0;
  printf("sparse direct: %d source pixels of layer 0 in %.3f s; all %d source pixels extrapolate to %.3f s\n", scattered,
         t_sparse, st.sources, t_sparse * st.sources / (scattered ? scattered : 1));
  sl_glow_kernel_free(&k);
  free(acc);

  /* APSF evaluations per second. */
  const double Ts[4] = {1.1, 1.5, 2.0, 5.0};
  for (int i = 0; i < 4; ++i) {
    sl_apsf_series s;
    sl_apsf_series_init(&s, &p.medium, Ts[i], 1e-4, 0, &err);
    const int n = 2000000;
    double sum = 0.0;
    t0 = now();
    for (int j = 0; j < n; ++j) sum += sl_apsf_series_eval(&s, -1.0 + 2.0 * j / n);
    const double t = now() - t0;
    printf("series T %.1f q 0.9 (tolerance 1e-4, %d terms): %.3g evaluations/s (checksum %.6g)\n", Ts[i], s.terms, n / t,
           sum);
    sl_apsf_series_free(&s);
  }
  {
    const int n = 20000;
    double sum = 0.0;
    t0 = now();
    for (int j = 0; j < n; ++j) sum += sl_apsf_single_scatter(&p.medium, 0.8, 0.001 + 3.0 * j / n);
    printf("single scattering (T 0.8): %.3g evaluations/s (checksum %.6g)\n", n / (now() - t0), sum);
  }
  sl_glow_workspace_free(ws);
  sl_image_free(&in);
  sl_image_free(&out);
  return 0;
}
