/* CIE 1931 colour matching and conversion of spectral radiance at a few wavelengths to linear
 * sRGB (IEC 61966-2-1 primaries, D65 white). */
#ifndef SL_CIE_H
#define SL_CIE_H

#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* CIE 1931 2-degree colour matching functions x_bar, y_bar, z_bar at one wavelength. */
void sl_cie_xyz_bar(double wavelength_nm, double xyz[3]);

/* Weights w[c * n + i] such that linear sRGB channel c = sum_i w[c*n+i] * radiance[i] for
 * radiance sampled at wavelengths_nm[0..n-1] (ascending, n >= 2; trapezoid rule in lambda).
 * Normalised so that a flat spectrum of 1 has luminance Y = 1. With white_balance != 0 the
 * channels are further scaled so that a flat spectrum maps to (1, 1, 1): the convention for a
 * sun of "irradiance 1 per channel" (DESIGN.md). */
int sl_cie_srgb_weights(const double *wavelengths_nm, int n, int white_balance, double *w, sl_error *err);

/* rgb = the weights applied to radiance (inline: the passes resolve every pixel with it). */
static inline void sl_cie_apply(const double *w, int n, const double *radiance, double rgb[3])
{
  for (int c = 0; c < 3; ++c) {
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += w[c * n + i] * radiance[i];
    rgb[c] = s;
  }
}

#ifdef __cplusplus
}
#endif
#endif
