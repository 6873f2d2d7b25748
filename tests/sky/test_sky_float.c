/* The per-sample sky compiled in single precision, as a GLSL port would run it: sky_sample.c with
 * double -> float and float math, against the double-precision quadrature of eq. 8. Measures how
 * much the stable forms lose in float (docs/SKY.md, Integration: GPU). Not linked with sl_sky. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "quadrature.h"
#include "sl_testing.h"

/* A float build of the per-sample functions under other names. */
#define double float
#define exp expf
#define fabs fabsf
#define sl_sky_exprel f_exprel
#define sl_sky_rayleigh_phase f_rayleigh_phase
#define sl_sky_path_length_factor f_path_length_factor
#define sl_sky_optical_depth f_optical_depth
#define sl_sky_sun_optical_depth f_sun_optical_depth
#define sl_sky_segment_length f_segment_length
#define sl_sky_ground_distance f_ground_distance
#define sqrt sqrtf
#define sl_sky_inscatter f_inscatter
#include "sky_sample.c"
#undef double
#undef exp
#undef fabs
#undef sqrt

static uint64_t state = 0x243F6A8885A308D3ull;
static double uniform(void)
{
  state ^= state >> 12;
  state ^= state << 25;
  state ^= state >> 27;
  return (double)((state * 2685821657736338717ull) >> 11) * (1.0 / 9007199254740992.0);
}

int main(void)
{
  const double kPi = 3.14159265358979323846, gamma = 1.0 / 8000.0;
  const int n = 3000;
  double worst = 0.0;
  int nonfinite = 0;
  for (int i = 0; i < n; ++i) {
    /* Rayleigh at 380-720 nm: 3.8e-6 .. 5.3e-5 m^-1 */
    double beta = 3.8e-6 * pow(5.3e-5 / 3.8e-6, uniform());
    double z = uniform() < 0.2 ? 0.0 : 2e4 * uniform();
    double sun_el = 0.5 + 89.5 * uniform();
    double l = sin(sun_el * kPi / 180.0);
    double r = uniform();
    double mu = r < 0.05 ? 0.0 : r < 0.1 ? l : 2.0 * uniform() - 1.0;
    double K = uniform() < 0.3 ? INFINITY : 10.0 * pow(1e4, uniform());
    double cos_vs = 2.0 * uniform() - 1.0;
    float Kf = f_segment_length((float)z, (float)mu, (float)K, 0.0f);
    float got = f_inscatter((float)beta, (float)gamma, (float)z, (float)mu, Kf, (float)(1.0 / l), (float)cos_vs);
    ref_sky s = {beta, gamma, z, mu, 1.0 / l, 3.0 / (16.0 * kPi) * (1.0 + cos_vs * cos_vs)};
    double want = ref_sky_radiance(&s, K, 1e-10);
    if (!isfinite(got)) ++nonfinite;
    double rel = fabs(got - want) / want;
    if (want > 1e-30 && rel > worst) worst = rel;
  }
  printf("float per-sample sky vs double quadrature: %d configurations, worst relative error %.3g\n", n, worst);
  CHECK(nonfinite == 0);
  /* float has 6e-8 resolution; the stable forms keep the error to a few tens of ulp */
  CHECK_MSG(worst < 1e-5, "float sky within 1e-5 of the quadrature");
  return sl_test_finish("test_sky_float");
}
