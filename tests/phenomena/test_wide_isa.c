/* The slicer's passes and the light-volume march exist twice, compiled for baseline x86-64 and for
 * AVX-512 (renderer_internal.h), and must be one renderer: the wide copy vectorises the light
 * steps across a tile's samples and the march's table reads across a ray's steps (gathers,
 * scatters, libmvec's eight-wide exp) where the baseline runs two at a time, and neither fuses
 * multiplies with adds. Every lighting model, three and sixteen wavelengths, one and two fields
 * (a mixed sample takes the fields' shares), sun in front and behind, slicer and light volume:
 * the two images must agree to libmvec's last bits (relative RMSE below 1e-6; measured 0). On a
 * CPU without AVX-512 both renders take the baseline and the test says so. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sl_renderer.h"
#include "sl_testing.h"

enum { NX = 40, NY = 36, NZ = 24 };

/* Seeded blobs of cloud and ice (ice only with two fields), some touching, in a 6 x 5 x 3 km box. */
static void fill(sl_volume *v, int two_fields)
{
  unsigned s = 2024u;
  for (int b = 0; b < 14; ++b) {
    s = s * 1664525u + 1013904223u;
    const int ci = 4 + (int)(s % (NX - 8)), cj = 4 + (int)((s >> 8) % (NY - 8)), ck = 3 + (int)((s >> 16) % (NZ - 6));
    const double radius = 2.0 + (s >> 24) % 4;
    float *eta = v->eta[two_fields && b % 2 ? SL_ICE : SL_CLOUD];
    const float peak = two_fields && b % 2 ? 3e4f : 8e7f; /* ice: optical depth ~1 across a blob */
    for (int k = 0; k < NZ; ++k)
      for (int j = 0; j < NY; ++j)
        for (int i = 0; i < NX; ++i) {
          const double r2 = ((i - ci) * (i - ci) + (j - cj) * (j - cj) + (k - ck) * (k - ck)) / (radius * radius);
          if (r2 < 1.0) eta[sl_volume_index(v, i, j, k)] += (float)(peak * (1.0 - r2));
        }
  }
}

int main(void)
{
  sl_error err = {0};
  int wide_seen = -1; /* whether the renders without baseline_isa took the AVX-512 copy */
  sl_atmosphere atm3, atm16;
  double spectral[SL_SKY_SPECTRAL_COUNT];
  sl_sky_spectral_wavelengths(spectral);
  sl_atmosphere_init(&atm3, sl_sky_rgb_wavelengths_nm, 3, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, &err);
  sl_atmosphere_init(&atm16, spectral, SL_SKY_SPECTRAL_COUNT, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, &err);
  sl_optics_tables *opt[2] = {NULL, NULL};
  for (int s = 0; s < 2; ++s) {
    sl_optics_request req;
    sl_optics_request_defaults(&req);
    req.particles = (1u << SL_CLOUD) | (1u << SL_ICE);
    sl_optics_request_wavelengths(&req, s ? "spectral16" : "rgb", &err);
    opt[s] = sl_optics_build(&req, &err);
    if (!CHECK(opt[s] != NULL)) return sl_test_finish("test_wide_isa");
  }
  const double spacing[3] = {150.0, 140.0, 125.0};
  const double origin[3] = {-0.5 * (NX - 1) * spacing[0], -0.5 * (NY - 1) * spacing[1], 500.0};
  sl_camera cam = {.position = {-2000, -11000, 2500}, .target = {0, 0, 2000}, .up = {0, 0, 1}, .fov_deg = 45,
                   .width = 64, .height = 48};
  const sl_lighting models[] = {SL_LIGHTING_MULTIPLE, SL_LIGHTING_MULTIPLE_EQ25, SL_LIGHTING_LOW_ALBEDO};
  const char *model_names[] = {"multiple", "eq25", "low-albedo"};
  const double suns[][2] = {{200.0, 30.0}, {20.0, 10.0}}; /* behind the camera; ahead of it, low */
  for (int fields = 1; fields <= 2; ++fields) {
    sl_volume v;
    if (!CHECK(sl_volume_init(&v, NX, NY, NZ, origin, spacing, &err) == SL_OK)) return sl_test_finish("test_wide_isa");
    CHECK(sl_volume_add_field(&v, SL_CLOUD, &err) == SL_OK);
    if (fields == 2) CHECK(sl_volume_add_field(&v, SL_ICE, &err) == SL_OK);
    fill(&v, fields == 2);
    for (size_t mi = 0; mi < sizeof models / sizeof models[0]; ++mi)
      for (int spec = 0; spec < 2; ++spec)
        for (int si = 0; si < 2; ++si)
        for (int lv = 0; lv < 2; ++lv) {
          if (spec && models[mi] != SL_LIGHTING_MULTIPLE) continue;
          sl_image img[2];
          int ok = 1;
          for (int base = 0; base < 2; ++base) {
            sl_scene sc = {.volume = &v, .optics = opt[spec], .atmosphere = spec ? &atm16 : &atm3,
                           .lighting = models[mi], .xi = 0.05, .baseline_isa = base, .light_volume = lv};
            sl_sun_direction(suns[si][1], suns[si][0], sc.sun_direction);
            /* The volume's layer alone (no sky behind it), so the comparison weighs only the volume. */
            sl_renderer *r = sl_renderer_create(&sc, &err);
            sl_render_stats st = {0};
            ok &= r && sl_image_alloc(&img[base], cam.width, cam.height, &err) == SL_OK &&
                  sl_renderer_render(r, &cam, &img[base], &st, &err) == SL_OK;
            if (base) CHECK_MSG(st.wide_isa == 0, "baseline_isa runs the baseline");
            else if (wide_seen < 0) {
              wide_seen = st.wide_isa;
              printf("%s\n", wide_seen ? "the CPU has AVX-512: baseline against the wide copy"
                                        : "no AVX-512 here: both renders take the baseline");
            }
            sl_renderer_destroy(r);
          }
          char name[96];
          snprintf(name, sizeof name, "%s, %d field(s), %s, %s, sun %g/%g", lv ? "light volume" : "slicer", fields,
                   model_names[mi], spec ? "16 wl" : "3 wl", suns[si][0], suns[si][1]);
          if (!CHECK_MSG(ok, name)) continue;
          double num = 0.0, den = 0.0, peak = 0.0, coverage = 0.0;
          int finite = 1;
          for (size_t i = 0; i < (size_t)cam.width * cam.height; ++i) coverage = fmax(coverage, 1.0 - img[1].transparency[i]);
          const size_t n = (size_t)cam.width * cam.height;
          for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
              const double a = img[0].rgba[4 * i + c], b = img[1].rgba[4 * i + c];
              finite &= isfinite(a) && isfinite(b);
              num += (a - b) * (a - b), den += b * b, peak = fmax(peak, b);
            }
          const double rel = den > 0.0 ? sqrt(num / den) : INFINITY;
          printf("%-62s relative RMSE %.3g (peak %.3g)\n", name, rel, peak);
          CHECK_MSG(finite && peak > 0.0 && coverage > 0.9, name); /* the blobs are in view and opaque somewhere */
          CHECK_MSG(rel <= 1e-6, name);
          sl_image_free(&img[0]), sl_image_free(&img[1]);
        }
    sl_volume_free(&v);
  }
  sl_optics_free(opt[0]), sl_optics_free(opt[1]);
  return sl_test_finish("test_wide_isa");
}
