#include "sl_particles.h"

#include <math.h>
#include <string.h>

/* Radii follow from Table 2's sigma_ext = 2 pi r^2 (the large-particle extinction limit):
 * cloud 10 um and rain 1 mm as the paper states; for ice and snow the equivalent radius that
 * reproduces Table 2's cross-section, sqrt(sigma / 2 pi). Densities: water 1000, solid ice
 * 917, snow aggregates 100 kg/m3 (a typical bulk density, Pruppacher & Klett 2000, ch. 2).
 * Graupel and hail (not in Table 2) are spheres at the effective radius 3 / (2 lambda) of their
 * representative exponential distributions (render/optics/rimed_ice.c): graupel of 400 kg/m3 with
 * Rutledge & Hobbs 1984's intercept 4e6 m^-4, hail of 900 kg/m3 with Lin et al. 1983's 4e4 m^-4,
 * both at 1 g/m3 (lambda 1500 and 580 per metre), with the large-sphere cross-section 2 pi r^2.
 * Effective radii: cloud and rain average over lognormals of median r_g and width s = 0.25
 * (render/optics/mie_distribution.c), whose effective radius is r_g exp(2.5 s^2); ice and snow are
 * the spheres of Table 2's cross-section; graupel and hail their distributions' 3 / (2 lambda). */
static const sl_particle_props PARTICLES[SL_PARTICLE_COUNT] = {
    [SL_CLOUD] = {"cloud", 6.28e-10, 10e-6, 1000.0, "water sphere, r = 10 um", 11.69118e-6},
    [SL_RAIN] = {"rain", 6.28e-6, 1e-3, 1000.0, "water sphere, r = 1 mm", 1.169118e-3},
    [SL_ICE] = {"ice", 1.82e-6, 5.382e-4, 917.0, "solid ice sphere with Table 2's cross-section", 5.382e-4},
    [SL_SNOW] = {"snow", 1.41e-5, 1.498e-3, 100.0, "aggregate of bulk density 100 kg/m3 with Table 2's cross-section", 1.498e-3},
    [SL_GRAUPEL] = {"graupel", 6.2832e-6, 1.0e-3, 400.0, "rimed-ice sphere of 400 kg/m3, r = 1 mm (exponential, lambda 1500/m)", 1.0e-3},
    [SL_HAIL] = {"hail", 4.2025e-5, 2.5862e-3, 900.0, "ice sphere of 900 kg/m3, r = 2.59 mm (exponential, lambda 580/m)", 2.5862e-3},
};

const sl_particle_props *sl_particle_properties(sl_particle p)
{
  if ((int)p < 0 || p >= SL_PARTICLE_COUNT) return NULL;
  return &PARTICLES[p];
}

double sl_particle_mass(sl_particle p)
{
  const sl_particle_props *pp = sl_particle_properties(p);
  if (!pp) return NAN;
  return pp->density_kg_m3 * 4.0 / 3.0 * M_PI * pp->radius_m * pp->radius_m * pp->radius_m;
}

const char *sl_particle_name(sl_particle p)
{
  const sl_particle_props *props = sl_particle_properties(p);
  return props ? props->name : "unknown";
}

int sl_particle_from_name(const char *name)
{
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
    if (strcmp(name, PARTICLES[p].name) == 0) return p;
  return -1;
}

double sl_number_concentration(double rho_air, double q, double particle_mass)
{
  return rho_air * q / particle_mass;
}
