/* Inside render/apsf: the 2D PSF as a function of the pixel offset, shared by the kernel
 * builders (kernel.c) and the convolution (glow.c), which fills FFT buffers from it directly. */
#ifndef SL_GLOW_INTERNAL_H
#define SL_GLOW_INTERNAL_H

#include <math.h>

#include "sl_glow.h"

/* The 2D PSF as a function of the pixel offset: 8 x 8 sub-samples within 6 pixels of the
 * source (where the profile changes within a pixel), a radial table uniform in sqrt(r) beyond
 * (the kernel of an HD frame has 8 M taps per layer: no atan per tap). */
enum { SL_GLOW_NEAR = 6, SL_GLOW_SUB = 8, SL_GLOW_NR = 16384 };
typedef struct sl_glow_model {
  double near[SL_GLOW_NEAR][SL_GLOW_NEAR]; /* |dx|, |dy| < 6, Dirac included */
  double radial[SL_GLOW_NR];
  double inv_r_table, scale;
  double T, blend, direct, series_scale;
  int terms;
} sl_glow_model;

int sl_glow_model_build(sl_glow_model *km, const sl_apsf_medium *m, double T, double focal_px, int rx, int ry,
                        sl_glow_norm norm, double tolerance, sl_error *err);

static inline double sl_glow_model_value(const sl_glow_model *km, int dx, int dy)
{
  dx = dx < 0 ? -dx : dx;
  dy = dy < 0 ? -dy : dy;
  if (dx < SL_GLOW_NEAR && dy < SL_GLOW_NEAR && dx * dx + dy * dy < SL_GLOW_NEAR * SL_GLOW_NEAR) return km->scale * km->near[dy][dx];
  const double t = sqrt(sqrt((double)dx * dx + (double)dy * dy) * km->inv_r_table) * (SL_GLOW_NR - 1);
  int i = (int)t;
  if (i > SL_GLOW_NR - 2) i = SL_GLOW_NR - 2;
  return km->scale * (km->radial[i] + (t - i) * (km->radial[i + 1] - km->radial[i]));
}

#endif
