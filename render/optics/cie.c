#include "sl_cie.h"

#include <math.h>

static double lobe(double l, double mean, double sigma_below, double sigma_above)
{
  const double s = l < mean ? sigma_below : sigma_above;
  const double t = (l - mean) / s;
  return exp(-0.5 * t * t);
}

void sl_cie_xyz_bar(double l, double xyz[3])
{
  /* Wyman, Sloan & Shirley 2013, "Simple analytic approximations to the CIE XYZ color matching
   * functions", JCGT 2(2), 1-11: the multi-lobe piecewise-Gaussian fit to the CIE 1931
   * 2-degree observer (their eq. 2 and table 1). Its error against the tabulated functions is
   * below the variation between CIE observers. */
  xyz[0] = 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) - 0.065 * lobe(l, 501.1, 20.4, 26.2);
  xyz[1] = 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1);
  xyz[2] = 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8);
}

/* XYZ -> linear sRGB, IEC 61966-2-1:1999 (the inverse of the primaries' matrix, D65 white). */
static const double XYZ_TO_SRGB[3][3] = {
    {3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};

int sl_cie_srgb_weights(const double *nm, int n, int white_balance, double *w, sl_error *err)
{
  if (n < 2) return sl_fail(err, SL_ERR_ARG, "cie: need at least two wavelengths, got %d", n);
  for (int i = 1; i < n; ++i)
    if (!(nm[i] > nm[i - 1])) return sl_fail(err, SL_ERR_ARG, "cie: wavelengths must ascend");
  double y_sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double dl = 0.5 * ((i + 1 < n ? nm[i + 1] : nm[i]) - (i > 0 ? nm[i - 1] : nm[i]));
    double xyz[3];
    sl_cie_xyz_bar(nm[i], xyz);
    y_sum += dl * xyz[1];
    for (int c = 0; c < 3; ++c)
      w[c * n + i] = dl * (XYZ_TO_SRGB[c][0] * xyz[0] + XYZ_TO_SRGB[c][1] * xyz[1] + XYZ_TO_SRGB[c][2] * xyz[2]);
  }
  for (int k = 0; k < 3 * n; ++k) w[k] /= y_sum;
  if (white_balance) {
    for (int c = 0; c < 3; ++c) {
      double flat = 0.0;
      for (int i = 0; i < n; ++i) flat += w[c * n + i];
      if (!(flat > 0.0)) return sl_fail(err, SL_ERR_ARG, "cie: wavelengths do not span channel %d", c);
      for (int i = 0; i < n; ++i) w[c * n + i] /= flat;
    }
  }
  return SL_OK;
}

