/* Sizes between tables (io/size_bins.c, docs/OPTICS.md): a cell whose effective radius r lies between
 * two tables R1 < r < R2 is drawn as the extinction-weighted mixture of their phase functions,
 * weights linear in ln r. Against the table computed at r itself (the geometric midpoint, the worst
 * place), for neighbour ratios R2 / R1 of 1.25 to 3 across cloud droplets and drizzle:
 *   - the mixture is a phase function (normalised, as a mixture of normalised ones must be);
 *   - the light sent the wrong way, half the L1 distance of the two phase functions over the sphere
 *     (Dirac included), grows with the ratio and stays under 2.5 % at the ratios the loader uses (1.5
 *     for cloud, 3 for drizzle and rain, whose phase functions change slowly with size);
 *   - the outside law the tables must follow: moving a distribution to another effective radius moves
 *     its diffraction lobe as 1 / r (Fraunhofer: every angle of the lobe scales with lambda / r), seen
 *     in the angle where the smooth part of P falls to a tenth of its value at 1 degree. */
#include <math.h>
#include <stdio.h>

#include "sl_optics.h"
#include "sl_testing.h"

#define STEP_DEG 0.25

static sl_optics_tables *build(sl_particle p, const double *radii, int n)
{
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.use_cache = 0;
  req.particles = 0;
  req.n_wavelengths = 1;
  req.wavelengths_nm[0] = 550.0;
  req.angle_step_deg = STEP_DEG;
  req.radius_samples = 128;
  req.max_order = 2;
  req.n_sizes = n;
  for (int i = 0; i < n; ++i) req.sizes[i] = (sl_optics_size){p, radii[i]};
  sl_error err = {0};
  sl_optics_tables *T = sl_optics_build(&req, &err);
  CHECK_MSG(T != NULL, err.message);
  return T;
}

/* The integral over the sphere of a function linear in theta between grid points, given at them:
 * exact for ams's representation (sl_optics.h). */
static double sphere_integral(const sl_phase_table *t, const double *f)
{
  const double h = t->step_rad;
  double sum = 0.0;
  for (int j = 0; j + 1 < t->n_angles; ++j) {
    const double t0 = j * h, t1 = j + 2 == t->n_angles ? M_PI : t0 + h;
    const double c0 = cos(t0), c1 = cos(t1), s0 = sin(t0), s1 = sin(t1);
    sum += f[j] * (c0 - c1) + (f[j + 1] - f[j]) / (t1 - t0) * (-(t1 - t0) * c1 + s1 - s0);
  }
  return 2.0 * M_PI * sum;
}

/* Half the L1 distance between the mixture of a and b (scattering weights wa, wb) and c. */
static double wrong_way(const sl_phase_table *a, const sl_phase_table *b, double wa, double wb, const sl_phase_table *c,
                        double *mixture_norm)
{
  const double fa = wa / (wa + wb), fb = wb / (wa + wb);
  double mix[4000], diff[4000];
  for (int j = 0; j < c->n_angles; ++j) {
    mix[j] = fa * a->ams[a->n_angles + j] + fb * b->ams[b->n_angles + j];
    diff[j] = fabs(mix[j] - c->ams[c->n_angles + j]);
  }
  const double dirac = fa * a->delta[1] + fb * b->delta[1];
  *mixture_norm = dirac + sphere_integral(c, mix);
  return 0.5 * (fabs(dirac - c->delta[1]) + sphere_integral(c, diff));
}

/* Scattering per unit mass of a table at effective radius R: sigma_ext albedo / R up to a constant
 * (sigma_ext = 3 Q m / (4 rho R) per representative particle). */
static double scattering_per_mass(const sl_phase_table *t, double R) { return t->sigma_ext * t->albedo * R; }

/* Fraunhofer diffraction makes the forward lobe a function of x theta alone, P = x^2 F(x theta), so
 * any feature of its shape sits at an angle proportional to 1 / r: here the first angle past the
 * truncation cone where the smooth part of P falls as steeply as theta^-2 (its log-slope -2). */
static double lobe_angle(const sl_phase_table *t)
{
  const float *p = t->ams + t->n_angles;
  double previous = 0.0;
  for (int j = (int)lround(0.75 / STEP_DEG); j + 2 < t->n_angles; ++j) {
    const double slope = log(p[j + 1] / p[j - 1]) / log((j + 1.0) / (j - 1.0));
    if (slope <= -2.0 && j > 0) return (j - 1 + (previous + 2.0) / (previous - slope)) * STEP_DEG;
    previous = slope;
  }
  return NAN;
}

int main(void)
{
  const double ratios[] = {1.25, 1.5, 2.0, 3.0};
  const struct {
    sl_particle p;
    double r0;
    const char *label;
  } cases[] = {{SL_CLOUD, 4e-6, "cloud 4 um"}, {SL_CLOUD, 10e-6, "cloud 10 um"}, {SL_CLOUD, 20e-6, "cloud 20 um"},
               {SL_RAIN, 60e-6, "drizzle 60 um"}};
  double at_loader_ratio = 0.0;
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    double previous = 0.0;
    for (size_t k = 0; k < sizeof ratios / sizeof ratios[0]; ++k) {
      const double R1 = cases[c].r0, R2 = R1 * ratios[k], mid = sqrt(R1 * R2);
      const double radii[3] = {R1, mid, R2};
      sl_optics_tables *T = build(cases[c].p, radii, 3);
      if (!T) return sl_test_finish("test_size_interpolation");
      const sl_phase_table *a = sl_optics_table_sized(T, cases[c].p, R1, 0);
      const sl_phase_table *m = sl_optics_table_sized(T, cases[c].p, mid, 0);
      const sl_phase_table *b = sl_optics_table_sized(T, cases[c].p, R2, 0);
      double norm;
      const double e = wrong_way(a, b, 0.5 * scattering_per_mass(a, R1), 0.5 * scattering_per_mass(b, R2), m, &norm);
      printf("%-14s ratio %.2f: light sent the wrong way %.4f, mixture normalised to %.2e\n", cases[c].label,
             ratios[k], e, fabs(norm - 1.0));
      CHECK(fabs(norm - 1.0) < 1e-4);
      CHECK(e >= previous - 2e-3); /* a wider ratio is no better, within the quadrature's noise */
      previous = e;
      /* The loader's ratios (io/size_bins.c): 1.5 for cloud, 3 for rain. */
      if (ratios[k] == (cases[c].p == SL_CLOUD ? 1.5 : 3.0) && e > at_loader_ratio) at_loader_ratio = e;
      if (k == 2) {
        /* Fraunhofer: twice the radius, half the lobe (the grid step and the lognormal's smoothing
         * leave a few per cent). */
        const double la = lobe_angle(a), lb = lobe_angle(b);
        printf("%-14s lobe's log-slope -2: %.3f deg at R, %.3f deg at 2R (ratio %.3f)\n", cases[c].label, la,
               lb, la / lb);
        if (c == 0) CHECK_CLOSE(la / lb, 2.0, 0.06, 0.0);
      }
      sl_optics_free(T);
    }
  }
  printf("worst light sent the wrong way at the loader's ratios (cloud 1.5, rain 3): %.4f\n", at_loader_ratio);
  CHECK(at_loader_ratio < 0.025);
  return sl_test_finish("test_size_interpolation");
}
