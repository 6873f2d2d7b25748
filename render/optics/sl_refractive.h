/* Refractive indices of water and ice (m = re + i im, im >= 0 absorbs). */
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

#ifdef __cplusplus
}
#endif
#endif
