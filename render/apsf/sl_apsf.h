/* The atmospheric point spread function of Narasimhan, Ramamoorthi and Nayar ("Analytic
 * rendering of multiple scattering in participating media"): the light field of an isotropic
 * point source in an infinite homogeneous medium as a Legendre series in mu = cos(theta), theta
 * measured from the outward radial direction, at optical distance T = sigma R from the source.
 *
 * Units of the output (docs/APSF.md, "Normalisation"). The series S(T, mu) is the paper's
 * eq. 27 with I0 = 1 and c_m = 1, a pure number. The code reads it as a radiance through
 *     L(R, mu) = I0 sigma^2 S(T, mu) / (4 pi),                       (c_m = sigma^2 / (4 pi))
 * which makes the model's fluence (L integrated over the sphere of directions) equal to
 * e^{-3 (1 - W0) T} times the vacuum fluence I0 / R^2 of the bare source: for W0 = 1 a camera
 * summing radiance over solid angle sees the source's energy, no more and no less. The
 * per-steradian weight a camera sees, relative to the vacuum image of the source, is then
 * T^2 S(T, mu) / (4 pi): sl_apsf_fluence_weight.
 *
 * The series converges only for T > 1. Below SL_APSF_BLEND_LO the code uses single scattering
 * plus the attenuated direct beam; between SL_APSF_BLEND_LO and SL_APSF_BLEND_HI it blends
 * the two with a smoothstep in T (sl_apsf_profile). */
#ifndef SL_APSF_H
#define SL_APSF_H

#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SL_APSF_BLEND_LO 1.05
#define SL_APSF_BLEND_HI 1.5
#define SL_APSF_MAX_TERMS 200000

/* The medium: single-scattering albedo W0 and the phase function, either Henyey–Greenstein
 * with parameter q (chi == NULL) or the normalised Legendre moments chi_l of render/optics
 * (chi_0 = 1, chi_1 = g; moments beyond n_chi are taken as 0). The paper's W_k are
 * W0 (2k+1) chi_k (its eq. 12 for HG, chi_k = q^k). */
typedef struct sl_apsf_medium {
  double albedo;
  double q;
  const double *chi;
  int n_chi;
} sl_apsf_medium;

/* chi_k of the medium's phase function (q^k for HG). */
double sl_apsf_chi(const sl_apsf_medium *m, int k);
/* Phase function normalised to mean 1 over the sphere (the paper's P, eq. 11), no albedo. */
double sl_apsf_phase(const sl_apsf_medium *m, double cos_scatter);

/* beta_m and alpha_m of eq. 25 (m >= 1) and ln g_m(T) of eq. 24 with I0 = 1 (T > 0). */
double sl_apsf_beta(const sl_apsf_medium *m, int order);
double sl_apsf_alpha(int order);
double sl_apsf_log_g(const sl_apsf_medium *m, int order, double T);

/* Number of Legendre terms (highest order + 1) after which the rest of eq. 27 is provably
 * below tolerance * S(T, 1) for every mu (|L_m| <= 1 and a geometric bound on g_m; see
 * docs/APSF.md). T must exceed 1. Returns SL_APSF_MAX_TERMS + 1 when the bound needs more. */
int sl_apsf_terms_needed(const sl_apsf_medium *m, double T, double tolerance);

/* The series for one T, planned once and evaluated at many mu. */
typedef struct sl_apsf_series {
  double T, tolerance;
  int terms;        /* Legendre terms kept: L_0 .. L_{terms-1} */
  double log_scale; /* S = exp(log_scale) * shape: the largest coefficient g_l + g_{l+1} */
  double *chi;      /* the coefficients over exp(log_scale), in sl_legendre_series's convention */
} sl_apsf_series;

/* terms <= 0: chosen from tolerance (> 0). T must exceed 1. */
int sl_apsf_series_init(sl_apsf_series *s, const sl_apsf_medium *m, double T, double tolerance, int terms,
                        sl_error *err);
/* S(T, mu), eq. 27 (Clenshaw); underflows to 0 where S < 1e-308 (T in the hundreds with
 * absorption), where the shape below still holds. */
double sl_apsf_series_eval(const sl_apsf_series *s, double mu);
/* S(T, mu) / exp(log_scale): the same function scaled to order 1, for any T. */
double sl_apsf_series_shape(const sl_apsf_series *s, double mu);
void sl_apsf_series_free(sl_apsf_series *s);
/* Fraction of the series' fluence in the back hemisphere mu <= 0 (the paper's Fig. 3 shows the
 * absolute energy there: this times 4 pi g_1). Tends to 1/4 as T grows (eq. 33: 1 + mu). */
double sl_apsf_series_back_fraction(const sl_apsf_series *s);

/* Single scattering of the point source seen from distance T, in S's units (the same radiance
 * normalisation), along a view ray at angle gamma from the source: W0 int P e^{-(tau+t)}/tau^2 dt.
 * +inf at gamma = 0. The unscattered beam (a Dirac of weight e^{-T} in the fluence weight) is
 * not included. */
double sl_apsf_single_scatter(const sl_apsf_medium *m, double T, double gamma);

/* T^2 S / (4 pi): radiance relative to the vacuum fluence of the source, per steradian. */
static inline double sl_apsf_fluence_weight(double T, double S) { return T * T * S / (4.0 * 3.14159265358979323846); }

/* The angular profile a camera sees at optical distance T in every regime, tabulated in
 * gamma (the angle from the source direction; mu = cos gamma for a camera inside the medium):
 *   weight(gamma) = T^2 S_eff(T, gamma) / (4 pi),   plus a Dirac of weight `direct` at gamma = 0,
 *   S_eff = w s S_series + (1 - w) S_single,   direct = e^{-T},
 *   w = smoothstep((T - SL_APSF_BLEND_LO) / (SL_APSF_BLEND_HI - SL_APSF_BLEND_LO)),
 *   s = max(0, 1 - e^{-T} / e^{-3 (1 - W0) T}).
 * The unscattered beam is explicit in every regime: the series has no Dirac (its forward peak
 * is smooth), so on a pixel grid it would spread the sharp e^{-T} of the source into a blur and
 * darken the source below its attenuated surroundings. s takes that share out of the series,
 * so the total fluence stays the series' e^{-3 (1 - W0) T} (docs/APSF.md, "Direct beam"). */
typedef struct sl_apsf_profile {
  double T, blend, direct;
  double series_scale; /* s above */
  int n;            /* samples over [0, gamma_max], uniform in sqrt(gamma) to resolve the peak */
  double gamma_max;
  double *weight;   /* n samples of the fluence weight (1/sr), the Dirac excluded */
  int terms;        /* series terms used (0 below the blend) */
} sl_apsf_profile;

int sl_apsf_profile_build(sl_apsf_profile *p, const sl_apsf_medium *m, double T, double tolerance,
                          double gamma_max, int n_samples, sl_error *err);
/* Fluence weight at gamma (linear interpolation; gamma > gamma_max gives 0; gamma = 0 in the
 * single-scattering regime gives the first sample's value, see docs/APSF.md). */
double sl_apsf_profile_eval(const sl_apsf_profile *p, double gamma);
void sl_apsf_profile_free(sl_apsf_profile *p);

/* Eq. 28: the cosine mu at which a camera at distance D from the centre of a spherical medium of
 * radius R (D > R, source at the centre, no refraction) sees the field along a ray at angle gamma
 * from the centre. Returns -2 when the ray misses the sphere. */
double sl_apsf_mu_outside(double D, double R, double gamma);

#ifdef __cplusplus
}
#endif
#endif
