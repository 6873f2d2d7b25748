/* The glow medium of a haze: render/optics' rural aerosol per channel (sl_glow.h). */
#include <stddef.h>

#include "sl_aerosol.h"
#include "sl_glow.h"

int sl_glow_haze_media(const double wavelengths_nm[3], sl_apsf_medium media[3], double sigma_scale[3], sl_error *err)
{
  sl_aerosol_optics ref;
  /* Visibility is defined at 550 nm (Koschmieder, sl_aerosol.h): sigma is the extinction there. */
  if (sl_aerosol_optics_compute(sl_aerosol_rural(), 550.0, 0, &ref, err)) return SL_ERR_ARG;
  for (int c = 0; c < 3; ++c) {
    sl_aerosol_optics o;
    if (sl_aerosol_optics_compute(sl_aerosol_rural(), wavelengths_nm[c], 0, &o, err)) return SL_ERR_ARG;
    media[c] = (sl_apsf_medium){o.albedo, o.asymmetry, NULL, 0}; /* Henyey-Greenstein with q = g */
    sigma_scale[c] = o.extinction_m2 / ref.extinction_m2;
  }
  return SL_OK;
}
