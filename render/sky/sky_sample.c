/* Per-sample atmospheric light, Riley et al. 2004 eqs. 1, 9-15: the C side of
 * sky_sample_shared.h, whose text the GPU pass compiles as GLSL. */
#include "sl_sky_sample.h"

#include <math.h>

#define SL_SKY_REAL double
#define SL_SKY_INFINITY INFINITY
#define sl_sky_isinf(x) isinf(x)
#define sl_sky_abs(x) fabs(x)
#define SL_SKY_IN_ARRAY(name, n) const double name[n]
#define SL_SKY_OUT_ARRAY(name, n) double name[n]
#include "sky_sample_shared.h"
