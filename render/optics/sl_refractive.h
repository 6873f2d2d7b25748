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

/* Solid ice's density (kg/m3) that sl_ice_index describes: ice Ih near 0 C. */
#define SL_SOLID_ICE_DENSITY 917.0

/* The Bruggeman effective medium of two components, index (re1 + i im1) at volume fraction f1
 * and (re2 + i im2) at 1 - f1: the permittivity eps that solves
 *     f1 (eps1 - eps) / (eps1 + 2 eps) + (1 - f1) (eps2 - eps) / (eps2 + 2 eps) = 0
 * (Bohren & Huffman 1983, eq. 8.51), the root with Im eps >= 0. Returns its index. */
void sl_bruggeman_index(double f1, double re1, double im1, double re2, double im2, double *re, double *im);

/* Rimed ice of bulk density rho (graupel, hail: ice with air in its pores) as one homogeneous
 * medium: Bruggeman's mixture of sl_ice_index at the volume fraction rho / 917 with air (index 1).
 * rho above 917 is solid ice. */
void sl_rimed_ice_index(double wavelength_nm, double density_kg_m3, double *re, double *im);

#ifdef __cplusplus
}
#endif
#endif
