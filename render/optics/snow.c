/* Snow aggregates: a smooth, featureless phase function.
 *
 * Aggregates of many crystals lose the halos of single prisms: Macke, Mueller & Raschke 1996
 * (J. Atmos. Sci. 53, 2813, "Single scattering properties of atmospheric ice crystals")
 * computed a featureless phase function with asymmetry parameter g ~ 0.75 for randomly
 * oriented fractal (Koch-type) polycrystals at visible wavelengths; Kokhanovsky & Zege 2004
 * (Appl. Opt. 43, 1589) adopt the same fractal model for snow. We use a Henyey–Greenstein
 * function with g = 0.75: it matches that asymmetry and smoothness, but not the detail of
 * the side- and back-scattering of the fractal model (its back-scatter is lower). Wavelength
 * independent, as geometric optics of non-absorbing ice is. Albedo 1 (ice absorbs < 1e-4 over
 * a millimetre in the visible); cross-section from Riley et al. 2004, Table 2. */
#include <math.h>

#include "optics_internal.h"
#include "sl_legendre.h"

#define SNOW_ASYMMETRY 0.75

int optics_snow(double wavelength_nm, const optics_grid *g, optics_raw_phase *out, sl_error *err)
{
  (void)wavelength_nm;
  (void)err;
  for (int j = 0; j < g->n_angles; ++j) out->p[j] = sl_hg_phase(SNOW_ASYMMETRY, g->mu[j]);
  out->sigma_ext = sl_particle_properties(SL_SNOW)->sigma_ext_m2;
  out->albedo = 1.0;
  out->asymmetry = SNOW_ASYMMETRY;
  return SL_OK;
}
