/* Phase tables: normalisation of every Ams_n, agreement with closed forms, and the measured
 * phenomena of issue 4: rainbows and Alexander's band (rain), glory (cloud), halos (ice). */
#include <math.h>
#include <stdio.h>

#include "optics_test_util.h"
#include "sl_testing.h"

int main(void)
{
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.use_cache = 0;
  req.angle_step_deg = 0.25; /* coarse enough for CI under sanitizers, fine enough for the bows */
  req.radius_samples = 16;
  req.ice_rays = 150000;
  sl_error err = {0};
  sl_optics_tables *T = sl_optics_build(&req, &err);
  CHECK_MSG(T != NULL, err.message);
  if (!T) return sl_test_finish("test_phase_tables");

  /* Every Ams_n integrates to 1 over the sphere (Riley et al. 2004, eq. 17), Dirac included. */
  double worst = 0.0;
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
    for (int w = 0; w < 3; ++w) {
      const sl_phase_table *t = sl_optics_table(T, (sl_particle)p, w);
      CHECK(t != NULL);
      if (!t) continue;
      for (int n = 0; n <= t->max_order; ++n) worst = fmax(worst, fabs(sphere_integral(t, n) - 1.0));
      CHECK(t->forward[0] == 1.0);
      for (int n = 1; n <= t->max_order; ++n) CHECK(t->forward[n] <= t->forward[n - 1] + 1e-6);
      /* Auto order: isotropic within the tolerance at N. */
      CHECK(sl_phase_table_isotropic_order(t, 2e-4) >= 0);
      CHECK(t->albedo > 0.999 && t->albedo <= 1.0);
    }
  printf("worst |integral - 1| over all tables and orders: %.3g\n", worst);
  {
    const sl_phase_table *t = sl_optics_table(T, SL_RAIN, 0);
    for (double th = 0.0; th <= SL_PI; th += 0.0123)
      CHECK_CLOSE(sl_phase_table_ams_theta(t, 3, th), sl_phase_table_ams(t, 3, cos(th)), 1e-9, 1e-12);
  }
  CHECK_MSG(worst < 1e-6, "every Ams_n integrates to 1 within 1e-6");

  /* Snow is HG(0.75): Ams_n must be HG's moments to the n-th power, and F_1 its closed form. */
  {
    const sl_phase_table *t = sl_optics_table(T, SL_SNOW, 1);
    const double g = 0.75;
    double chi[400];
    for (int n = 1; n <= 4; ++n) {
      for (int l = 0; l < 400; ++l) chi[l] = pow(g, (double)l * n);
      double err_max = 0.0;
      for (int k = 0; k <= 180; k += 3) {
        const double mu = cos(k * SL_PI / 180.0), want = sl_legendre_series(chi, 400, mu);
        err_max = fmax(err_max, fabs(sl_phase_table_ams(t, n, mu) - want) / want);
      }
      printf("snow Ams_%d vs HG moments^n: max relative difference %.3g\n", n, err_max);
      CHECK_MSG(err_max < 2e-3, "snow Ams_n equals the HG series with moments g^(l n)");
    }
    const double F_hg = (1.0 + g) / (2.0 * g) * (1.0 - (1.0 - g) / sqrt(1.0 + g * g));
    CHECK_CLOSE(t->forward[1], F_hg, 1e-4, 0.0);
  }

  /* F_n from the table agrees with F_n from the Legendre moments (eq. 23 two ways). */
  /* The Dirac's moments are all f, whose series converges too slowly: it is added apart. */
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p) {
    const sl_phase_table *t = sl_optics_table(T, (sl_particle)p, 1);
    static double smooth[4000];
    const double f = t->truncated_fraction;
    for (int l = 0; l < t->n_moments && l < 4000; ++l) smooth[l] = t->moments[l] - f;
    const double F = f + sl_legendre_forward_fraction(smooth, t->n_moments < 4000 ? t->n_moments : 4000);
    CHECK_CLOSE(t->forward[1], F, 1e-4, 0.0);
  }

  /* Eq. 20 checked by direct quadrature, independently of the Legendre route: for rain (with
   * its forward Dirac f) Ams_2 = f^2 delta + 2 f Pt + Pt (*) Pt, where the spherical convolution
   * (Pt (*) Pt)(theta) = int Pt(theta') Pt(cos gamma) dOmega', cos gamma = cos theta cos theta' +
   * sin theta sin theta' cos phi, is summed with 3 Gauss points per grid cell in theta' and
   * 720 steps in phi. */
  {
    const sl_phase_table *t = sl_optics_table(T, SL_RAIN, 1);
    const double f = t->truncated_fraction;
    static const double gx[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
    static const double gw[3] = {0.5555555555555556, 0.8888888888888888, 0.5555555555555556};
    const double angles[4] = {20.0, 60.0, 100.0, 150.0};
    double worst = 0.0;
    for (int a = 0; a < 4; ++a) {
      const double th = angles[a] * SL_PI / 180.0, ct = cos(th), st = sin(th);
      double conv = 0.0;
      for (int j = 0; j + 1 < t->n_angles; ++j) {
        const double lo = j * t->step_rad, hi = (j + 1) * t->step_rad;
        for (int q = 0; q < 3; ++q) {
          const double tp = 0.5 * (lo + hi) + 0.5 * (hi - lo) * gx[q];
          const double w = 0.5 * (hi - lo) * gw[q] * sin(tp) * sl_phase_table_ams(t, 1, cos(tp));
          double inner = 0.0;
          for (int k = 0; k < 720; ++k) {
            const double phi = (k + 0.5) * 2.0 * SL_PI / 720.0;
            inner += sl_phase_table_ams(t, 1, ct * cos(tp) + st * sin(tp) * cos(phi));
          }
          conv += w * inner * 2.0 * SL_PI / 720.0;
        }
      }
      const double want = 2.0 * f * sl_phase_table_ams(t, 1, ct) + conv;
      const double got = sl_phase_table_ams(t, 2, ct);
      printf("rain Ams_2(%3.0f deg): Legendre %.6g, direct quadrature %.6g\n", angles[a], got, want);
      worst = fmax(worst, fabs(got - want) / want);
    }
    CHECK_MSG(worst < 1e-3, "Ams_2 equals P (*) P by direct quadrature within 1e-3");
  }

  /* Rain: primary bow maximum in 137..139.8 degrees, secondary in 126..130.5, Alexander's dark
   * band between them below both; red's primary at a smaller scattering angle than blue's and
   * the order reversed for the secondary. Wavelength 0 is red (650), 2 is blue (440). */
  double primary[3], secondary[3];
  for (int w = 0; w < 3; ++w) {
    const sl_phase_table *t = sl_optics_table(T, SL_RAIN, w);
    primary[w] = argmax_deg(t, 1, 135.0, 145.0);
    secondary[w] = argmax_deg(t, 1, 122.0, 133.0);
    const double band = min_deg_value(t, 1, secondary[w] + 0.5, primary[w] - 0.5);
    printf("rain %3.0f nm: primary %.2f, secondary %.2f degrees\n", t->wavelength_nm, primary[w], secondary[w]);
    CHECK(primary[w] >= 137.0 && primary[w] <= 139.8);
    CHECK(secondary[w] >= 126.0 && secondary[w] <= 130.5);
    CHECK(band < 0.5 * table_value_deg(t, 1, primary[w]) && band < 0.5 * table_value_deg(t, 1, secondary[w]));
  }
  CHECK(primary[0] < primary[2]);
  CHECK(secondary[0] > secondary[2]);

  /* Cloud: the glory, a maximum at 180 degrees, with rings whose radius grows with wavelength:
   * the first minimum away from 180 lies further out in red than in blue. A finer grid for
   * cloud alone (cheap: x ~ 100) resolves the ring radii (about 0.5 to 1 degree). */
  sl_optics_request fine = req;
  fine.particles = 1u << SL_CLOUD;
  fine.angle_step_deg = 0.05;
  fine.max_order = 2;
  fine.n_moments = 400; /* only P itself is examined */
  sl_optics_tables *C = sl_optics_build(&fine, &err);
  CHECK_MSG(C != NULL, err.message);
  double first_min[3] = {0, 0, 0};
  for (int w = 0; w < 3 && C; ++w) {
    const sl_phase_table *t = sl_optics_table(C, SL_CLOUD, w);
    const int J = t->n_angles;
    const float *P = t->ams + J;
    CHECK(P[J - 1] > P[J - 2] && P[J - 1] > P[J - 3]);
    int j = J - 2;
    while (j > J / 2 && !(P[j] < P[j - 1] && P[j] <= P[j + 1])) --j;
    first_min[w] = 180.0 - j * t->step_rad * 180.0 / SL_PI;
    printf("cloud %3.0f nm: glory P(180) = %.3g, first ring minimum %.2f degrees from 180\n", t->wavelength_nm,
           P[J - 1], first_min[w]);
  }
  CHECK(first_min[0] > first_min[1] && first_min[1] > first_min[2]);
  sl_optics_free(C);

  /* Ice: halo maxima near 22 and 46 degrees; red on the inside: the angle where P first rises
   * half-way from the minimum inside the halo to its peak is smaller for red than for blue. */
  double edge22[3];
  for (int w = 0; w < 3; ++w) {
    const sl_phase_table *t = sl_optics_table(T, SL_ICE, w);
    const double h22 = argmax_deg(t, 1, 19.0, 26.0), h46 = argmax_deg(t, 1, 42.0, 50.0);
    const double base = min_deg_value(t, 1, 15.0, 21.0), peak = table_value_deg(t, 1, h22);
    double e = 15.0;
    while (e < h22 && table_value_deg(t, 1, e) < 0.5 * (base + peak)) e += 0.01;
    edge22[w] = e;
    printf("ice %3.0f nm: maxima %.2f and %.2f degrees, inner edge of 22-degree halo %.2f\n", t->wavelength_nm, h22,
           h46, e);
    CHECK(h22 >= 21.0 && h22 <= 23.5);
    CHECK(h46 >= 44.5 && h46 <= 48.5); /* minimum deviation 45.5 (red) .. 47.2 (blue) */
    CHECK(table_value_deg(t, 1, h46) > 1.2 * min_deg_value(t, 1, 36.0, 42.0));
  }
  CHECK(edge22[0] < edge22[2]);

  sl_optics_free(T);
  return sl_test_finish("test_phase_tables");
}
