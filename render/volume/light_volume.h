/* What the cached light volume's sweep (light_volume_sweep.c) and its eye march
 * (light_volume_march.c) share: where a sample's state lies. */
#ifndef SL_LIGHT_VOLUME_H
#define SL_LIGHT_VOLUME_H

#include "renderer_internal.h"

/* The first float of sample (i, j, k)'s state (ln I per wavelength, then n; stride floats). */
static inline size_t lv_index(const sl_volume *v, int i, int j, int k, int stride)
{
  return sl_volume_index(v, i, j, k) * (size_t)stride;
}

#endif
