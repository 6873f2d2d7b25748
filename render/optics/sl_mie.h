/* Lorenz–Mie scattering by a homogeneous sphere (Bohren & Huffman 1983, ch. 4; algorithm of
 * their BHMIE with the criteria of Wiscombe 1980, "Improved Mie scattering algorithms",
 * Appl. Opt. 19, 1505).
 *
 * Conventions: refractive index m = m_re + i*m_im relative to the medium, m_im >= 0 absorbs
 * (Bohren & Huffman's sign; Wiscombe's MIEV0 writes the same sphere as m_re - i*m_im).
 * Amplitudes S1, S2 are Bohren & Huffman's, so S11 = (|S1|^2 + |S2|^2) / 2 and
 * integral of S11 over the sphere = x^2 * pi * Qsca (= k^2 C_sca). */
#ifndef SL_MIE_H
#define SL_MIE_H

#include <stddef.h>

#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sl_mie_efficiencies {
  double qext, qsca, qback; /* extinction, scattering, radar backscatter efficiencies */
  double g;                 /* asymmetry parameter <cos theta> */
  int terms;                /* number of series terms used (Wiscombe's N_stop) */
} sl_mie_efficiencies;

typedef struct sl_amplitude {
  double re, im;
} sl_amplitude;

/* Size parameter range the code is tested for: 1e-6 .. 1e5 is accepted, 1e-3 .. 2e4 tested. */
#define SL_MIE_X_MIN 1e-6
#define SL_MIE_X_MAX 1e5

/* Number of terms of the series (Wiscombe 1980, eq. 21 and its small-x form). */
int sl_mie_series_terms(double x);

/* Efficiencies, and, when n_angles > 0, S1/S2 (either may be NULL) and S11 (may be NULL) at the
 * cosines mu[0..n_angles-1]. Returns SL_OK or SL_ERR_ARG / SL_ERR_NOMEM. */
int sl_mie(double x, double m_re, double m_im, const double *mu, int n_angles, sl_mie_efficiencies *out,
           sl_amplitude *s1, sl_amplitude *s2, double *s11, sl_error *err);

/* Same, for angles that come in mirrored pairs: mu_half[0..n_half-1] are cosines >= 0 and the
 * result s11[0..2*n_half-1] holds S11(mu_half[i]) at i and S11(-mu_half[i]) at 2*n_half-1-i.
 * Uses pi_n(-mu) = (-1)^(n-1) pi_n(mu), tau_n(-mu) = (-1)^n tau_n(mu) to halve the work.
 * workspace: NULL, or a buffer reused between calls (sl_mie_workspace_free releases it). */
typedef struct sl_mie_workspace {
  void *buffer;
  size_t bytes;
} sl_mie_workspace;
int sl_mie_s11_mirrored(double x, double m_re, double m_im, const double *mu_half, int n_half,
                        sl_mie_efficiencies *out, double *s11, sl_mie_workspace *ws, sl_error *err);
void sl_mie_workspace_free(sl_mie_workspace *ws);

#ifdef __cplusplus
}
#endif
#endif
