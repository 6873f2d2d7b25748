/* Three-vector arithmetic shared by the renderers and the camera: inline, so the hot loops that use
 * it in render/volume keep it in registers across files. */
#ifndef SL_VEC3_H
#define SL_VEC3_H

#include <math.h>

static inline double sl_dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static inline void sl_cross3(const double a[3], const double b[3], double out[3])
{
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Scales v to unit length; returns 1 (v unchanged) for a zero or non-finite vector. */
static inline int sl_normalize3(double v[3])
{
  const double n = sqrt(sl_dot3(v, v));
  if (!(n > 0.0) || !isfinite(n)) return 1;
  v[0] /= n, v[1] /= n, v[2] /= n;
  return 0;
}

#endif
