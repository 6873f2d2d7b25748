/* A pixel's resolve (Riley et al. 2004, sec. 5): its accumulated volume light through the air in
 * front of it, in linear sRGB, with its coverage and depth. Inlined into the passes, whose
 * specialised copies give the wavelength count as a constant (a call per pixel with the count
 * read at run time was 7 ms of a 90 ms light-volume march at 512^2). */
#ifndef SL_RESOLVE_H
#define SL_RESOLVE_H

#include "renderer_internal.h"
#include "sl_cie.h"
#include "sl_sample_physics.h"

/* Writes pixel q from its accumulator a (radiance per wavelength, transparency, depth
 * numerator): the aerial perspective in front of t_mid along d (view NULL: no air), the
 * spectral-to-RGB conversion. nwl is r->model.nwl. */
static inline __attribute__((always_inline)) void sl__resolve_pixel(const sl_renderer *r, const int nwl,
                                                                    const sl_sky_view *view, const double d[3],
                                                                    double t_mid, const float *a, sl_image *img,
                                                                    size_t q)
{
  const float transparency = a[nwl];
  double front[SL_MAX_WAVELENGTHS], front_t[SL_MAX_WAVELENGTHS], spectrum[SL_MAX_WAVELENGTHS];
  for (int c = 0; c < nwl; ++c) front[c] = 0.0, front_t[c] = 1.0;
  if (view && transparency < 1.0f) sl_sky_view_segment(view, d, 0.0, t_mid, front, front_t);
  for (int c = 0; c < nwl; ++c) spectrum[c] = sl_resolve_layer(a[c], 1.0 - transparency, front[c], front_t[c]);
  double rgb[3];
  sl_cie_apply(r->to_rgb, nwl, spectrum, rgb);
  for (int c = 0; c < SL_CHANNELS; ++c) img->rgba[4 * q + c] = (float)rgb[c];
  img->rgba[4 * q + 3] = 1.0f - transparency;
  img->transparency[q] = transparency;
  const double coverage = 1.0 - transparency;
  img->depth[q] = (float)sl_resolve_depth(a[nwl + 1], coverage, INFINITY);
}

#endif
