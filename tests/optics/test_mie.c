/* Mie against published values: Bohren & Huffman's BHMIE example and Wiscombe's MIEV0 test
 * cases (Wiscombe 1979, NCAR/TN-140+STR, tables reproduced in MVTstNew.f). Wiscombe writes
 * m = n - ik; we pass +k. S11 = (|S1|^2+|S2|^2)/2 is independent of the sign convention. */
#include "sl_mie.h"
#include "sl_testing.h"

#include <math.h>

#define SL_PI 3.14159265358979323846

typedef struct ref_case {
  double m_re, m_im, x;
  double qext, qsca, gqsc; /* gqsc = g * Qsca as tabulated by Wiscombe */
} ref_case;

/* Wiscombe MIEV0 test cases 5-19 (7 significant digits). */
static const ref_case WISCOMBE[] = {
    {0.75, 0.0, 0.099, 7.417859e-06, 7.417859e-06, 1.074279e-08},
    {0.75, 0.0, 0.101, 8.033542e-06, 8.033542e-06, 1.211000e-08},
    {0.75, 0.0, 10.0, 2.232265, 2.232265, 2.001164},
    {0.75, 0.0, 1000.0, 1.997908, 1.997908, 1.688121},
    {1.33, 1e-5, 1.0, 9.395198e-02, 9.392330e-02, 1.733048e-02},
    {1.33, 1e-5, 100.0, 2.101321, 2.096594, 1.821854},
    {1.33, 1e-5, 10000.0, 2.004089, 1.723857, 1.564987},
    {1.5, 1.0, 0.055, 1.014910e-01, 1.131687e-05, 5.558541e-09},
    {1.5, 1.0, 0.056, 1.033467e-01, 1.216311e-05, 6.193255e-09},
    {1.5, 1.0, 1.0, 2.336321, 6.634538e-01, 1.274736e-01},
    {1.5, 1.0, 100.0, 2.097502, 1.283697, 1.091466},
    {1.5, 1.0, 10000.0, 2.004368, 1.236574, 1.046525},
    {10.0, 10.0, 1.0, 2.532993, 2.049405, -2.267961e-01},
    {10.0, 10.0, 100.0, 2.071124, 1.836785, 1.021648},
    {10.0, 10.0, 10000.0, 2.005914, 1.795393, 9.842238e-01},
};

/* S1, S2 (re, im) at 0, 30, 60, 90, 120, 150, 180 degrees from the same tables. */
typedef struct ref_amplitudes {
  double m_re, m_im, x;
  double s[7][4];
  int first, last; /* angles checked */
} ref_amplitudes;

static const ref_amplitudes AMPLITUDES[] = {
    {0.75, 0.0, 10.0,
     {{5.580662e+01, -9.758097e+00, 5.580662e+01, -9.758097e+00},
      {-7.672879e+00, 1.087317e+01, -1.092923e+01, 9.629667e+00},
      {3.587894e+00, -1.756177e+00, 3.427411e+00, 8.082691e-02},
      {-1.785905e+00, -5.232828e-02, -5.148748e-01, -7.027288e-01},
      {1.537971e+00, -8.329374e-02, -6.908338e-01, 2.152693e-01},
      {-4.140427e-01, 1.876851e-01, 5.247557e-01, -1.923391e-01},
      {-1.078568e+00, -3.608807e-02, 1.078568e+00, 3.608807e-02}},
     0, 6},
    {0.75, 0.0, 1000.0,
     {{4.994770e+05, -1.336502e+04, 4.994770e+05, -1.336502e+04},
      {-3.999296e+02, -3.316361e+02, -3.946018e+02, -1.147791e+02},
      {-5.209852e+02, -5.776614e+02, -1.970767e+02, -6.937470e+02},
      {-1.600887e+02, 1.348013e+02, -4.152365e+01, 1.143000e+02},
      {8.431720e+01, -1.209493e+02, -4.261732e+01, 5.535055e+01},
      {-7.556092e+01, -8.134810e+01, 4.218303e+01, 9.100831e+01},
      {1.705778e+01, 4.842510e+02, -1.705778e+01, -4.842510e+02}},
     0, 6},
    {1.33, 1e-5, 100.0,
     {{5.253302e+03, -1.243188e+02, 5.253302e+03, -1.243188e+02},
      {-5.534573e+01, -2.971881e+01, -8.467204e+01, -1.999470e+01},
      {1.710488e+01, -1.520096e+01, 3.310764e+01, -2.709787e+00},
      {-3.655758e+00, 8.769860e+00, -6.550512e+00, -4.675370e+00},
      {2.414318e+00, 5.380874e-01, 6.039011e+00, -1.169971e+01},
      {-1.222996e+00, 3.283917e+01, -9.653812e+00, 1.474455e+01},
      {-5.659205e+01, 4.650974e+01, 5.659205e+01, -4.650974e+01}},
     0, 6},
    {1.5, 1.0, 1.0,
     {{5.840802e-01, 1.905153e-01, 5.840802e-01, 1.905153e-01},
      {5.657020e-01, 1.871997e-01, 5.001610e-01, 1.456112e-01},
      {5.175251e-01, 1.784426e-01, 2.879639e-01, 4.105398e-02},
      {4.563396e-01, 1.671665e-01, 3.622847e-02, -6.182646e-02},
      {4.002117e-01, 1.566427e-01, -1.748750e-01, -1.229586e-01},
      {3.621572e-01, 1.493910e-01, -3.056823e-01, -1.438460e-01},
      {3.488438e-01, 1.468286e-01, -3.488438e-01, -1.468286e-01}},
     0, 6},
    /* x = 10 000, absorbing: the forward and side angles (Wiscombe's 180-degree value was
     * computed with fewer terms than later codes use, so it is left out). */
    {1.5, 1.0, 10000.0,
     {{5.010919e+07, -1.753404e+05, 5.010919e+07, -1.753404e+05},
      {-3.690394e+03, -1.573897e+03, -9.333175e+02, -1.839736e+03},
      {2.391551e+02, 3.247786e+03, -1.202951e+03, -1.899647e+02},
      {-2.607463e+03, 7.414859e+02, 1.013073e+03, -1.064666e+03},
      {-6.183154e+02, 2.264970e+03, 1.334826e+02, -1.800859e+03},
      {-3.368019e+02, 2.115750e+03, 2.293862e+02, -1.996754e+03},
      {0, 0, 0, 0}},
     0, 5},
};

static double s11_of(const double s[4])
{
  return 0.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + s[3] * s[3]);
}

int main(void)
{
  sl_error err = {0};
  sl_mie_efficiencies e;

  /* Bohren & Huffman 1983, appendix A, BHMIE's example: radius 0.525 um, wavelength 0.6328 um,
   * m = 1.55 (non-absorbing): Qext = Qsca = 3.10543, Qback = 2.92534, g = 0.63314 (5 decimals). */
  const double x_bh = 2.0 * SL_PI * 0.525 / 0.6328;
  CHECK(sl_mie(x_bh, 1.55, 0.0, NULL, 0, &e, NULL, NULL, NULL, &err) == SL_OK);
  CHECK_CLOSE(e.qext, 3.10543, 0.0, 6e-6);
  CHECK_CLOSE(e.qsca, 3.10543, 0.0, 6e-6);
  CHECK_CLOSE(e.qback, 2.92534, 0.0, 6e-6);
  CHECK_CLOSE(e.g, 0.63314, 0.0, 6e-6);

  for (size_t i = 0; i < sizeof WISCOMBE / sizeof WISCOMBE[0]; ++i) {
    const ref_case *r = &WISCOMBE[i];
    CHECK(sl_mie(r->x, r->m_re, r->m_im, NULL, 0, &e, NULL, NULL, NULL, &err) == SL_OK);
    /* 7 significant digits tabulated: 1e-6 relative covers the rounding of the last one. */
    CHECK_CLOSE(e.qext, r->qext, 1e-6, 0.0);
    CHECK_CLOSE(e.qsca, r->qsca, 1e-6, 0.0);
    CHECK_CLOSE(e.g * e.qsca, r->gqsc, 2e-6, 0.0); /* small-x entries carry 6-7 digits */
  }

  const double deg[7] = {0, 30, 60, 90, 120, 150, 180};
  double mu[7];
  for (int j = 0; j < 7; ++j) mu[j] = cos(deg[j] * SL_PI / 180.0);
  mu[3] = 0.0;
  for (size_t i = 0; i < sizeof AMPLITUDES / sizeof AMPLITUDES[0]; ++i) {
    const ref_amplitudes *r = &AMPLITUDES[i];
    double s11[7];
    CHECK(sl_mie(r->x, r->m_re, r->m_im, mu, 7, &e, NULL, NULL, s11, &err) == SL_OK);
    for (int j = r->first; j <= r->last; ++j) CHECK_CLOSE(s11[j], s11_of(r->s[j]), 1e-5, 0.0);
  }

  /* The mirrored evaluation agrees with the direct one. */
  {
    const double half[4] = {1.0, cos(0.3), cos(1.1), 0.0};
    double s11m[8], full[8], fm[8];
    for (int j = 0; j < 4; ++j) {
      fm[j] = half[j];
      fm[7 - j] = -half[j];
    }
    CHECK(sl_mie_s11_mirrored(150.0, 1.333, 1e-8, half, 4, &e, s11m, NULL, &err) == SL_OK);
    CHECK(sl_mie(150.0, 1.333, 1e-8, fm, 8, &e, NULL, NULL, full, &err) == SL_OK);
    for (int j = 0; j < 8; ++j) CHECK_CLOSE(s11m[j], full[j], 1e-10, 0.0);
  }

  /* Bad arguments are reported, not trusted. */
  sl_error_clear(&err);
  CHECK(sl_mie(-1.0, 1.33, 0.0, NULL, 0, &e, NULL, NULL, NULL, &err) == SL_ERR_ARG);
  sl_error_clear(&err);
  CHECK(sl_mie(1.0, 1.33, -0.1, NULL, 0, &e, NULL, NULL, NULL, &err) == SL_ERR_ARG);
  return sl_test_finish("test_mie");
}
