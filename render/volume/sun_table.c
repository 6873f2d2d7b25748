/* The sunlight that reaches each altitude of the content box through the air, tabulated once per
 * frame (sun_table.h). */
#include "renderer_internal.h"

#include <math.h>

/* The altitudes the box [lo, hi] spans: its bottom and top on the flat ground; on the sphere,
 * from the bottom point nearest the sphere's centre's vertical to the top corner farthest out. */
static void box_altitudes(const sl_atmosphere *atm, const double lo[3], const double hi[3], double *hlo, double *hhi)
{
  if (!atm || !(atm->ground_radius > 0.0)) {
    *hlo = lo[2], *hhi = hi[2];
    return;
  }
  double near[3], far[3];
  for (int a = 0; a < 2; ++a) {
    near[a] = lo[a] > 0.0 ? lo[a] : hi[a] < 0.0 ? hi[a] : 0.0;
    far[a] = fabs(lo[a]) > fabs(hi[a]) ? lo[a] : hi[a];
  }
  near[2] = lo[2], far[2] = hi[2];
  *hlo = sl_sky_altitude(atm, near, NULL);
  *hhi = sl_sky_altitude(atm, far, NULL);
}

void sl__sun_table_init(sun_table *t, const sl_scene *sc, const sl_sky_view *view, const double lo[3],
                        const double hi[3])
{
  t->nwl = sc->atmosphere ? sc->atmosphere->count : SL_CHANNELS;
  t->atm = sc->atmosphere;
  double hlo, hhi;
  box_altitudes(sc->atmosphere, lo, hi, &hlo, &hhi);
  t->z0 = hlo;
  t->dz = (hhi - hlo) / (SUN_TABLE_SIZE - 1);
  for (int i = 0; i < SUN_TABLE_SIZE; ++i)
    for (int c = 0; c < t->nwl; ++c) {
      if (!sc->atmosphere) {
        t->rgb[i][c] = sc->sun_irradiance[c];
        continue;
      }
      const sl_atmosphere *atm = sc->atmosphere;
      const double z = hlo + i * t->dz;
      t->rgb[i][c] = view->night ? 0.0
                                 : atm->sun_irradiance[c] *
                                       exp(-sl_sky_sun_optical_depth(atm->beta_sea_level[c], 1.0 / atm->scale_height,
                                                                     z, view->airmass));
    }
}
