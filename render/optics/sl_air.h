/* Optics of air molecules: closed forms, no tables. */
#ifndef SL_AIR_H
#define SL_AIR_H

#ifdef __cplusplus
extern "C" {
#endif

/* Rayleigh scattering cross-section of one air molecule (m^2), Bodhaine et al. 1999, eq. 29. */
double sl_air_cross_section(double wavelength_nm);
/* Rayleigh phase function (1/sr), Riley et al. 2004, eq. 1. */
double sl_rayleigh_phase(double cos_theta);
/* Ams_n of air: eq. 1's moments are chi_0 = 1, chi_2 = 1/10, so
 * Ams_n = (1 + 5 (1/10)^n P_2(mu)) / (4 pi); n = 0 has no smooth part here (returns 0). */
double sl_rayleigh_ams(int n, double cos_theta);

#ifdef __cplusplus
}
#endif
#endif
