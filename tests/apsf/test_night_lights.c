/* Emissive lights in a rendered frame (render/volume/sl_point_lights.h) through the glow
 * (render/apsf): photometry by the inverse-square law, the halo of one lamp in a homogeneous haze
 * against the projected 3D PSF summed independently (apsf_reference.h), its energy against a
 * quadrature of the PSF over the frame, the cloud's transmittance against Beer-Lambert through a
 * uniform slab, an opaque cloud hiding a lamp, depth ordering through a haze bank, and the
 * airlight closed form (eq. 31) against the radiative-transfer integral it solves. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "apsf_reference.h"
#include "sl_glow.h"
#include "sl_point_lights.h"
#include "sl_renderer.h"
#include "sl_testing.h"

/* Eq. 27 brute force (apsf_reference.h's g_m) with its coefficients summed once per (T, q). */
typedef struct brute_series {
  int terms;
  long double c[256];
} brute_series;
static void brute_init(brute_series *b, double T, double q, int terms)
{
  b->terms = terms;
  for (int l = 0; l < terms; ++l) b->c[l] = ref_g(l, T, q, 1.0) + ref_g(l + 1, T, q, 1.0);
}
static double brute_eval(const brute_series *b, double mu)
{
  long double sum = b->c[0], p0 = 1.0L, p1 = mu;
  if (b->terms > 1) sum += b->c[1] * p1;
  for (int l = 2; l < b->terms; ++l) {
    const long double pl = ((2.0L * l - 1.0L) * mu * p1 - (l - 1.0L) * p0) / l;
    sum += b->c[l] * pl;
    p0 = p1;
    p1 = pl;
  }
  return (double)sum;
}

/* The fluence weight T^2 S / (4 pi) times the solid angle of a unit pixel at (u, v) pixels from
 * the principal point: the 2D PSF on the image plane. */
typedef struct halo_plane {
  const brute_series *bs;
  double f, T;
} halo_plane;
static double halo_on_plane(const void *user, double u, double v)
{
  const halo_plane *h = user;
  const double r2 = u * u + v * v, f = h->f;
  return h->T * h->T * brute_eval(h->bs, 1.0 / sqrt(1.0 + r2 / (f * f))) / (4.0 * REF_PI) * f / ((f * f + r2) * sqrt(f * f + r2));
}

/* An empty frame: black, nothing in front (depth +inf, transparency 1). */
static void blank_frame(sl_image *img)
{
  for (int i = 0; i < img->width * img->height; ++i) {
    for (int c = 0; c < 4; ++c) img->rgba[4 * i + c] = 0.0f;
    img->depth[i] = INFINITY;
    img->transparency[i] = 1.0f;
  }
}

/* A camera on the y axis looking along +y at height z0, odd size: the centre pixel's centre is
 * the principal point. */
static sl_camera axis_camera(double y0, double z0, int W, int H, double fov)
{
  sl_camera cam;
  memset(&cam, 0, sizeof cam);
  cam.position[0] = 0.0, cam.position[1] = y0, cam.position[2] = z0;
  cam.target[0] = 0.0, cam.target[1] = y0 + 1000.0, cam.target[2] = z0;
  cam.up[2] = 1.0;
  cam.fov_deg = fov;
  cam.width = W, cam.height = H;
  return cam;
}

static void test_photometry(void)
{
  /* A 1000 cd white lamp at 5 km: illuminance 1000 / 5000^2 = 4e-5 lx, in sun units / 128000 lx;
   * the pixel's radiance times its solid angle gives it back, wherever the lamp lands. */
  const int W = 101, H = 81;
  sl_camera cam = axis_camera(0.0, 100.0, W, H, 40.0);
  const double white[3] = {1, 1, 1};
  sl_point_light l[3];
  sl_photometric_to_render(1000.0, white, l[0].intensity);
  CHECK_CLOSE(l[0].intensity[1], 1000.0 / 128000.0, 1e-12, 0);
  const double pos[3][3] = {{0, 5000, 100}, {1200, 5000, -600}, {0, -5000, 100}}; /* centre, off-axis, behind */
  for (int k = 0; k < 3; ++k) {
    memcpy(l[k].position, pos[k], sizeof pos[k]);
    memcpy(l[k].intensity, l[0].intensity, sizeof l[0].intensity);
  }
  sl_light_pixel lp[3];
  int n = 0;
  sl_error err = {0};
  CHECK(sl_point_lights_project(&cam, l, 3, lp, &n, &err) == SL_OK);
  CHECK(n == 2); /* the lamp behind the camera is not drawn */
  const double f = 0.5 * H / tan(20.0 * REF_PI / 180.0);
  for (int k = 0; k < n; ++k) {
    const int px = (int)(lp[k].pixel % W), py = (int)(lp[k].pixel / W);
    const double u = (px + 0.5 - 0.5 * W) / f, v = (py + 0.5 - 0.5 * H) / f;
    const double solid_angle = 1.0 / (f * f) / pow(1.0 + u * u + v * v, 1.5);
    const double d2 = pos[k][0] * pos[k][0] + pos[k][1] * pos[k][1] + (pos[k][2] - 100.0) * (pos[k][2] - 100.0);
    CHECK_CLOSE(lp[k].radiance[0] * solid_angle, 1000.0 / d2 / 128000.0, 1e-9, 0);
    CHECK_CLOSE(lp[k].depth, pos[k][1], 1e-9, 0);
  }
  /* Where the off-axis lamp lands: x = f X / Y to the right, y = f Z / Y down from the centre. */
  CHECK((int)(lp[1].pixel % W) == (int)floor(0.5 * W + f * 1200.0 / 5000.0));
  CHECK((int)(lp[1].pixel / W) == (int)floor(0.5 * H + f * 700.0 / 5000.0));
  /* Colour: unit luminance whatever the weights. */
  const double sodium[3] = {1.0, 0.29, 0.01};
  double I[3];
  sl_photometric_to_render(1.0, sodium, I);
  CHECK_CLOSE(0.2126 * I[0] + 0.7152 * I[1] + 0.0722 * I[2], 1.0 / 128000.0, 1e-12, 0);
}

/* One lamp straight ahead at distance d in a homogeneous haze with T = sigma d: the glowed frame
 * against the projected 3D PSF (eq. 27 summed by brute force, the code's documented
 * normalisation: fluence weight T^2 S / (4 pi), the series scaled by 1 - e^{-T} next to the
 * Dirac e^{-T} for W0 = 1), and its energy against the PSF integrated over the frame. */
static void test_lamp_halo(void)
{
  const int W = 129, H = 129;
  const double d = 4000.0, T = 2.5, q = 0.8, fov = 40.0;
  sl_camera cam = axis_camera(0.0, 50.0, W, H, fov);
  sl_point_light l = {{0.0, d, 50.0}, {0.01, 0.02, 0.03}};
  sl_light_pixel lp;
  int n = 0;
  sl_error err = {0};
  sl_image img = {0};
  sl_image_alloc(&img, W, H, &err);
  blank_frame(&img);
  unsigned char *mask = calloc((size_t)W * H, 1);
  CHECK(sl_point_lights_project(&cam, &l, 1, &lp, &n, &err) == SL_OK && n == 1);
  CHECK(lp.pixel == (size_t)(H / 2) * W + W / 2);
  sl_point_lights_draw(&lp, n, img.transparency, &img, mask);
  CHECK(mask[lp.pixel] == 1 && img.depth[lp.pixel] == (float)d);
  const double L0 = img.rgba[4 * lp.pixel + 1];
  sl_glow_params p;
  sl_glow_params_defaults(&p);
  p.medium.albedo = 1.0, p.medium.q = q;
  p.sigma = T / d;
  p.fov_y_deg = fov;
  p.threshold = 1e30; /* the mask alone makes the lamp a source */
  p.source_mask = mask;
  p.tolerance = 1e-9;
  sl_glow_workspace *ws = sl_glow_workspace_create(W, H, 0, 0, &err);
  sl_image out = {0};
  sl_image_alloc(&out, W, H, &err);
  sl_glow_stats st;
  CHECK(ws && sl_glow_apply(ws, &p, &img, &out, &st, &err) == SL_OK);
  CHECK(st.sources == 1);
  CHECK_CLOSE(st.T_min, T, 1e-6, 0);
  const double f = sl_glow_focal_px(H, fov * REF_PI / 180.0);
  const double share = 1.0 - exp(-T);
  brute_series bs;
  brute_init(&bs, T, q, 200);
  double worst = 0.0, sum = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double dx = x - W / 2, dy = y - H / 2, r2 = dx * dx + dy * dy;
      const double got = out.rgba[4 * ((size_t)y * W + x) + 1];
      sum += got;
      if (r2 < 36.0) continue; /* sub-pixel averaged near the lamp (test_glow checks that part) */
      const halo_plane at = {&bs, f, T};
      const double want = L0 * share * halo_on_plane(&at, dx, dy);
      worst = fmax(worst, fabs(got - want) / want);
    }
  printf("lamp halo: largest relative difference from the brute-force projected PSF beyond 6 px: %.3g\n", worst);
  CHECK(worst < 2e-4);
  /* Energy: the frame holds e^{-T} (the direct beam) plus the series' fluence inside the frame,
   * int T^2 S / (4 pi) dOmega by Gauss-Legendre on the image plane (16 x 16 panels of 24 x 24). */
  const halo_plane plane = {&bs, f, T};
  const double integral = ref_plane_integral(halo_on_plane, &plane, -0.5 * W, 0.5 * W, -0.5 * H, 0.5 * H, 16);
  const double want_sum = L0 * (exp(-T) + share * integral);
  printf("lamp energy: frame %.8g, e^-T + fluence in the frame by quadrature %.8g (of %.8g)\n", sum, want_sum, L0);
  CHECK_CLOSE(sum, want_sum, 5e-4, 0);
  sl_glow_workspace_free(ws);
  sl_image_free(&img);
  sl_image_free(&out);
  free(mask);
}

/* The renderer's transmittance to the lamps: a uniform cloud slab (Table 2 droplets, sigma_ex =
 * 2 pi (10 um)^2) between the camera and some of them. */
static void test_cloud_between(void)
{
  sl_error err = {0};
  sl_volume v;
  const int N = 10;
  const double spacing[3] = {200.0, 200.0, 200.0}, origin[3] = {-900.0, -900.0, 100.0};
  CHECK(sl_volume_init(&v, N, N, N, origin, spacing, &err) == SL_OK);
  CHECK(sl_volume_add_field(&v, SL_CLOUD, &err) == SL_OK);
  const double sigma_ex = 2.0 * REF_PI * 10e-6 * 10e-6;
  const double betas[2] = {1e-3, 0.05}; /* tau = 2 across the 2 km box; tau = 100: opaque */
  for (int b = 0; b < 2; ++b) {
    for (size_t i = 0; i < sl_volume_count(&v); ++i) v.eta[SL_CLOUD][i] = (float)(betas[b] / sigma_ex);
    sl_scene sc;
    memset(&sc, 0, sizeof sc);
    sc.volume = &v;
    sc.sun_direction[2] = 1.0;
    sc.sun_irradiance[0] = sc.sun_irradiance[1] = sc.sun_irradiance[2] = 1.0;
    sc.lighting = SL_LIGHTING_LOW_ALBEDO;
    sc.termination_transparency = 1e-6;
    sl_renderer *r = sl_renderer_create(&sc, &err);
    CHECK(r != NULL);
    const int W = 61, H = 41;
    sl_camera cam = axis_camera(-6000.0, 1000.0, W, H, 30.0);
    /* Behind the slab on the axis; in front of it; beside it (its ray misses the box). */
    sl_point_light l[3] = {{{0.0, 3000.0, 1000.0}, {1, 1, 1}},
                           {{600.0, -3000.0, 1000.0}, {1, 1, 1}},
                           {{3000.0, 3000.0, 1000.0}, {1, 1, 1}}};
    sl_light_pixel lp[3];
    int n = 0;
    CHECK(sl_point_lights_project(&cam, l, 3, lp, &n, &err) == SL_OK && n == 3);
    float *opaque = malloc(sizeof(float) * W * H);
    for (int i = 0; i < W * H; ++i) opaque[i] = INFINITY;
    sl_point_lights_stop_rays(lp, n, opaque);
    cam.opaque_distance = opaque;
    sl_image img = {0};
    sl_image_alloc(&img, W, H, &err);
    CHECK(sl_renderer_render(r, &cam, &img, NULL, &err) == SL_OK);
    for (int i = 0; i < W * H * 4; ++i) img.rgba[i] = 0.0f;
    sl_point_lights_draw(lp, n, img.transparency, &img, NULL);
    const double seen[3] = {img.rgba[4 * lp[0].pixel], img.rgba[4 * lp[1].pixel], img.rgba[4 * lp[2].pixel]};
    if (b == 0) {
      /* Beer-Lambert through 1.8 km of the box (y from -900 - 100 to 900 + 100: the box spans the
       * cells, sample centres +- half a cell) at beta: tau = 2. */
      CHECK_CLOSE(seen[0] / lp[0].radiance[0], exp(-betas[0] * 2000.0), 2e-3, 0);
      printf("cloud between: transmittance %.6f against exp(-2) = %.6f\n", seen[0] / lp[0].radiance[0], exp(-2.0));
    } else {
      printf("opaque cloud: the lamp behind keeps %.3g of its light\n", seen[0] / lp[0].radiance[0]);
      CHECK(seen[0] <= 1e-6 * lp[0].radiance[0]);
    }
    CHECK_CLOSE(seen[1], lp[1].radiance[0], 1e-6, 0); /* in front of the cloud: untouched */
    CHECK_CLOSE(seen[2], lp[2].radiance[0], 1e-6, 0); /* beside it */
    sl_image_free(&img);
    free(opaque);
    sl_renderer_destroy(r);
  }
  sl_volume_free(&v);
}

/* Depth ordering through a haze bank 5 km deep: a lamp at 3 km gets T = 3 sigma, lamps at 9 and
 * 12 km are seen through all of the bank, T = 5 sigma, and sit in the farther layer. */
static void test_depth_ordering(void)
{
  const int W = 65, H = 49;
  sl_camera cam = axis_camera(0.0, 20.0, W, H, 40.0);
  const double sigma = 0.4e-3;
  sl_point_light l[3] = {{{-300.0, 3000.0, 0.0}, {1, 1, 1}}, {{900.0, 9000.0, 0.0}, {1, 1, 1}},
                         {{-1500.0, 12000.0, 0.0}, {1, 1, 1}}};
  sl_light_pixel lp[3];
  int n = 0;
  sl_error err = {0};
  CHECK(sl_point_lights_project(&cam, l, 3, lp, &n, &err) == SL_OK && n == 3);
  sl_image img = {0}, out = {0};
  sl_image_alloc(&img, W, H, &err);
  sl_image_alloc(&out, W, H, &err);
  blank_frame(&img);
  unsigned char *mask = calloc((size_t)W * H, 1);
  sl_point_lights_draw(lp, n, NULL, &img, mask);
  sl_glow_params p;
  sl_glow_params_defaults(&p);
  p.medium.q = 0.7;
  p.sigma = sigma;
  p.bank_depth = 5000.0;
  p.fov_y_deg = 40.0;
  p.threshold = 1e30;
  p.source_mask = mask;
  sl_glow_workspace *ws = sl_glow_workspace_create(W, H, 0, 0, &err);
  sl_glow_stats st;
  CHECK(ws && sl_glow_apply(ws, &p, &img, &out, &st, &err) == SL_OK);
  const double d_near = sqrt(300.0 * 300.0 + 3000.0 * 3000.0 + 20.0 * 20.0);
  printf("depth ordering: %d sources in %d layers, T %.4f (near lamp %.4f) to %.4f (bank %.4f)\n", st.sources,
         st.layers_used, st.T_min, sigma * d_near, st.T_max, sigma * 5000.0);
  CHECK(st.sources == 3 && st.layers_used == 2);
  /* The distance comes from the pixel centre's ray (the lamp sits within half a pixel of it). */
  CHECK_CLOSE(st.T_min, sigma * d_near, 2e-3, 0);
  CHECK_CLOSE(st.T_max, sigma * 5000.0, 1e-9, 0);
  CHECK(st.T_max > st.T_min);
  sl_glow_workspace_free(ws);
  sl_image_free(&img);
  sl_image_free(&out);
  free(mask);
}

/* Eq. 31's closed form against the transfer equation it solves, dL/dtau = -L + J, integrated
 * as L(T) = L0 e^{-T} + int_0^T J e^{-t} dt by Simpson's rule; and J of uniform hemispheres for a
 * horizontal sight line against the phase-function integral over the sphere (HG, Gauss-Legendre
 * in cos, trapezoid in azimuth). */
static void test_airlight(void)
{
  const double L0 = 0.3, J = 0.8;
  const double Ts[4] = {0.01, 0.5, 2.0, 7.0};
  for (int k = 0; k < 4; ++k) {
    const int n = 2000;
    const double h = Ts[k] / n;
    double integral = 0.0;
    for (int i = 0; i <= n; ++i) integral += (i == 0 || i == n ? 1 : i % 2 ? 4 : 2) * J * exp(-i * h);
    integral *= h / 3.0;
    CHECK_CLOSE(sl_airlight_path(L0, J, Ts[k]), L0 * exp(-Ts[k]) + integral, 1e-12, 0);
  }
  /* J along a sight line at elevation e against W0/(4 pi) int P(d.w) L(w) dw over the sphere
   * (P normalised to mean 1, ref_hg): composite Gauss-Legendre in cos per hemisphere (the radiance
   * jumps at the horizon; 32 panels of 16 nodes resolve q = 0.9's forward peak) x 1024 azimuths
   * (periodic and smooth in azimuth: the trapezoid converges fast). */
  enum { NG = 16, PANELS = 32, NPHI = 1024 };
  double x[NG], w[NG];
  ref_gauss(NG, x, w);
  const double qs[3] = {0.0, 0.65, 0.9}, elev_deg[5] = {0.0, 5.0, 15.0, -10.0, 60.0};
  const double W0 = 0.94, L_up = 1.0, L_down = 0.15;
  double worst = 0.0;
  for (int a = 0; a < 3; ++a) {
    CHECK_CLOSE(sl_airlight_upper_share(qs[a], 0.0), 0.5, 1e-12, 0); /* the mirror symmetry */
    for (int e = 0; e < 5; ++e) {
      const double el = elev_deg[e] * REF_PI / 180.0, d[3] = {cos(el), 0.0, sin(el)};
      double sum = 0.0;
      for (int h = 0; h < 2; ++h)
        for (int pn = 0; pn < PANELS; ++pn)
          for (int i = 0; i < NG; ++i) {
            const double z = (pn + 0.5 * (x[i] + 1.0)) / PANELS, ct = h ? -z : z, st = sqrt(1.0 - ct * ct);
            double ring = 0.0;
            for (int j = 0; j < NPHI; ++j) {
              const double ph = 2.0 * REF_PI * (j + 0.5) / NPHI;
              ring += ref_hg(qs[a], d[0] * st * cos(ph) + d[2] * ct);
            }
            sum += 0.5 * w[i] / PANELS * (2.0 * REF_PI / NPHI) * ring * (h ? L_down : L_up);
          }
      const double quad = W0 * sum / (4.0 * REF_PI);
      const double code = sl_airlight_source(W0, qs[a], el, L_up, L_down);
      const double horizontal = sl_airlight_source(W0, qs[a], 0.0, L_up, L_down);
      worst = fmax(worst, fabs(code / quad - 1.0));
      printf("airlight: q %.2f, sight line %+5.1f deg: J sphere quadrature %.6f, code %.6f, horizontal value %.6f "
             "(%+.1f %%)\n",
             qs[a], elev_deg[e], quad, code, horizontal, 100.0 * (horizontal / quad - 1.0));
    }
  }
  printf("airlight: J against the sphere quadrature, largest relative difference %.2g\n", worst);
  CHECK(worst < 1e-5);
}

int main(void)
{
  test_photometry();
  test_lamp_halo();
  test_cloud_between();
  test_depth_ordering();
  test_airlight();
  return sl_test_finish("night_lights");
}
