/* An independent solution of the plane-parallel slab (tests only): the adding-doubling method
 * (van de Hulst 1980, ch. 4; Hansen & Travis 1974, sec. 3.4) for the azimuth-averaged radiance
 * field, with double-Gauss quadrature. It shares no code with the path tracer: it integrates
 * the transport equation deterministically, not by sampling. */
#ifndef SL_ADDING_DOUBLING_H
#define SL_ADDING_DOUBLING_H

typedef struct ad_slab {
  double tau;          /* optical thickness */
  double albedo;       /* single-scattering albedo */
  const double *chi;   /* Legendre moments of the phase function (chi_0 = 1), or NULL: HG */
  int n_chi;
  double g;            /* HG asymmetry when chi is NULL */
  double mu0;          /* cosine of the sun's zenith angle */
  int n_quad;          /* Gauss points per hemisphere (< 128) */
  double mu_extra;     /* > 0: also report the reflection and transmission functions at this mu */
} ad_slab;

typedef struct ad_fluxes {
  double reflectance, transmittance, direct_transmittance; /* per unit incident horizontal irradiance */
  /* van de Hulst's reflection and (diffuse) transmission functions at mu_extra: I / (mu0 F) for
   * an incident flux pi F normal to the beam, i.e. pi I / E with E the horizontal irradiance. */
  double reflection_function, transmission_function;
} ad_fluxes;

/* Returns 0 on success. */
int ad_slab_fluxes(const ad_slab *s, ad_fluxes *out);

#endif
