/* Legendre machinery for zonal (axially symmetric) angular distributions on the sphere.
 *
 * A distribution D(mu), mu = cos(theta), normalised to 1 over the sphere, is written
 *   D(mu) = sum_l (2l+1)/(4 pi) * chi_l * P_l(mu),   chi_l = 2 pi * integral_{-1}^{1} D P_l dmu,
 * so chi_0 = 1 and chi_1 = g. The spherical convolution of two such distributions multiplies
 * their chi_l (Funk–Hecke theorem); Ams_n of Riley et al. 2004, eq. 20, has chi_l^n. */
#ifndef SL_LEGENDRE_H
#define SL_LEGENDRE_H

#include "sl_quadrature.h" /* sl_gauss_legendre */

#ifdef __cplusplus
extern "C" {
#endif

#define SL_PI 3.14159265358979323846

/* Henyey–Greenstein phase function (1/sr); its moments are chi_l = g^l. */
double sl_hg_phase(double g, double mu);

/* D(mu) from moments chi[0..n_moments-1] (Clenshaw summation). */
double sl_legendre_series(const double *chi, int n_moments, double mu);

/* Moments chi[0..n_moments-1] of a function given at n_nodes Gauss–Legendre nodes:
 * chi_l = 2 pi sum_i w_i D(x_i) P_l(x_i). Exact when D is a polynomial of degree
 * < 2 n_nodes - n_moments + 1. */
void sl_legendre_moments_gauss(const double *nodes, const double *weights, const double *values, int n_nodes,
                               int n_moments, double *chi);

/* Forward-hemisphere fraction of a distribution from its moments:
 * 2 pi int_0^1 D dmu = 1/2 chi_0 + 1/2 sum_{l odd} chi_l (P_{l-1}(0) - P_{l+1}(0)). */
double sl_legendre_forward_fraction(const double *chi, int n_moments);

#ifdef __cplusplus
}
#endif
#endif
