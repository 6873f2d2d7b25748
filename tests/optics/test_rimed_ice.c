/* Graupel and hail optics against outside values: Bruggeman's index against a bisection of the
 * equation it solves (and its two pure limits), the extinction efficiency of large spheres against
 * 2, the tables' extinction per unit mass against the exponential distribution's closed form
 * Q lambda / (2 rho), the normalisation of every Ams_n, Dirac included, and the smoothness in angle
 * and in colour that averaging over a broad distribution of sizes gives. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "optics_test_util.h"
#include "sl_mie.h"
#include "sl_refractive.h"
#include "sl_testing.h"

/* Bruggeman's condition for real permittivities, f (e1 - e) / (e1 + 2 e) + (1 - f)(e2 - e) / (e2 + 2 e). */
static double bruggeman_residual(double f, double e1, double e2, double e)
{
  return f * (e1 - e) / (e1 + 2.0 * e) + (1.0 - f) * (e2 - e) / (e2 + 2.0 * e);
}

static double bruggeman_bisection(double f, double e1, double e2)
{
  double lo = fmin(e1, e2), hi = fmax(e1, e2); /* the residual is decreasing in e between them */
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (bruggeman_residual(f, e1, e2, mid) > 0.0) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

static int compare_doubles(const void *a, const void *b)
{
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The median over grid points in [lo, hi] degrees of |second difference| of ln P (tables a and b
 * NULL) or of ln P_a - ln P_b (two wavelengths' P: the colour of the scattered light). */
static double median_log_curvature(const sl_phase_table *a, const sl_phase_table *b, double lo, double hi)
{
  const double step = a->step_rad * 180.0 / SL_PI;
  double d[4096];
  int n = 0;
  for (int j = (int)ceil(lo / step); j * step <= hi && j + 1 < a->n_angles && n < 4096; ++j) {
    double v[3];
    for (int k = 0; k < 3; ++k) {
      v[k] = log(a->ams[a->n_angles + j - 1 + k]);
      if (b) v[k] -= log(b->ams[b->n_angles + j - 1 + k]);
    }
    d[n++] = fabs(v[0] - 2.0 * v[1] + v[2]);
  }
  qsort(d, (size_t)n, sizeof *d, compare_doubles);
  return n ? d[n / 2] : NAN;
}

int main(void)
{
  /* Bruggeman: real indices, against bisection; the index of ice at f = 1 and of air at f = 0. */
  const double fractions[] = {0.0, 0.1, 400.0 / 917.0, 0.5, 900.0 / 917.0, 1.0};
  for (size_t i = 0; i < sizeof fractions / sizeof fractions[0]; ++i) {
    const double f = fractions[i], n_ice = 1.3117;
    double re, im;
    sl_bruggeman_index(f, n_ice, 0.0, 1.0, 0.0, &re, &im);
    const double want = sqrt(bruggeman_bisection(f, n_ice * n_ice, 1.0));
    CHECK_CLOSE(re, want, 1e-12, 0.0);
    CHECK_CLOSE(im, 0.0, 0.0, 1e-15);
  }
  {
    double ice_re, ice_im, re, im;
    sl_ice_index(550.0, &ice_re, &ice_im);
    sl_rimed_ice_index(550.0, 917.0, &re, &im);
    CHECK_CLOSE(re, ice_re, 1e-12, 0.0);
    CHECK_CLOSE(im, ice_im, 1e-6, 0.0);
    sl_rimed_ice_index(550.0, 400.0, &re, &im);
    printf("graupel (400 kg/m3) at 550 nm: m = %.5f + %.3gi (ice %.5f + %.3gi)\n", re, im, ice_re, ice_im);
    /* Air pores dilute the absorption: the mixture's imaginary part lies between air's and ice's. */
    CHECK(re > 1.0 && re < ice_re && im > 0.0 && im < ice_im);
  }

  /* Large spheres: Q_ext -> 2 within 1 % (the extinction paradox), at the largest Mie size used. */
  {
    double re, im;
    sl_rimed_ice_index(440.0, 400.0, &re, &im);
    sl_mie_efficiencies e;
    sl_error err = {0};
    CHECK(sl_mie(2.0e4, re, im, NULL, 0, &e, NULL, NULL, NULL, &err) == SL_OK);
    printf("graupel sphere x = 2e4: Qext %.5f\n", e.qext);
    CHECK_CLOSE(e.qext, 2.0, 0.01, 0.0);
  }

  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.use_cache = 0;
  req.particles = (1u << SL_GRAUPEL) | (1u << SL_HAIL);
  req.angle_step_deg = 0.5;
  req.radius_samples = 256;
  sl_error err = {0};
  sl_optics_tables *T = sl_optics_build(&req, &err);
  CHECK_MSG(T != NULL, err.message);
  if (!T) return sl_test_finish("test_rimed_ice");
  /* Exponential n(D) ~ exp(-lambda D): mean area (pi/4) 2 / lambda^2, mean mass rho pi / lambda^3, so
   * the extinction per unit mass is Q lambda / (2 rho). The distributions are the species' own:
   * graupel lambda 1500/m at 400 kg/m3, hail 580/m at 900 kg/m3 (render/optics/rimed_ice.c). */
  const struct {
    sl_particle p;
    double lambda, rho;
  } cases[] = {{SL_GRAUPEL, 1500.0, 400.0}, {SL_HAIL, 580.0, 900.0}};
  for (int c = 0; c < 2; ++c)
    for (int w = 0; w < 3; ++w) {
      const sl_phase_table *t = sl_optics_table(T, cases[c].p, w);
      CHECK(t != NULL);
      if (!t) continue;
      const double q = t->sigma_ext / sl_particle_mass(cases[c].p) * 2.0 * cases[c].rho / cases[c].lambda;
      printf("%s %g nm: Q_ext %.5f, albedo %.6f, g %.4f, forward Dirac %.4f, N %d\n",
             sl_particle_name(cases[c].p), t->wavelength_nm, q, t->albedo, t->asymmetry, t->truncated_fraction,
             t->max_order);
      CHECK_CLOSE(q, 2.0, 0.01, 0.0);
      /* Visible ice absorbs little: below 2e-3 of the extinction even across centimetres. */
      CHECK(t->albedo > 0.998 && t->albedo <= 1.0);
      /* Large spheres scatter forward: half the extinction is diffraction inside a fraction of a
       * degree, so g is near (1 + g_geometric) / 2 and well above snow's 0.75. */
      CHECK(t->asymmetry > 0.8 && t->asymmetry < 1.0);
      double worst = 0.0;
      for (int n = 0; n <= t->max_order; ++n) worst = fmax(worst, fabs(sphere_integral(t, n) - 1.0));
      CHECK_MSG(worst < 1e-4, "every Ams_n of graupel and hail integrates to 1 within 1e-4");
      /* Over a broad distribution of large spheres each size's interference ripple, a hundredth
       * of a degree apart and shifting with size, averages out: what is left is the geometric
       * envelope and the diffraction tail, curving over degrees. Where one sphere stands for the
       * sizes beyond Mie's reach, the grid samples its ripple as noise, and in colour too (the
       * ripple moves with wavelength): stripes around a sun behind hail. On this grid that gave
       * hail a median |second difference| of ln P of 0.37-0.50 and of the colour 0.49-0.61,
       * graupel's colour 0.14-0.16. Outside the truncation cone, 2 degrees to the backward. */
      const double curve = median_log_curvature(t, NULL, 2.0, 178.0);
      const double colour = median_log_curvature(t, sl_optics_table(T, cases[c].p, (w + 1) % 3), 2.0, 178.0);
      printf("  median |second difference| of ln P %.4f, of ln P / P(next wavelength) %.4f\n", curve, colour);
      CHECK_MSG(curve < 0.05 && colour < 0.1, "graupel and hail smooth in angle and colour");
    }
  /* Per representative particle the tables must carry the cross-section that, times the number
   * eta = rho q / m, gives that extinction per unit mass: graupel's is larger than hail's by
   * (1500 / 400) / (580 / 900) = 5.82 (more, smaller, lighter particles per kilogram). */
  const double kg = sl_optics_table(T, SL_GRAUPEL, 1)->sigma_ext / sl_particle_mass(SL_GRAUPEL);
  const double kh = sl_optics_table(T, SL_HAIL, 1)->sigma_ext / sl_particle_mass(SL_HAIL);
  CHECK_CLOSE(kg / kh, (1500.0 / 400.0) / (580.0 / 900.0), 0.01, 0.0);
  sl_optics_free(T);
  return sl_test_finish("test_rimed_ice");
}
