/* Quadrature rules shared by the optics tables, the glows and the sky's irradiance on the ground. */
#ifndef SL_QUADRATURE_H
#define SL_QUADRATURE_H

#ifdef __cplusplus
extern "C" {
#endif

/* Gauss-Legendre nodes and weights on [-1, 1] (Newton iteration on P_n, n >= 1). */
void sl_gauss_legendre(int n, double *nodes, double *weights);

#ifdef __cplusplus
}
#endif
#endif
