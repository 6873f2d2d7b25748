/* Guards for the arguments of acos and sqrt that rounding pushes just outside their domains: a dot
 * product of two unit vectors a few ulps beyond +-1, a difference of two equal quantities a few
 * ulps below 0. Written once in the subset that compiles as C (double) and as GLSL 1.50 (float;
 * the GPU pass embeds this very text, tests/gpu checks both). */
#ifndef SL_GUARDS_H
#define SL_GUARDS_H

#ifndef SL_GLSL
#include <math.h>
#define SL_GUARD static inline double
#define SL_GUARD_REAL double
#else
#define SL_GUARD float
#define SL_GUARD_REAL float
#endif

/* A cosine into [-1, 1]; NaN stays NaN (a broken direction should show, not read as 0 degrees). */
SL_GUARD sl_clamp_cosine(SL_GUARD_REAL c) { return c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c); }

/* The square root of a quantity that is >= 0 but for rounding (1 - mu^2, a variance): 0 below 0. */
SL_GUARD sl_safe_sqrt(SL_GUARD_REAL x) { return sqrt(x > 0.0 ? x : 0.0); }

#endif
