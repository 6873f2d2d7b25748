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

/* The quadrature's i-th node in t = lambda D: midpoints of R equal steps of (0, RIMED_T_MAX]. */
static double node_t(int i, int R)
{
  return RIMED_T_MAX * (i + 0.5) / R;
}

/* The large-particle limit's spheres: midpoints of equal steps of x across [x_max / 2, x_max]. */
static double band_size_parameter(int j)
{
  return SL_RIMED_X_MIE_MAX * (0.5 + 0.5 * (j + 0.5) / SL_RIMED_BAND_SPHERES);
}

int optics_rimed_ice(sl_particle p, double wavelength_nm, const optics_grid *g, int radius_samples,
                     optics_raw_phase *out, sl_error *err)
{
  const optics_exponential *dist = optics_rimed_distribution(p);
  if (!dist) return sl_fail(err, SL_ERR_ARG, "optics: %s is not rimed ice", sl_particle_name(p));
  if (radius_samples < 1) return sl_fail(err, SL_ERR_ARG, "optics: radius_samples must be >= 1");
  double m_re, m_im;
  sl_rimed_ice_index(wavelength_nm, dist->density_kg_m3, &m_re, &m_im);
  const double k = 2.0 * SL_PI / (wavelength_nm * 1e-9);
  const int J = g->n_angles, half = (J + 1) / 2, R = radius_samples, B = SL_RIMED_BAND_SPHERES;
  const size_t row = (size_t)(2 * half);
  /* Rows 0..R-1: the quadrature's nodes (those beyond x_max unused); rows R..R+B-1: the band. */
  double *s11 = malloc(sizeof(double) * (size_t)(R + B) * row);
  sphere_scattering *sph = malloc(sizeof *sph * (size_t)(R + B));
  if (!s11 || !sph) {
    free(s11), free(sph);
    return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory for %d radii", R + B);
  }
  int failed = 0;
  sl_error first = {0};
#pragma omp parallel
  {
    sl_mie_workspace ws = {0};
#pragma omp for schedule(dynamic, 1)
    for (int i = 0; i < R + B; ++i) {
      const double x = i >= R ? band_size_parameter(i - R) : k * 0.5 * node_t(i, R) / dist->slope_per_m;
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
  /* The large-particle limit, x > x_max = 2e4: Q_ext = 2 (the extinction paradox: diffraction
   * removes as much as the geometric shadow); the absorbed fraction grows with the path through the
   * sphere, Q_abs = x times the band's mean Q_abs / x (weak absorption, capped at 1); and S11 per
   * unit of scattering cross-section is the band's mean. Outside the diffraction peak geometric
   * optics makes that shape independent of size for a weakly absorbing sphere; the peak itself, 1/x
   * radians wide (0.003 degrees at 2e4), lies inside the table's truncation cone at every larger x.
   * The band's mean, not one sphere: a sphere's S11 carries interference ripple a hundredth of a
   * degree apart, which the table's grid samples as noise that differs between wavelengths
   * (coloured stripes around a sun behind hail); over sizes the ripple averages out, as it does
   * over the distribution the limit stands for. Visible ice absorbs below 1e-3 across a
   * centimetre, so what the limit leaves out is the diffraction tail's fall (as 1/x against the
   * geometric part) beyond the band, a few degrees from the forward direction. */
  double *mean_s11 = calloc(2 * row, sizeof(double)), *shape = mean_s11 + row;
  if (!mean_s11) {
    free(s11), free(sph);
    return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory");
  }
  double qabs_per_x = 0.0, g_lim = 0.0;
  for (int j = 0; j < B; ++j) {
    const double x = band_size_parameter(j);
    const sphere_scattering s = sph[R + j];
    const double *src = s11 + (size_t)(R + j) * row;
    for (size_t a = 0; a < row; ++a) shape[a] += src[a] / (x * x * s.qsca * B);
    qabs_per_x += (s.qext - s.qsca) / (x * B);
    g_lim += s.g / B;
  }
  double sum_sca = 0.0, sum_ext = 0.0, sum_g = 0.0, sum_d3 = 0.0;
  for (int i = 0; i < R; ++i) {
    const double t = node_t(i, R);
    const double d = t / dist->slope_per_m, x = k * 0.5 * d, area = 0.25 * SL_PI * d * d;
    const double w = exp(-t); /* number per unit lambda D, the midpoint rule's weight */
    sphere_scattering s = sph[i];
    if (x > SL_RIMED_X_MIE_MAX) {
      const double qabs = fmin(1.0, qabs_per_x * x);
      s = (sphere_scattering){2.0, 2.0 - qabs, g_lim};
      /* S11 integrates to x^2 pi Q_sca (sl_mie.h): the band's shape times this sphere's x^2 Q_sca. */
      for (size_t a = 0; a < row; ++a) mean_s11[a] += w * x * x * s.qsca * shape[a];
    } else {
      const double *src = s11 + (size_t)i * row;
      for (size_t a = 0; a < row; ++a) mean_s11[a] += w * src[a];
    }
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
