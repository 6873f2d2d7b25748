/* Phenomena measured in images rendered with the multiple-scattering lighting: each pixel's
 * angle from the antisolar point (or from the sun) comes from the camera, and the radiance is
 * profiled against it. Also the lighting's thin limits: single scattering with the tabulated
 * phase function, and eq. 24 = eq. 25. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homogeneous_reference.h"
#include "sl_testing.h"

#define NBINS 1800 /* 0.1 degree bins */

/* The same measurements on the GPU path's frames: tests/gpu builds this file with
 * SL_PHENOMENA_GPU and a shim that draws the volume layer with the GPU pass. */
#ifdef SL_PHENOMENA_GPU
int sl_test_gpu_render(const sl_renderer *r, const sl_camera *cam, sl_image *img);
#define RENDER_VOLUME(r, cam, img, err) sl_test_gpu_render(r, cam, img)
#else
#define RENDER_VOLUME(r, cam, img, err) sl_renderer_render(r, cam, img, NULL, err)
#endif

static sl_optics_tables *tables(unsigned particles)
{
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.particles = particles;
  sl_error err = {0};
  sl_optics_tables *t = sl_optics_build(&req, &err);
  if (!t) fprintf(stderr, "optics: %s\n", err.message);
  return t;
}

/* Renders a box of one particle type and profiles radiance / coverage (the box's effective
 * scattered radiance per unit opacity, which removes the path-length dependence) against the
 * angle between each pixel's ray and `axis`, in 0.1 degree bins. */
static void profile(sl_particle particle, const sl_optics_tables *opt, const double lo[3], const double hi[3],
                    double tau_per_m, const double sun[3], const sl_camera *cam, const double axis[3],
                    double prof[3][NBINS], int counts[NBINS])
{
  sl_volume v;
  make_box_volume(&v, 8, 8, 4, lo, hi, 1.0);
  /* make_box_volume fills the cloud field; move it to the requested particle with the table's
   * cross-section so that beta = tau_per_m. */
  double sigma = 0.0;
  for (int c = 0; c < 3; ++c) sigma += sl_optics_table(opt, particle, c)->sigma_ext / 3.0;
  v.eta[particle] = v.eta[SL_CLOUD];
  if (particle != SL_CLOUD) v.eta[SL_CLOUD] = NULL;
  for (size_t i = 0; i < sl_volume_count(&v); ++i) v.eta[particle][i] = (float)(tau_per_m / sigma);
  sl_scene sc = {.volume = &v, .optics = opt, .lighting = SL_LIGHTING_MULTIPLE, .slices = 256};
  memcpy(sc.sun_direction, sun, 3 * sizeof(double));
  for (int c = 0; c < 3; ++c) sc.sun_irradiance[c] = 1.0;
  sl_error err = {0};
  sl_renderer *r = sl_renderer_create(&sc, &err);
  if (!r) fprintf(stderr, "%s\n", err.message);
  sl_image img;
  sl_image_alloc(&img, cam->width, cam->height, &err);
  if (!CHECK(RENDER_VOLUME(r, cam, &img, &err) == 0)) memset(img.rgba, 0, 4 * sizeof(float) * cam->width * cam->height);
  memset(prof, 0, 3 * NBINS * sizeof(double));
  memset(counts, 0, NBINS * sizeof(int));
  double fwd[3], right[3], up[3];
  for (int a = 0; a < 3; ++a) fwd[a] = cam->target[a] - cam->position[a];
  double n = sqrt(fwd[0] * fwd[0] + fwd[1] * fwd[1] + fwd[2] * fwd[2]);
  for (int a = 0; a < 3; ++a) fwd[a] /= n;
  right[0] = fwd[1] * cam->up[2] - fwd[2] * cam->up[1];
  right[1] = fwd[2] * cam->up[0] - fwd[0] * cam->up[2];
  right[2] = fwd[0] * cam->up[1] - fwd[1] * cam->up[0];
  n = sqrt(right[0] * right[0] + right[1] * right[1] + right[2] * right[2]);
  for (int a = 0; a < 3; ++a) right[a] /= n;
  up[0] = right[1] * fwd[2] - right[2] * fwd[1];
  up[1] = right[2] * fwd[0] - right[0] * fwd[2];
  up[2] = right[0] * fwd[1] - right[1] * fwd[0];
  const double th = tan(0.5 * cam->fov_deg * M_PI / 180.0), aspect = (double)cam->width / cam->height;
  for (int py = 0; py < cam->height; ++py)
    for (int px = 0; px < cam->width; ++px) {
      const size_t q = (size_t)py * cam->width + px;
      const double cover = img.rgba[4 * q + 3];
      if (cover < 1e-3) continue;
      const double sx = (2.0 * (px + 0.5) / cam->width - 1.0) * th * aspect, sy = (1.0 - 2.0 * (py + 0.5) / cam->height) * th;
      double d[3];
      for (int a = 0; a < 3; ++a) d[a] = fwd[a] + sx * right[a] + sy * up[a];
      n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      double c = (d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2]) / n;
      c = c > 1 ? 1 : c < -1 ? -1 : c;
      const int bin = (int)(acos(c) * 180.0 / M_PI * 10.0);
      if (bin < 0 || bin >= NBINS) continue;
      for (int ch = 0; ch < 3; ++ch) prof[ch][bin] += img.rgba[4 * q + ch] / cover;
      counts[bin]++;
    }
  for (int b = 0; b < NBINS; ++b)
    for (int ch = 0; ch < 3; ++ch)
      if (counts[b]) prof[ch][b] /= counts[b];
  sl_image_free(&img);
  sl_renderer_destroy(r);
  free(v.eta[particle]);
  v.eta[particle] = NULL;
  sl_volume_free(&v);
}

/* Angle (degrees) of the largest profile value of channel ch in [a, b] degrees. */
static double peak(double prof[3][NBINS], const int counts[NBINS], int ch, double a, double b, double *value)
{
  double best = -1.0, at = NAN;
  for (int bin = (int)(a * 10); bin <= (int)(b * 10) && bin < NBINS; ++bin)
    if (counts[bin] > 0 && prof[ch][bin] > best) best = prof[ch][bin], at = (bin + 0.5) / 10.0;
  if (value) *value = best;
  return at;
}

static double mean(double prof[3][NBINS], const int counts[NBINS], int ch, double a, double b)
{
  double s = 0.0;
  int n = 0;
  for (int bin = (int)(a * 10); bin < (int)(b * 10); ++bin)
    if (counts[bin]) s += prof[ch][bin], n++;
  return n ? s / n : NAN;
}

int main(void)
{
  static double prof[3][NBINS];
  static int counts[NBINS];
  sl_optics_tables *opt = tables((1u << SL_RAIN) | (1u << SL_ICE) | (1u << SL_CLOUD));
  if (!CHECK(opt != NULL)) return sl_test_finish("test_phenomena");

  /* Rainbow: a sun 10 degrees up in the north behind the viewer; optically thin rain to the south. */
  {
    double sun[3] = {0.0, cos(10 * M_PI / 180), sin(10 * M_PI / 180)};
    const double anti[3] = {-sun[0], -sun[1], -sun[2]};
    const double lo[3] = {-40e3, -60e3, 0}, hi[3] = {40e3, 0, 6000};
    sl_camera cam = {.position = {0, -100, 300}, .target = {0, -1000, 300 + 1000 * tan(22 * M_PI / 180)},
                     .up = {0, 0, 1}, .fov_deg = 80, .width = 220, .height = 220};
    profile(SL_RAIN, opt, lo, hi, 2e-5, sun, &cam, anti, prof, counts);
    double vr, vb;
    const double red1 = peak(prof, counts, 0, 36, 46, &vr), blue1 = peak(prof, counts, 2, 36, 46, &vb);
    const double red2 = peak(prof, counts, 0, 48, 56, NULL), blue2 = peak(prof, counts, 2, 48, 56, NULL);
    const double band = mean(prof, counts, 1, 44.5, 48.5), inside = mean(prof, counts, 1, 30, 38);
    printf("rainbow: primary red %.1f blue %.1f; secondary red %.1f blue %.1f; green between bows %.3g, inside %.3g\n",
           red1, blue1, red2, blue2, band, inside);
    CHECK_MSG(red1 >= 40 && red1 <= 43, "primary red maximum 40-43 degrees from the antisolar point");
    CHECK_MSG(blue1 >= 40 && blue1 <= 43, "primary blue maximum 40-43 degrees");
    CHECK_MSG(red1 > blue1, "red outside blue in the primary");
    CHECK_MSG(red2 >= 50 && red2 <= 54 && blue2 >= 50 && blue2 <= 54, "secondary maxima 50-54 degrees");
    CHECK_MSG(red2 < blue2, "order reversed in the secondary");
    CHECK_MSG(band < inside, "Alexander's dark band is darker than inside the primary");
  }
  /* Halo: thin cirrus ice overhead, looking 22 degrees beside a sun 30 degrees up. */
  {
    double sun[3] = {0.0, cos(30 * M_PI / 180), sin(30 * M_PI / 180)};
    const double lo[3] = {-40e3, -40e3, 8000}, hi[3] = {40e3, 60e3, 9000};
    sl_camera cam = {.position = {0, 0, 100}, .target = {0, 1000, 100 + 1000 * tan(30 * M_PI / 180)},
                     .up = {0, 0, 1}, .fov_deg = 70, .width = 200, .height = 200};
    profile(SL_ICE, opt, lo, hi, 2e-4, sun, &cam, sun, prof, counts);
    const double red = peak(prof, counts, 0, 19, 25, NULL), blue = peak(prof, counts, 2, 19, 25, NULL);
    /* The inner edge: where each colour first reaches half its rise from 18 degrees to its peak. */
    double edge[3];
    for (int ch = 0; ch < 3; ch += 2) {
      double top;
      peak(prof, counts, ch, 19, 25, &top);
      const double base = mean(prof, counts, ch, 17, 18.5);
      edge[ch] = NAN;
      for (int bin = 185; bin < 250; ++bin)
        if (counts[bin] && prof[ch][bin] >= 0.5 * (base + top)) {
          edge[ch] = bin / 10.0;
          break;
        }
    }
    printf("halo: red maximum %.1f, blue maximum %.1f; half-rise red %.1f, blue %.1f\n", red, blue, edge[0], edge[2]);
    CHECK_MSG(red >= 21 && red <= 23, "22 degree halo between 21 and 23 degrees");
    CHECK_MSG(edge[0] < edge[2], "red on the halo's inner edge");
  }
  /* Glory: looking down on a thin cloud deck at the antisolar point, sun behind the camera. */
  {
    double sun[3] = {0.0, -sin(20 * M_PI / 180), cos(20 * M_PI / 180)};
    const double anti[3] = {-sun[0], -sun[1], -sun[2]};
    const double lo[3] = {-20e3, -20e3, 1000}, hi[3] = {20e3, 20e3, 1100};
    const double pos[3] = {0, 3000 * sin(20 * M_PI / 180), 1100 + 3000 * cos(20 * M_PI / 180)};
    sl_camera cam = {.position = {pos[0], pos[1], pos[2]}, .target = {pos[0] + anti[0], pos[1] + anti[1], pos[2] + anti[2]},
                     .up = {0, 1, 0}, .fov_deg = 14, .width = 200, .height = 200};
    profile(SL_CLOUD, opt, lo, hi, 2e-4, sun, &cam, anti, prof, counts);
    double centre = mean(prof, counts, 1, 0, 0.4), ring_gap = mean(prof, counts, 1, 1.5, 2.5);
    int extrema = 0;
    for (int ch = 0; ch < 3; ++ch)
      for (int b = 6; b < 50; ++b)
        if (counts[b - 1] && counts[b] && counts[b + 1] && prof[ch][b] > prof[ch][b - 1] && prof[ch][b] > prof[ch][b + 1])
          extrema++;
    printf("glory: centre %.4g, at 1.5-2.5 degrees %.4g, local maxima within 5 degrees (3 colours) %d\n", centre,
           ring_gap, extrema);
    CHECK_MSG(centre > 1.2 * ring_gap, "the glory's bright centre at the antisolar point");
    CHECK_MSG(extrema >= 2, "coloured rings within 5 degrees of the antisolar point");
  }
  /* Thin limits: a homogeneous thin cloud box matches single scattering with the tabulated phase
   * function, and eq. 24 and eq. 25 agree. */
  {
    const double lo[3] = {-1000, -1000, 1000}, hi[3] = {1000, 1000, 3000};
    /* tau 1e-4 across: the light reaching the box has scattered n ~ 1e-4 times, so Ams_{n+1} is
     * P to within n (Ams_2 - P) / P, below 1e-3 here. */
    const double beta = 5e-8;
    sl_volume v;
    make_box_volume(&v, 4, 4, 4, lo, hi, beta);
    /* The renderer treats hydrometeor extinction as grey: the mean cross-section over the
     * wavelengths (DESIGN.md). */
    double sigma = 0.0;
    for (int c = 0; c < 3; ++c) sigma += sl_optics_table(opt, SL_CLOUD, c)->sigma_ext / 3.0;
    for (size_t i = 0; i < sl_volume_count(&v); ++i) v.eta[SL_CLOUD][i] = (float)(beta / sigma);
    double sun[3] = {0.5, 0.3, 0.6};
    const double sn = sqrt(0.7);
    for (int a = 0; a < 3; ++a) sun[a] /= sn;
    sl_camera cam = {.position = {0, -6000, 2000}, .target = {0, 0, 2000}, .up = {0, 0, 1}, .fov_deg = 20,
                     .width = 9, .height = 9};
    double got[2];
    for (int mode = 0; mode < 2; ++mode) {
      sl_scene sc = {.volume = &v, .optics = opt, .slices = 256, .lighting = mode ? SL_LIGHTING_MULTIPLE_EQ25 : SL_LIGHTING_MULTIPLE};
      memcpy(sc.sun_direction, sun, sizeof sun);
      for (int c = 0; c < 3; ++c) sc.sun_irradiance[c] = 1.0;
      sl_image img;
      render_frame(&sc, &cam, &img);
      got[mode] = img.rgba[4 * (4 * 9 + 4) + 1];
      sl_image_free(&img);
    }
    const sl_phase_table *t = sl_optics_table(opt, SL_CLOUD, 1);
    const double cos_scatter = sun[1]; /* view direction (0,1,0) */
    box_medium m = {.beta = beta, .phase = sl_phase_table_ams(t, 1, cos_scatter), .albedo = t->albedo};
    memcpy(m.lo, lo, sizeof lo);
    memcpy(m.hi, hi, sizeof hi);
    const double d[3] = {0, 1, 0};
    const double want = reference_radiance(&m, cam.position, d, sun, 0.0, 4000);
    printf("thin cloud: eq. 24 %.6g, eq. 25 %.6g, single scattering %.6g\n", got[0], got[1], want);
    CHECK_CLOSE(got[0], want, 0.01, 0.0);
    CHECK_CLOSE(got[1], got[0], 0.01, 0.0);
    sl_volume_free(&v);
  }
  sl_optics_free(opt);
  return sl_test_finish("test_phenomena");
}
