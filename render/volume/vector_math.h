/* glibc's libmvec holds vector versions of exp and log (and expm1 since glibc 2.35) for the x86-64 vector function ABI (SSE2
 * to AVX-512). Declaring the scalar functions `omp declare simd` lets GCC turn the calls in a
 * `#pragma omp simd` loop into those versions, as <math.h> itself does only under -ffast-math
 * (which would also drop the renderer's NaN checks). libmvec keeps double precision (within 4
 * ulp); elsewhere the loops stay scalar calls. Internal to render/volume. */
#ifndef SL_VECTOR_MATH_H
#define SL_VECTOR_MATH_H

#include <math.h>

#if defined(SL_HAVE_LIBMVEC) && defined(__GNUC__) && defined(__x86_64__)
#pragma omp declare simd notinbranch
double exp(double);
#pragma omp declare simd notinbranch
double log(double);
#endif
#if defined(SL_HAVE_LIBMVEC_EXPM1) && defined(__GNUC__) && defined(__x86_64__)
#pragma omp declare simd notinbranch
double expm1(double);
#endif

#endif
