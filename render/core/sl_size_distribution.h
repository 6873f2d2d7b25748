/* Gamma size distributions of bulk microphysics schemes, n(D) = N0 D^mu exp(-lambda D), for
 * spheres of a fixed bulk density (m = rho pi D^3 / 6): the slope and the effective radius that a
 * voxel's mass content and number concentration imply. The schemes' constants live in
 * io/species.c (docs/DATA.md tables them with their sources). */
#ifndef SL_SIZE_DISTRIBUTION_H
#define SL_SIZE_DISTRIBUTION_H

#ifdef __cplusplus
extern "C" {
#endif

/* How a scheme sets the shape mu. */
typedef enum sl_shape_rule {
  SL_SHAPE_FIXED = 0,      /* mu as given */
  SL_SHAPE_MARTIN1994 = 1, /* cloud droplets in Morrison et al. 2005 and P3: from the number */
  SL_SHAPE_THOMPSON2008 = 2 /* cloud droplets in Thompson et al. 2008: from the number */
} sl_shape_rule;

typedef struct sl_gamma_distribution {
  sl_shape_rule rule;
  double mu;              /* shape when rule is SL_SHAPE_FIXED */
  double density_kg_m3;   /* bulk density of the spheres */
  double fixed_number_m3; /* the scheme's number concentration when it predicts none (cloud
                             droplets of one-moment cloud water); 0: none */
  double fixed_intercept_m4; /* N0 (m^-4) of a single-moment scheme's exponential (rain, graupel:
                                Marshall-Palmer style), which the mass then scales; 0: none */
  const char *source;     /* the scheme's documentation, for reports */
} sl_gamma_distribution;

/* The shape mu of distribution d at number concentration N (m^-3). */
double sl_gamma_shape(const sl_gamma_distribution *d, double number_m3);
/* The slope lambda (1/m) of the distribution that holds mass content M (kg/m3) in N particles
 * per m3: M = rho pi / 6 N Gamma(mu + 4) / (Gamma(mu + 1) lambda^3). */
double sl_gamma_slope(const sl_gamma_distribution *d, double mass_kg_m3, double number_m3);
/* Number concentration (m^-3) of the distribution with d's fixed intercept N0 that holds mass content
 * M: M = rho pi / 6 N0 Gamma(mu + 4) / lambda^(mu + 4) gives lambda, and N = N0 Gamma(mu + 1) /
 * lambda^(mu + 1). 0 when d fixes no intercept. */
double sl_gamma_number_from_intercept(const sl_gamma_distribution *d, double mass_kg_m3);
/* Effective radius (m), half the ratio of the third to the second moment, (mu + 3) / (2 lambda):
 * the size whose spheres have the distribution's extinction per unit mass in the large-particle
 * limit (3 Q / (4 rho r_eff)). */
double sl_gamma_effective_radius(const sl_gamma_distribution *d, double mass_kg_m3, double number_m3);

#ifdef __cplusplus
}
#endif
#endif
