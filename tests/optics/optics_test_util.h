/* Helpers shared by the optics tests. */
#ifndef OPTICS_TEST_UTIL_H
#define OPTICS_TEST_UTIL_H

#include <math.h>

#include "sl_legendre.h"
#include "sl_optics.h"

/* Independent quadrature of a table's Ams_n over the sphere: 5-point Gauss–Legendre on every
 * grid interval in theta, through the public lookup (not the builder's weights). */
static inline double sphere_integral(const sl_phase_table *t, int n)
{
  static const double x5[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  static const double w5[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                               0.2369268850561891};
  double s = 0.0;
  for (int j = 0; j + 1 < t->n_angles; ++j) {
    const double a = j * t->step_rad, b = (j + 1 == t->n_angles - 1) ? SL_PI : (j + 1) * t->step_rad;
    for (int q = 0; q < 5; ++q) {
      const double th = 0.5 * (a + b) + 0.5 * (b - a) * x5[q];
      s += 0.5 * (b - a) * w5[q] * sin(th) * sl_phase_table_ams(t, n, cos(th));
    }
  }
  return 2.0 * SL_PI * s + t->delta[n < t->max_order ? n : t->max_order];
}

static inline double table_value_deg(const sl_phase_table *t, int n, double deg)
{
  return sl_phase_table_ams(t, n, cos(deg * SL_PI / 180.0));
}

/* Angle (degrees) of the largest value of Ams_n in [lo, hi], scanning grid points. */
static inline double argmax_deg(const sl_phase_table *t, int n, double lo, double hi)
{
  const double step = t->step_rad * 180.0 / SL_PI;
  double best = -1.0, at = NAN;
  for (int j = (int)ceil(lo / step); j * step <= hi + 1e-9 && j < t->n_angles; ++j) {
    const double v = t->ams[(size_t)n * (size_t)t->n_angles + (size_t)j];
    if (v > best) {
      best = v;
      at = j * step;
    }
  }
  return at;
}

static inline double min_deg_value(const sl_phase_table *t, int n, double lo, double hi)
{
  const double step = t->step_rad * 180.0 / SL_PI;
  double best = INFINITY;
  for (int j = (int)ceil(lo / step); j * step <= hi + 1e-9 && j < t->n_angles; ++j)
    best = fmin(best, t->ams[(size_t)n * (size_t)t->n_angles + (size_t)j]);
  return best;
}

#endif
