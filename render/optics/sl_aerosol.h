/* Haze: a stated aerosol model through the project's Mie code (sl_mie), averaged over its size
 * distribution, and visibility turned into extinction by Koschmieder's law.
 *
 * The model (sl_aerosol_rural): Shettle & Fenn's rural aerosol, "Models for the aerosols of the
 * lower atmosphere and the effects of humidity variations on their optical properties",
 * AFGL-TR-79-0214 (1979), at 0 % relative humidity: a mixture of 70 % water-soluble and 30 %
 * dust-like substance in two lognormal modes,
 *     n(r) = sum_i N_i / (ln(10) r sigma_i sqrt(2 pi)) exp(-(log10 r - log10 r_i)^2 / (2 sigma_i^2)),
 *     r_1 = 0.027 um, sigma_1 = 0.35, N_1 / N = 0.999875;  r_2 = 0.43 um, sigma_2 = 0.40, N_2 / N = 1.25e-4,
 * refractive index 1.53 - 0.0066 i near 550 nm, taken constant over 440-650 nm (its real part
 * varies by < 0.5 % and its imaginary part by tens of per cent over the visible in the report's
 * tables; the albedo is what the imaginary part moves). Humidity growth is not modelled.
 *
 * Digits checked (docs/APSF.md, "Haze"): the composition (0.7 / 0.3), both mode radii, both
 * widths and both number fractions agree with quotations of the report's Tables 1-2 at 0 % RH:
 * the table "Modele d'aerosol" of "Initiation a la science des aerosols" (studylibfr.com/doc/
 * 624041, "adapte de Shettle and Fenn (1979) pour une humidite relative de 0 %": 0.999875,
 * 0.027 um, 0.35; 0.000125, 0.43 um, 0.4) and, except the radii, Eradiate's Shettle & Fenn
 * module (eradiate/eradiate, SIZE_DISTRIBUTION_PARAMS, COMPOSITION). The refractive index was
 * not found in a quotable source in reach: it is the report's value as first transcribed,
 * unverified. */
#ifndef SL_AEROSOL_H
#define SL_AEROSOL_H

#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SL_AEROSOL_MAX_MODES 4

typedef struct sl_lognormal_mode {
  double median_radius_m; /* r_i of the number distribution */
  double sigma_log10;     /* standard deviation of log10 r */
  double number_fraction; /* N_i / N */
} sl_lognormal_mode;

typedef struct sl_aerosol_model {
  const char *name, *source;
  int n_modes;
  sl_lognormal_mode modes[SL_AEROSOL_MAX_MODES];
  double m_re, m_im; /* relative to air, m_im >= 0 absorbs (sl_mie's sign) */
} sl_aerosol_model;

/* Shettle & Fenn 1979, rural, 0 % RH (above). */
const sl_aerosol_model *sl_aerosol_rural(void);

/* Per-particle optics averaged over the number distribution at one wavelength. */
typedef struct sl_aerosol_optics {
  double wavelength_nm;
  double extinction_m2; /* <C_ext>: mean extinction cross-section per particle */
  double scattering_m2; /* <C_sca> */
  double albedo;        /* W0 = <C_sca> / <C_ext> */
  double asymmetry;     /* g = <C_sca g> / <C_sca>: the q of the APSF's Henyey-Greenstein phase */
} sl_aerosol_optics;

/* Midpoint quadrature in each mode's ln r over +-7 standard deviations with nodes_per_mode nodes
 * (0: 400). Returns SL_OK or SL_ERR_ARG. */
int sl_aerosol_optics_compute(const sl_aerosol_model *m, double wavelength_nm, int nodes_per_mode,
                              sl_aerosol_optics *out, sl_error *err);

/* Koschmieder's law: extinction (1/m) of a haze or fog with meteorological visibility V (m), the
 * distance at which a black object's contrast against the horizon sky falls to the threshold
 * 0.02: sigma = -ln(0.02) / V = 3.912 / V (at 550 nm, where the eye is most sensitive). */
#define SL_KOSCHMIEDER_CONTRAST 0.02
double sl_koschmieder_extinction(double visibility_m);

#ifdef __cplusplus
}
#endif
#endif
