/* Glows: the FFT convolution against direct convolution, a point source against the 3D PSF
 * projected by hand, energy bookkeeping, depth layers and their blending, eqs. 30-31 on
 * pixels that are not sources, and bad input. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "apsf_reference.h"
#include "sl_glow.h"
#include "sl_testing.h"

static unsigned long long rng = 88172645463325252ULL;
static double uniform(void)
{
  rng ^= rng << 13;
  rng ^= rng >> 7;
  rng ^= rng << 17;
  return (rng >> 11) * (1.0 / 9007199254740992.0);
}

static double kernel_at(const sl_glow_kernel *k, int dx, int dy)
{
  if (abs(dx) > k->rx || abs(dy) > k->ry) return 0.0;
  return k->w[(size_t)(dy + k->ry) * (2 * k->rx + 1) + dx + k->rx];
}

static void direct_convolution(const sl_glow_kernel *k, const float *src, int W, int H, double *out)
{
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      double s = 0.0;
      for (int sy = 0; sy < H; ++sy)
        for (int sx = 0; sx < W; ++sx)
          if (src[sy * W + sx] != 0.0f) s += src[sy * W + sx] * kernel_at(k, x - sx, y - sy);
      out[y * W + x] = s;
    }
}

static void test_fft_equals_direct(void)
{
  const int W = 37, H = 29;
  const sl_apsf_medium m = {0.9, 0.85, NULL, 0};
  const int radii[2][2] = {{0, 0}, {10, 7}}; /* whole frame; a truncated kernel */
  for (int r = 0; r < 2; ++r) {
    sl_error err = {0};
    sl_glow_workspace *ws = sl_glow_workspace_create(W, H, 0, 0, &err);
    CHECK(ws != NULL);
    if (!ws) return;
    sl_glow_kernel k;
    const int rx = radii[r][0] ? radii[r][0] : W - 1, ry = radii[r][1] ? radii[r][1] : H - 1;
    if (sl_glow_kernel_build(&k, &m, 1.8, sl_glow_focal_px(H, 50.0 * REF_PI / 180.0), rx, ry, SL_GLOW_FLUENCE, 1e-6,
                             &err)) {
      CHECK_MSG(0, err.message);
      sl_glow_workspace_free(ws);
      return;
    }
    float *src[3], *acc[3];
    double *want = malloc(sizeof(double) * W * H);
    for (int c = 0; c < 3; ++c) {
      src[c] = calloc(W * H, sizeof(float));
      acc[c] = calloc(W * H, sizeof(float));
      for (int i = 0; i < W * H; ++i)
        if (uniform() < 0.08) src[c][i] = (float)(uniform() * (c == 2 ? 1000.0 : 5.0));
    }
    memset(src[1], 0, sizeof(float) * W * H); /* an empty channel costs nothing and stays 0 */
    CHECK(sl_glow_convolve(ws, &k, (const float *const *)src, acc, 3, &err) == SL_OK);
    for (int c = 0; c < 3; ++c) {
      direct_convolution(&k, src[c], W, H, want);
      double peak = 0.0, worst = 0.0;
      for (int i = 0; i < W * H; ++i) peak = fmax(peak, fabs(want[i]));
      for (int i = 0; i < W * H; ++i) worst = fmax(worst, fabs(acc[c][i] - want[i]));
      char what[96];
      snprintf(what, sizeof what, "FFT vs direct, channel %d, radius %d x %d: %.3g of the peak", c, rx, ry,
               peak > 0 ? worst / peak : worst);
      CHECK_MSG(peak > 0 ? worst <= 1e-5 * peak : worst == 0.0, what);
      if (c == 2) printf("%s\n", what);
    }
    for (int c = 0; c < 3; ++c) {
      free(src[c]);
      free(acc[c]);
    }
    free(want);
    sl_glow_kernel_free(&k);
    sl_glow_workspace_free(ws);
  }
}

/* The 2D PSF by hand from the 3D PSF: a pixel at r pixels from the source sees
 * mu = cos(atan(r / f)) and covers f / (f^2 + r^2)^{3/2} sr; the fluence weight is T^2 S / (4 pi). */
static double psf_by_hand(const sl_apsf_series *s, double f, double dx, double dy)
{
  const double r2 = dx * dx + dy * dy;
  return s->T * s->T * sl_apsf_series_eval(s, cos(atan(sqrt(r2) / f))) / (4.0 * REF_PI) * f /
         ((f * f + r2) * sqrt(f * f + r2));
}

typedef struct psf_plane {
  const sl_apsf_series *s;
  double f;
} psf_plane;
static double psf_on_plane(const void *user, double u, double v)
{
  const psf_plane *p = user;
  return psf_by_hand(p->s, p->f, u, v);
}

/* The share of the series once the unscattered beam e^{-T} is explicit (sl_apsf.h), W0 = 1. */
static double series_share(double T) { return 1.0 - exp(-T); }

static void test_point_source(void)
{
  const int W = 81, H = 61;
  sl_image in = {0}, out = {0};
  sl_error err = {0};
  sl_image_alloc(&in, W, H, &err);
  sl_image_alloc(&out, W, H, &err);
  for (int i = 0; i < W * H * 4; ++i) in.rgba[i] = 0.0f;
  const int sx = 23, sy = 17; /* off-centre: the kernel is the same everywhere */
  for (int c = 0; c < 3; ++c) in.rgba[4 * (sy * W + sx) + c] = c == 0 ? 1.0f : 2.0f;
  sl_glow_params p;
  sl_glow_params_defaults(&p);
  p.fixed_T = 2.0;
  p.medium.q = 0.8;
  p.fov_y_deg = 60.0;
  p.threshold = 0.5;
  p.n_layers = 1;
  p.tolerance = 1e-8;
  sl_glow_workspace *ws = sl_glow_workspace_create(W, H, 0, 0, &err);
  sl_glow_stats st;
  CHECK(ws && sl_glow_apply(ws, &p, &in, &out, &st, &err) == SL_OK);
  CHECK(st.sources == 1 && st.layers_used == 1);
  sl_apsf_series s;
  sl_apsf_series_init(&s, &p.medium, 2.0, 1e-10, 0, &err);
  const double f = sl_glow_focal_px(H, 60.0 * REF_PI / 180.0);
  double worst = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double dx = x - sx, dy = y - sy;
      if (dx * dx + dy * dy < 36.0) continue; /* sub-sampled pixels: below */
      const double want = series_share(2.0) * psf_by_hand(&s, f, dx, dy);
      worst = fmax(worst, fabs(out.rgba[4 * (y * W + x)] - want) / want);
      CHECK_CLOSE(out.rgba[4 * (y * W + x) + 1], 2.0 * want, 1e-4, 0);
    }
  printf("point source: largest relative difference from the projected 3D PSF: %.3g\n", worst);
  CHECK(worst < 1e-4);
  /* The source pixel: the average of the PSF over the pixel (midpoint rule on 64 x 64). */
  double avg = 0.0;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) avg += psf_by_hand(&s, f, (i + 0.5) / 64 - 0.5, (j + 0.5) / 64 - 0.5);
  CHECK_CLOSE(out.rgba[4 * (sy * W + sx)], series_share(2.0) * avg / 4096.0 + exp(-2.0), 1e-4, 0);
  sl_apsf_series_free(&s);
  sl_glow_workspace_free(ws);
  sl_image_free(&in);
  sl_image_free(&out);
}

static void test_energy(void)
{
  /* (a) The convolution conserves what the kernel says: sum(out) = sum over sources of the
   * source times the kernel's sum over the frame's offsets from it. */
  const int W = 48, H = 40;
  const sl_apsf_medium m = {1.0, 0.9, NULL, 0};
  sl_error err = {0};
  sl_glow_workspace *ws = sl_glow_workspace_create(W, H, 0, 0, &err);
  sl_glow_kernel k;
  const double f = sl_glow_focal_px(H, 70.0 * REF_PI / 180.0);
  sl_glow_kernel_build(&k, &m, 1.6, f, W - 1, H - 1, SL_GLOW_FLUENCE, 1e-8, &err);
  float *src = calloc(W * H, sizeof(float)), *acc = calloc(W * H, sizeof(float));
  double want = 0.0;
  for (int n = 0; n < 12; ++n) {
    const int x = (int)(uniform() * W), y = (int)(uniform() * H);
    const float v = (float)(1.0 + 10.0 * uniform());
    src[y * W + x] += v;
    double in_frame = 0.0;
    for (int yy = 0; yy < H; ++yy)
      for (int xx = 0; xx < W; ++xx) in_frame += kernel_at(&k, xx - x, yy - y);
    want += v * in_frame;
  }
  float *srcs[1] = {src}, *accs[1] = {acc};
  sl_glow_convolve(ws, &k, (const float *const *)srcs, accs, 1, &err);
  double got = 0.0;
  for (int i = 0; i < W * H; ++i) got += acc[i];
  CHECK_CLOSE(got, want, 1e-6, 0);
  free(src);
  free(acc);
  sl_glow_kernel_free(&k);
  sl_glow_workspace_free(ws);

  /* (b) The kernel's sum is the fluence the normalisation promises over the frame's solid
   * angle: int T^2 S / (4 pi) dOmega over the frame, by 2D Gauss–Legendre on the image plane. */
  const int R = 100;
  const double fb = sl_glow_focal_px(2 * R + 1, 90.0 * REF_PI / 180.0);
  sl_glow_kernel_build(&k, &m, 2.5, fb, R, R, SL_GLOW_FLUENCE, 1e-10, &err);
  sl_apsf_series s;
  sl_apsf_series_init(&s, &m, 2.5, 1e-12, 0, &err);
  const psf_plane plane = {&s, fb};
  double integral = ref_plane_integral(psf_on_plane, &plane, -(R + 0.5), R + 0.5, -(R + 0.5), R + 0.5, 16);
  integral = series_share(2.5) * integral + exp(-2.5);
  printf("energy: kernel sum over a 90 degree square frame %.8f, quadrature %.8f (whole sphere: 1)\n", k.sum, integral);
  CHECK_CLOSE(k.sum, integral, 2e-4, 0);
  CHECK(k.sum < 1.0);
  sl_apsf_series_free(&s);
  sl_glow_kernel_free(&k);
}

static void fill_scene(sl_image *img, double sky)
{
  for (int i = 0; i < img->width * img->height; ++i) {
    for (int c = 0; c < 3; ++c) img->rgba[4 * i + c] = 0.05f * (c + 1);
    img->rgba[4 * i + 3] = 1.0f;
    img->depth[i] = (float)sky;
  }
}

static void test_layers(void)
{
  /* Sources at T = 1.6 and 3.2 (the two ends: layers 0 and 7 of 8, the others empty) and one
   * at the geometric mean, which must get the mean of the two layers' glows. */
  const int W = 64, H = 48;
  sl_image in = {0}, out = {0}, one = {0};
  sl_error err = {0};
  sl_image_alloc(&in, W, H, &err);
  sl_image_alloc(&out, W, H, &err);
  sl_image_alloc(&one, W, H, &err);
  fill_scene(&in, 1000.0);
  sl_glow_params p;
  sl_glow_params_defaults(&p);
  p.sigma = 1e-3;
  p.fov_y_deg = 30.0;
  p.threshold = 5.0;
  p.n_layers = 2;
  p.attenuate = 0;
  const double f = sl_glow_focal_px(H, 30.0 * REF_PI / 180.0);
  /* On-axis pixels: the view-axis depth is the distance up to the secant. */
  const int xs[3] = {10, 50, 32}, ys[3] = {10, 36, 24};
  const double Ts[3] = {1.6, 3.2, sqrt(1.6 * 3.2)};
  for (int n = 0; n < 3; ++n) {
    const double u = (xs[n] + 0.5 - 0.5 * W) / f, v = (ys[n] + 0.5 - 0.5 * H) / f;
    const int i = ys[n] * W + xs[n];
    in.depth[i] = (float)(Ts[n] / p.sigma / sqrt(1 + u * u + v * v));
    for (int c = 0; c < 3; ++c) in.rgba[4 * i + c] = 100.0f;
  }
  sl_glow_workspace *ws = sl_glow_workspace_create(W, H, 0, 0, &err);
  sl_glow_stats st;
  CHECK(sl_glow_apply(ws, &p, &in, &out, &st, &err) == SL_OK);
  CHECK(st.sources == 3 && st.layers_used == 2);
  CHECK_CLOSE(st.T_min, 1.6, 1e-5, 0);
  CHECK_CLOSE(st.T_max, 3.2, 1e-5, 0);
  /* The middle source alone, as half of each layer's kernel. */
  sl_glow_kernel k0, k1;
  sl_glow_kernel_build(&k0, &p.medium, st.layer_T[0], f, W - 1, H - 1, SL_GLOW_FLUENCE, p.tolerance, &err);
  sl_glow_kernel_build(&k1, &p.medium, st.layer_T[1], f, W - 1, H - 1, SL_GLOW_FLUENCE, p.tolerance, &err);
  double worst = 0.0, peak = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      double want = 0.0;
      for (int n = 0; n < 3; ++n) {
        const sl_glow_kernel *a = n == 0 ? &k0 : &k1;
        want += 100.0 * (n < 2 ? kernel_at(a, x - xs[n], y - ys[n])
                               : 0.5 * (kernel_at(&k0, x - xs[n], y - ys[n]) + kernel_at(&k1, x - xs[n], y - ys[n])));
      }
      int is_src = 0;
      for (int n = 0; n < 3; ++n) is_src |= x == xs[n] && y == ys[n];
      if (!is_src) want += 0.05;
      worst = fmax(worst, fabs(out.rgba[4 * (y * W + x)] - want));
      peak = fmax(peak, want);
    }
  CHECK(worst <= 1e-5 * peak);
  sl_glow_kernel_free(&k0);
  sl_glow_kernel_free(&k1);

  /* Continuity: nudging the middle source's depth by 1e-4 moves its glow by about as much. */
  const int im = ys[2] * W + xs[2];
  in.depth[im] *= 1.0001f;
  CHECK(sl_glow_apply(ws, &p, &in, &one, &st, &err) == SL_OK);
  double change = 0.0;
  for (int i = 0; i < W * H; ++i) change = fmax(change, fabs(one.rgba[4 * i] - out.rgba[4 * i]));
  CHECK(change < 1e-2 * peak);

  /* Eqs. 30-31 without sources: e^{-T} L0 + L_sky (1 - e^{-T}); the sky (infinite depth,
   * no sky distance) untouched. */
  fill_scene(&in, 1500.0);
  for (int x = 0; x < W; ++x) in.depth[x] = INFINITY;
  p.attenuate = 1;
  p.airlight[0] = 0.3;
  p.airlight[1] = 0.4;
  p.airlight[2] = 0.5;
  CHECK(sl_glow_apply(ws, &p, &in, &out, &st, &err) == SL_OK);
  CHECK(st.sources == 0 && st.layers_used == 0);
  const double u = (40 + 0.5 - 0.5 * W) / f, v = (30 + 0.5 - 0.5 * H) / f;
  const double t = exp(-1.5 * sqrt(1 + u * u + v * v));
  for (int c = 0; c < 3; ++c) {
    CHECK_CLOSE(out.rgba[4 * (30 * W + 40) + c], 0.05 * (c + 1) * t + (0.3 + 0.1 * c) * (1 - t), 1e-6, 0);
    CHECK(out.rgba[4 * 5 + c] == in.rgba[4 * 5 + c]);
  }
  /* With a sky distance the sky is attenuated too. */
  p.sky_distance = 2000.0;
  CHECK(sl_glow_apply(ws, &p, &in, &out, &st, &err) == SL_OK);
  CHECK(fabs(out.rgba[4 * 5] - in.rgba[4 * 5]) > 0.05); /* airlight 0.3 over 0.05 at T ~ 2 */
  sl_glow_workspace_free(ws);
  sl_image_free(&in);
  sl_image_free(&out);
  sl_image_free(&one);
}

static void test_sphere_from_outside(void)
{
  /* Eq. 28 in a kernel: as the camera comes to the sphere's surface (D/R -> 1) the view from
   * outside becomes the view from inside at T = T_radius (mu -> cos gamma). */
  const sl_apsf_medium m = {1.0, 0.85, NULL, 0};
  const double f = sl_glow_focal_px(41, 60.0 * REF_PI / 180.0);
  sl_glow_kernel in, out;
  sl_error err = {0};
  CHECK(sl_glow_kernel_build(&in, &m, 2.0, f, 20, 20, SL_GLOW_FLUENCE, 1e-9, &err) == SL_OK);
  CHECK(sl_glow_kernel_build_sphere(&out, &m, 2.0, 1.0 + 1e-9, f, 20, 20, 1e-9, &err) == SL_OK);
  double worst = 0.0;
  for (int i = 0; i < 41 * 41; ++i) worst = fmax(worst, fabs(in.w[i] - out.w[i]) / in.w[i]);
  printf("sphere seen from its surface vs from inside: %.3g\n", worst);
  CHECK(worst < 1e-4);
  sl_glow_kernel_free(&out);
  /* Farther away the sphere covers asin(R/D): nothing outside that cone. */
  CHECK(sl_glow_kernel_build_sphere(&out, &m, 2.0, 3.0, f, 20, 20, 1e-9, &err) == SL_OK);
  for (int dy = -20; dy <= 20; ++dy)
    for (int dx = -20; dx <= 20; ++dx) {
      const double g = atan(sqrt((dx + 0.5) * (dx + 0.5) + (dy + 0.5) * (dy + 0.5)) / f);
      if (g > asin(1.0 / 3.0) + 0.05) CHECK(out.w[(dy + 20) * 41 + dx + 20] == 0.0);
    }
  sl_glow_kernel_free(&out);
  CHECK(sl_glow_kernel_build_sphere(&out, &m, 1.2, 3.0, f, 20, 20, 1e-9, &err) == SL_ERR_ARG);
  sl_glow_kernel_free(&in);
}

static void test_bad_input(void)
{
  sl_image in = {0}, out = {0};
  sl_error err = {0};
  sl_image_alloc(&in, 8, 8, &err);
  sl_image_alloc(&out, 8, 8, &err);
  fill_scene(&in, 100.0);
  sl_glow_params p;
  sl_glow_params_defaults(&p);
  sl_glow_workspace *ws = sl_glow_workspace_create(8, 8, 0, 0, &err);
  CHECK(sl_glow_apply(ws, &p, &in, &out, NULL, &err) == SL_ERR_ARG); /* no sigma, no T */
  sl_error_clear(&err);
  p.sigma = 1e-3;
  float *depth = in.depth;
  in.depth = NULL;
  CHECK(sl_glow_apply(ws, &p, &in, &out, NULL, &err) == SL_ERR_ARG); /* no depth */
  CHECK(strstr(err.message, "depth") != NULL);
  in.depth = depth;
  sl_error_clear(&err);
  in.depth[3] = NAN;
  CHECK(sl_glow_apply(ws, &p, &in, &out, NULL, &err) == SL_ERR_DATA);
  sl_error_clear(&err);
  sl_apsf_series s;
  const sl_apsf_medium m = {1.0, 0.9, NULL, 0};
  CHECK(sl_apsf_series_init(&s, &m, 1.0, 1e-3, 0, &err) == SL_ERR_ARG); /* T = 1 diverges */
  sl_error_clear(&err);
  CHECK(sl_apsf_series_init(&s, &m, 1.0 + 1e-7, 1e-3, 0, &err) == SL_ERR_ARG); /* too many terms */
  sl_glow_workspace_free(ws);
  sl_image_free(&in);
  sl_image_free(&out);
}

int main(void)
{
  test_fft_equals_direct();
  test_point_source();
  test_energy();
  test_layers();
  test_sphere_from_outside();
  test_bad_input();
  return sl_test_finish("test_glow");
}
