/* Refractive indices of water and ice (m = re + i im, im >= 0 absorbs) and the optics of air. */
#ifndef SL_REFRACTIVE_H
#define SL_REFRACTIVE_H

#ifdef __cplusplus
extern "C" {
#endif

/* Liquid water: real part from the IAPWS 1997 formulation (Harvey et al. 1998), imaginary part
 * from Hale & Querry 1973. temperature_k and density_kg_m3 feed IAPWS only.
 * sl_water_index_re is relative to vacuum; sl_water_index returns the index relative to air. */
double sl_water_index_re(double wavelength_nm, double temperature_k, double density_kg_m3);
double sl_water_index_im(double wavelength_nm);
/* Cloud and rain water at 10 C (283.15 K, 999.70 kg/m3). */
void sl_water_index(double wavelength_nm, double *re, double *im);

/* Ice Ih, Warren & Brandt 2008 (tabulated 390-730 nm). */
void sl_ice_index(double wavelength_nm, double *re, double *im);

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
