/* Hydrometeor particle types and the bulk properties that turn a mixing ratio into an
 * extinction coefficient. The optics module refines the per-wavelength optics; the mass and
 * the extinction cross-section of a representative particle live here, once. */
#ifndef SL_PARTICLES_H
#define SL_PARTICLES_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sl_particle {
  SL_CLOUD = 0, /* liquid cloud droplets */
  SL_RAIN = 1,  /* raindrops */
  SL_ICE = 2,   /* pristine ice crystals (hexagonal) */
  SL_SNOW = 3,  /* snow aggregates */
  SL_GRAUPEL = 4, /* rimed ice, about 400 kg/m3, millimetres */
  SL_HAIL = 5,  /* dense ice, about 900 kg/m3, millimetres to centimetres */
  SL_PARTICLE_COUNT = 6
} sl_particle;

typedef struct sl_particle_props {
  const char *name;          /* "cloud", "rain", ... */
  double sigma_ext_m2;       /* extinction cross-section, Riley et al. 2004 Table 2 */
  double radius_m;           /* radius of the representative particle */
  double density_kg_m3;      /* bulk density of the representative particle */
  const char *mass_source;   /* how the mass was chosen, for reports */
  /* Effective radius of the size distribution the optics tables average over (render/optics):
   * the tables' extinction per unit mass is 3 Q / (4 density r_eff) with Q near 2, so a voxel
   * whose particles have another effective radius scales it by r_eff / its own (io/species.c). */
  double effective_radius_m;
} sl_particle_props;

const sl_particle_props *sl_particle_properties(sl_particle p);
const char *sl_particle_name(sl_particle p);
/* Mass (kg) of the representative particle: density * 4/3 pi r^3. */
double sl_particle_mass(sl_particle p);
/* Returns -1 for an unknown name. */
int sl_particle_from_name(const char *name);

/* Number concentration (m^-3) from a mixing ratio q (kg/kg) and air density (kg/m^3):
 * eta = rho_air * q / m_particle (DESIGN.md). Negative q must be clamped by the caller. */
double sl_number_concentration(double rho_air, double q, double particle_mass);

#ifdef __cplusplus
}
#endif
#endif
