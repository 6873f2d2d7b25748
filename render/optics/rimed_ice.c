/* Graupel and hail: Mie scattering by spheres of rimed ice, averaged over an exponential size
 * distribution, with a stated large-particle limit where the series would be too long.
 *
 * The particle is a homogeneous sphere whose index is Bruggeman's mixture of ice and air at the
 * species' bulk density (sl_rimed_ice_index; docs/OPTICS.md says why Bruggeman and what a real,
 * lumpy, rough graupel particle does differently). Sizes follow n(D) = N0 exp(-lambda D), the
 * distribution of the single-moment schemes these species come from: graupel after Rutledge &
 * Hobbs 1984 (J. Atmos. Sci. 41, 2949: N0 = 4e6 m^-4, 400 kg/m3), hail after Lin, Farley & Orville
 * 1983 (J. Clim. Appl. Meteor. 22, 1065: N0 = 4e4 m^-4; 900 kg/m3 as in Morrison's and
 * Milbrandt & Yau's hail), both at a mass content of 1 g/m3, where lambda = (pi rho N0 / (rho q))^(1/4)
 * is 1500 and 580 per metre: effective radii 1.0 and 2.6 mm. */
#include <math.h>
#include <stdlib.h>

#include "optics_internal.h"
#include "sl_legendre.h"
#include "sl_mie.h"
#include "sl_refractive.h"

static const optics_exponential DISTRIBUTIONS[SL_PARTICLE_COUNT] = {
    [SL_GRAUPEL] = {1500.0, 400.0, "exponential, lambda 1500/m (Rutledge & Hobbs 1984's N0 at 1 g/m3), 400 kg/m3"},
    [SL_HAIL] = {580.0, 900.0, "exponential, lambda 580/m (Lin et al. 1983's N0 at 1 g/m3), 900 kg/m3"},
};

const optics_exponential *optics_rimed_distribution(sl_particle p)
{
  return (p == SL_GRAUPEL || p == SL_HAIL) ? &DISTRIBUTIONS[p] : NULL;
}

/* The quadrature covers lambda D in (0, 20]: the cross-section weight (lambda D)^2 exp(-lambda D)
 * beyond 20 is below 2e-6 of its peak and its integral beyond 20 below 1e-5 of the whole. */
#define RIMED_T_MAX 20.0

/* Scattering of one sphere of size parameter x: S11 on the mirrored half grid and the
 * cross-sections per unit of its geometric area (efficiencies). */
typedef struct sphere_scattering {
  double qext, qsca, g;
} sphere_scattering;

int optics_rimed_ice(sl_particle p, double wavelength_nm, const optics_grid *g, int radius_samples,
                     optics_raw_phase *out, sl_error *err)
{
  const optics_exponential *dist = optics_rimed_distribution(p);
  if (!dist) return sl_fail(err, SL_ERR_ARG, "optics: %s is not rimed ice", sl_particle_name(p));
  if (radius_samples < 1) return sl_fail(err, SL_ERR_ARG, "optics: radius_samples must be >= 1");
  double m_re, m_im;
  sl_rimed_ice_index(wavelength_nm, dist->density_kg_m3, &m_re, &m_im);
  const double k = 2.0 * SL_PI / (wavelength_nm * 1e-9);
  const int J = g->n_angles, half = (J + 1) / 2, R = radius_samples;
  const size_t row = (size_t)(2 * half);
  /* Row R holds the sphere at x = SL_RIMED_X_MIE_MAX, the shape of every larger one. */
  double *s11 = malloc(sizeof(double) * (size_t)(R + 1) * row);
  sphere_scattering *sph = malloc(sizeof *sph * (size_t)(R + 1));
  if (!s11 || !sph) {
    free(s11), free(sph);
    return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory for %d radii", R);
  }
  int failed = 0;
  sl_error first = {0};
#pragma omp parallel
  {
    sl_mie_workspace ws = {0};
#pragma omp for schedule(dynamic, 1)
    for (int i = 0; i <= R; ++i) {
      const double x = i == R ? SL_RIMED_X_MIE_MAX : k * 0.5 * RIMED_T_MAX * (i + 0.5) / R / dist->slope_per_m;
      if (i < R && x > SL_RIMED_X_MIE_MAX) continue; /* the large-particle limit, below */
      sl_mie_efficiencies e;
      sl_error e_local = {0};
      if (sl_mie_s11_mirrored(x, m_re, m_im, g->mu, half, &e, s11 + (size_t)i * row, &ws, &e_local)) {
#pragma omp critical
        {
          if (!failed) first = e_local;
          failed = 1;
        }
        continue;
      }
      sph[i] = (sphere_scattering){e.qext, e.qsca, e.g};
    }
    sl_mie_workspace_free(&ws);
  }
  if (failed) {
    free(s11), free(sph);
    return sl_fail(err, first.code, "%s", first.message);
  }
  /* The large-particle limit, x > 2e4: Q_ext = 2 (the extinction paradox: diffraction removes as
   * much as the geometric shadow); the absorbed fraction grows with the path through the sphere,
   * Q_abs = Q_abs(2e4) x / 2e4 (weak absorption, capped at 1); and S11 keeps the shape it has at
   * x = 2e4. Outside the diffraction peak geometric optics makes the angular pattern independent of
   * size for a weakly absorbing sphere; the peak itself, 1/x radians wide (0.003 degrees at 2e4),
   * lies inside the table's truncation cone at every larger x, so its narrowing changes no table.
   * Visible ice absorbs below 1e-3 across a centimetre: the limit's error is the missing ripple. */
  const sphere_scattering lim = sph[R];
  const double qabs_lim = lim.qext - lim.qsca;
  double sum_sca = 0.0, sum_ext = 0.0, sum_g = 0.0, sum_d3 = 0.0;
  double *mean_s11 = calloc(row, sizeof(double));
  if (!mean_s11) {
    free(s11), free(sph);
    return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory");
  }
  for (int i = 0; i < R; ++i) {
    const double t = RIMED_T_MAX * (i + 0.5) / R;
    const double d = t / dist->slope_per_m, x = k * 0.5 * d, area = 0.25 * SL_PI * d * d;
    const double w = exp(-t); /* number per unit lambda D, the midpoint rule's weight */
    const double *src = s11 + (size_t)i * row;
    double scale = 1.0;
    sphere_scattering s = sph[i];
    if (x > SL_RIMED_X_MIE_MAX) {
      const double qabs = fmin(1.0, qabs_lim * x / SL_RIMED_X_MIE_MAX);
      s = (sphere_scattering){2.0, 2.0 - qabs, lim.g};
      /* S11 integrates to x^2 pi Q_sca (sl_mie.h): the limit's shape, rescaled to this sphere. */
      scale = (x / SL_RIMED_X_MIE_MAX) * (x / SL_RIMED_X_MIE_MAX) * s.qsca / lim.qsca;
      src = s11 + (size_t)R * row;
    }
    for (size_t j = 0; j < row; ++j) mean_s11[j] += w * scale * src[j];
    sum_ext += w * area * s.qext;
    sum_sca += w * area * s.qsca;
    sum_g += w * area * s.qsca * s.g;
    sum_d3 += w * d * d * d;
  }
  /* P = <S11> / (k^2 <C_sca>) (B&H eq. 3.16), in 1/sr, on the full grid from the mirrored one. */
  for (int j = 0; j < J; ++j) out->p[j] = mean_s11[j < half ? j : j + 1] / (k * k * sum_sca);
  /* Per representative particle (sl_particles.h): the distribution's extinction per unit mass
   * times the representative particle's mass, as for cloud and rain. */
  const double mean_mass = dist->density_kg_m3 * SL_PI / 6.0 * sum_d3;
  out->sigma_ext = sum_ext / mean_mass * sl_particle_mass(p);
  out->albedo = sum_sca / sum_ext;
  out->asymmetry = sum_g / sum_sca;
  free(mean_s11), free(s11), free(sph);
  return SL_OK;
}
