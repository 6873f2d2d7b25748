/* The series with the particle tables of render/optics (cloud droplets and raindrops at 650,
 * 515 and 440 nm): W_k = W0 (2k+1) chi_k from the tables' moments. Checked against identities
 * and a brute-force sum that uses the moments directly, and the per-channel glow against three
 * single-medium glows. Prints how far the table's PSF is from HG with q = g. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "apsf_reference.h"
#include "sl_glow.h"
#include "sl_optics.h"
#include "sl_testing.h"

/* Eq. 27 with g_m from eq. 25 and the table's moments, summed directly in long double. */
static double brute(const sl_phase_table *t, double T, double mu, int terms)
{
  long double sum = 0.0L, p0 = 1.0L, p1 = mu, g_prev = 0.0L;
  for (int l = 0; l < terms; ++l) {
    long double pl = l == 0 ? 1.0L : (l == 1 ? (long double)mu : 0.0L);
    if (l >= 2) {
      pl = ((2.0L * l - 1.0L) * mu * p1 - (l - 1.0L) * p0) / l;
      p0 = p1;
      p1 = pl;
    }
    const int m = l + 1;
    const long double W = (long double)t->albedo * (2.0L * (m - 1) + 1.0L) * (m - 1 < t->n_moments ? t->moments[m - 1] : 0.0);
    const long double beta = (2.0L * m + 1.0L) / m * (1.0L - W / (2.0L * m - 1.0L));
    const long double g_next = expl(-beta * T - (m + 1.0L) * logl(T));
    sum += (g_prev + g_next) * pl;
    g_prev = g_next;
  }
  return (double)sum;
}

int main(void)
{
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.particles = (1u << SL_CLOUD) | (1u << SL_RAIN);
  req.angle_step_deg = 0.5;
  req.radius_samples = 8;
  req.use_cache = 0;
  sl_error err = {0};
  sl_optics_tables *tables = sl_optics_build(&req, &err);
  CHECK_MSG(tables != NULL, err.message);
  if (!tables) return sl_test_finish("test_apsf_optics");
  static double x[400], w[400];
  ref_gauss(400, x, w);
  const sl_particle parts[2] = {SL_CLOUD, SL_RAIN};
  for (int ip = 0; ip < 2; ++ip)
    for (int wl = 0; wl < 3; ++wl) {
      const sl_phase_table *t = sl_optics_table(tables, parts[ip], wl);
      const sl_apsf_medium m = {t->albedo, 0.0, t->moments, t->n_moments};
      for (double T = 1.2; T < 12; T *= 2.2) {
        sl_apsf_series s;
        if (sl_apsf_series_init(&s, &m, T, 1e-6, 0, &err)) {
          CHECK_MSG(0, err.message);
          continue;
        }
        const double peak = sl_apsf_series_eval(&s, 1.0);
        /* Boundary property, fluence identity, and the brute-force sum. */
        CHECK(fabs(sl_apsf_series_eval(&s, -1.0)) <= 1e-6 * peak);
        double sum = 0.0;
        for (int n = 0; n < 400; ++n) sum += w[n] * sl_apsf_series_eval(&s, x[n]);
        CHECK_CLOSE(T * T * 2.0 * REF_PI * sum, 4.0 * REF_PI * exp(-3.0 * (1.0 - t->albedo) * T), 1e-6, 0);
        const int many = s.terms + (int)(30.0 / log(T));
        double worst = 0.0;
        for (int a = 0; a <= 60; ++a) {
          const double mu = cos(REF_PI * a / 60.0);
          worst = fmax(worst, fabs(sl_apsf_series_eval(&s, mu) - brute(t, T, mu, many)));
        }
        char what[128];
        snprintf(what, sizeof what, "%s %.0f nm T %.3g: %d terms, error %.3g of the peak",
                 sl_particle_name(parts[ip]), t->wavelength_nm, T, s.terms, worst / peak);
        CHECK_MSG(worst <= 1e-6 * peak, what);
        /* How far Henyey-Greenstein with the same g is (for docs/APSF.md). */
        if (wl == 1 && (T > 2.5 && T < 6)) {
          const sl_apsf_medium hg = {t->albedo, t->moments[1], NULL, 0};
          sl_apsf_series h;
          sl_apsf_series_init(&h, &hg, T, 1e-6, 0, &err);
          double d = 0.0;
          for (int a = 0; a <= 90; ++a) {
            const double mu = cos(REF_PI * a / 90.0);
            d = fmax(d, fabs(sl_apsf_series_eval(&s, mu) - sl_apsf_series_eval(&h, mu)));
          }
          printf("%s 515 nm, T %.3g: table (g %.4f, albedo %.6f, %d moments) vs HG q = g: largest difference %.3g of "
                 "the peak\n",
                 sl_particle_name(parts[ip]), T, t->moments[1], t->albedo, t->n_moments, d / peak);
          sl_apsf_series_free(&h);
        }
        sl_apsf_series_free(&s);
      }
    }

  /* Per-channel media: channel c of a glow with the three cloud tables equals channel c of a
   * glow with table c alone. */
  const int W = 40, H = 30;
  sl_image in = {0}, out = {0}, one = {0};
  sl_image_alloc(&in, W, H, &err);
  sl_image_alloc(&out, W, H, &err);
  sl_image_alloc(&one, W, H, &err);
  for (int i = 0; i < W * H * 4; ++i) in.rgba[i] = 0.0f;
  for (int c = 0; c < 3; ++c) in.rgba[4 * (12 * W + 17) + c] = 10.0f;
  sl_apsf_medium media[3];
  for (int c = 0; c < 3; ++c) {
    const sl_phase_table *t = sl_optics_table(tables, SL_CLOUD, c);
    media[c] = (sl_apsf_medium){t->albedo, 0.0, t->moments, t->n_moments};
  }
  sl_glow_params p;
  sl_glow_params_defaults(&p);
  p.fixed_T = 1.8;
  p.threshold = 1.0;
  for (int c = 0; c < 3; ++c) p.channel_medium[c] = &media[c];
  sl_glow_workspace *ws = sl_glow_workspace_create(W, H, 0, 0, &err);
  CHECK(sl_glow_apply(ws, &p, &in, &out, NULL, &err) == SL_OK);
  double spread = 0.0;
  for (int c = 0; c < 3; ++c) {
    sl_glow_params q = p;
    for (int k = 0; k < 3; ++k) q.channel_medium[k] = NULL;
    q.medium = media[c];
    CHECK(sl_glow_apply(ws, &q, &in, &one, NULL, &err) == SL_OK);
    double worst = 0.0, peak = 0.0;
    for (int i = 0; i < W * H; ++i) {
      worst = fmax(worst, fabs(out.rgba[4 * i + c] - one.rgba[4 * i + c]));
      peak = fmax(peak, one.rgba[4 * i + c]);
      spread = fmax(spread, fabs(out.rgba[4 * i + c] - out.rgba[4 * i + 1]));
    }
    CHECK(worst <= 1e-6 * peak);
  }
  CHECK(spread > 0.0); /* the three wavelengths do differ */
  sl_glow_workspace_free(ws);
  sl_image_free(&in);
  sl_image_free(&out);
  sl_image_free(&one);
  sl_optics_free(tables);
  return sl_test_finish("test_apsf_optics");
}
