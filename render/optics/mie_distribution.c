/* Cloud droplets and raindrops: Mie scattering averaged over a lognormal size distribution
 * (Riley et al. 2004, sec. 3.1, who used MiePlot with lognormal distributions after
 * Pruppacher & Klett). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "optics_internal.h"
#include "sl_legendre.h"
#include "sl_mie.h"
#include "sl_refractive.h"

/* Number distributions n(ln r) = N / (sqrt(2 pi) s) exp(-(ln r - ln r_g)^2 / (2 s^2)).
 * Median radii follow Riley et al.'s representative sizes (Table 2: 0.01 mm cloud droplets,
 * 1 mm raindrops); mode radius = r_g exp(-s^2). Widths: s = 0.25 (geometric standard deviation
 * 1.28). For cloud droplets, lognormal fits of stratiform cloud spectra compiled by Miles,
 * Verlinde & Clothiaux 2000 (J. Atmos. Sci. 57, 295) have relative dispersions mostly
 * 0.2-0.4; for rain, lognormal fits to raindrop spectra by Feingold & Levin 1986
 * (J. Clim. Appl. Meteor. 25, 1346) have geometric standard deviations of about 1.2-1.5.
 * s = 0.25 is a choice within both ranges, narrow enough to keep the glory's rings. */
static const optics_lognormal DISTRIBUTIONS[SL_PARTICLE_COUNT] = {
    [SL_CLOUD] = {10e-6, 0.25, "lognormal, median radius 10 um, s = 0.25 (Miles et al. 2000 range)"},
    [SL_RAIN] = {1e-3, 0.25, "lognormal, median radius 1 mm, s = 0.25 (Feingold & Levin 1986 range)"},
};

const optics_lognormal *optics_size_distribution(sl_particle p)
{
  if ((p == SL_CLOUD || p == SL_RAIN)) return &DISTRIBUTIONS[p];
  return NULL;
}

double optics_lognormal_effective_radius(const optics_lognormal *d)
{
  return d->median_radius_m * exp(2.5 * d->sigma_ln * d->sigma_ln);
}

int optics_size_distribution_at(sl_particle p, double r_eff_m, optics_lognormal *out)
{
  const optics_lognormal *own = optics_size_distribution(p);
  if (!own) return 0;
  *out = *own;
  if (r_eff_m > 0.0) out->median_radius_m = r_eff_m * exp(-2.5 * own->sigma_ln * own->sigma_ln);
  return 1;
}

int optics_mie_distribution(sl_particle p, const optics_lognormal *dist, double wavelength_nm,
                            const optics_grid *g, int radius_samples, optics_raw_phase *out, sl_error *err)
{
  if (!dist) return sl_fail(err, SL_ERR_ARG, "optics: %s is not a Mie particle", sl_particle_name(p));
  if (radius_samples < 1) return sl_fail(err, SL_ERR_ARG, "optics: radius_samples must be >= 1");
  double m_re, m_im;
  sl_water_index(wavelength_nm, &m_re, &m_im);
  const double k = 2.0 * SL_PI / (wavelength_nm * 1e-9);

  const int J = g->n_angles, half = (J + 1) / 2; /* theta <= 90 degrees, mirrored for the rest */
  const int R = radius_samples;
  double *s11 = malloc(sizeof(double) * (size_t)R * (size_t)(2 * half));
  double *csca = malloc(sizeof(double) * (size_t)R * 4);
  if (!s11 || !csca) {
    free(s11), free(csca);
    return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory for %d radii", R);
  }
  double *cext = csca + R, *gsca = cext + R, *weight = gsca + R;
  int failed = 0;
  sl_error first = {0};

  /* Quadrature in t = (ln r - ln r_g) / s on [-3, 3] with equal steps (midpoint nodes): the
   * integrands oscillate in r (ripple, interference), so nodes that avoid a regular pattern in
   * size parameter are what matters, not polynomial degree. */
#pragma omp parallel
  {
    sl_mie_workspace ws = {0};
#pragma omp for schedule(dynamic, 1)
    for (int i = 0; i < R; ++i) {
      const double t = -3.0 + 6.0 * (i + 0.5) / R;
      const double r = dist->median_radius_m * exp(dist->sigma_ln * t);
      const double x = k * r;
      sl_mie_efficiencies e;
      sl_error e_local = {0};
      weight[i] = exp(-0.5 * t * t);
      if (sl_mie_s11_mirrored(x, m_re, m_im, g->mu, half, &e, s11 + (size_t)i * (size_t)(2 * half), &ws, &e_local)) {
#pragma omp critical
        {
          if (!failed) first = e_local;
          failed = 1;
        }
        continue;
      }
      const double area = SL_PI * r * r;
      csca[i] = area * e.qsca;
      cext[i] = area * e.qext;
      gsca[i] = area * e.qsca * e.g;
    }
    sl_mie_workspace_free(&ws);
  }
  if (failed) {
    free(s11), free(csca);
    return sl_fail(err, first.code, "%s", first.message);
  }

  double sum_sca = 0.0, sum_ext = 0.0, sum_g = 0.0, sum_r3 = 0.0, sum_w = 0.0;
  for (int i = 0; i < R; ++i) {
    const double t = -3.0 + 6.0 * (i + 0.5) / R;
    const double r = dist->median_radius_m * exp(dist->sigma_ln * t);
    sum_sca += weight[i] * csca[i];
    sum_ext += weight[i] * cext[i];
    sum_g += weight[i] * gsca[i];
    sum_r3 += weight[i] * r * r * r;
    sum_w += weight[i];
  }
  /* P = <S11> / (k^2 <C_sca>) (B&H eq. 3.16 with S11 = (|S1|^2+|S2|^2)/2), in 1/sr. */
  for (int j = 0; j < J; ++j) {
    const int src = j < half ? j : j + 1; /* mirrored output duplicates 90 degrees */
    double s = 0.0;
    for (int i = 0; i < R; ++i) s += weight[i] * s11[(size_t)i * (size_t)(2 * half) + (size_t)src];
    out->p[j] = s / (k * k * sum_sca);
  }
  /* Extinction per representative particle (sl_particles.h): the renderer computes the number
   * of representative particles from the mass, so the cross-section it needs is the
   * distribution's extinction per unit mass times the representative particle's mass. */
  const sl_particle_props *props = sl_particle_properties(p);
  const double mean_r3 = sum_r3 / sum_w, rep_r3 = props->radius_m * props->radius_m * props->radius_m;
  out->sigma_ext = (sum_ext / sum_w) * rep_r3 / mean_r3;
  out->albedo = sum_sca / sum_ext;
  out->asymmetry = sum_g / sum_sca;
  free(s11), free(csca);
  return SL_OK;
}
