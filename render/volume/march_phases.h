/* Eq. 26's angular term for a batch of the light-volume march's steps along one ray
 * (light_volume_march.c), whose scattering angle is the ray's. */
#ifndef SL_MARCH_PHASES_H
#define SL_MARCH_PHASES_H

#include <math.h>

#include "lighting.h"
#include "sl_sample_physics.h"

#define SL__MARCH_PHASE_BATCH 32 /* the march's batch of steps (MARCH_BATCH) */

/* Eq. 26's angular term of a batch of a ray's steps per wavelength at the mean expected
 * scattering count n of each step's two ends (sl_eye_phase_at). The angle is the ray's, so each
 * table's values at it (sl_ams_at_angle) are read once a batch for the orders its steps span, into
 * rows; where all steps share their orders (two thirds of them in the cumulonimbus) the rows are
 * numbers the steps' loop takes without a gather. A batch whose orders span
 * SL__MARCH_ORDER_ROWS - 1 or more (a ray into a thick core's far side) reads the tables per step.
 * Bitwise sl_eye_phase_at's values (tests/volume/test_march_phases.c). */
#define SL__MARCH_ORDER_ROWS 16
static inline __attribute__((always_inline)) void sl__march_phases(const sl_light_model *m, const int mode,
                                                                   const int nf, const int nwl, const int live,
                                                                   float (*restrict fields)[SL_MAX_FIELDS],
                                                                   const double *restrict n, const int angle_index,
                                                                   const double angle_weight,
                                                                   double (*restrict phase)[SL__MARCH_PHASE_BATCH])
{
  /* Orders past every table's last read its last: they share a row. */
  int top = 0, k_lo = 1 << 30, k_hi = -1;
  for (int j = 0; j < nf; ++j)
    for (int c = 0; c < nwl; ++c) top = m->max_order[j][c] > top ? m->max_order[j][c] : top;
  for (int s = 0; s < live; ++s) {
    const double order = n[s] + 1.0;
    const int k = !(order >= 0.0) ? -1 : order < top ? (int)floor(order) : top; /* -1 (NaN too): per step */
    k_lo = k < k_lo ? k : k_lo;
    k_hi = k > k_hi ? k : k_hi;
  }
  if (mode == SL_LIGHTING_LOW_ALBEDO || k_lo < 0 || k_hi - k_lo >= SL__MARCH_ORDER_ROWS - 1) {
#pragma GCC ivdep
    for (int s = 0; s < live; ++s) {
      double ph[SL_MAX_WAVELENGTHS];
      sl_eye_phase_at(m, mode, nf, nwl, fields[s], n[s], angle_index, angle_weight, ph);
      for (int c = 0; c < nwl; ++c) phase[c][s] = ph[c];
    }
    return;
  }
  /* rows[j][c][i]: the table at order k_lo + i, i up to k_hi + 1 - k_lo (a step's order above its own). */
  double rows[SL_MAX_FIELDS][SL_MAX_WAVELENGTHS][SL__MARCH_ORDER_ROWS];
  for (int j = 0; j < nf; ++j)
    for (int c = 0; c < nwl; ++c)
      for (int i = 0; i <= k_hi + 1 - k_lo; ++i)
        rows[j][c][i] = sl_ams_at_angle(m, mode, nf, nwl, j, c, k_lo + i, angle_index, angle_weight);
  if (k_lo == k_hi) {
#pragma omp simd
    for (int s = 0; s < live; ++s) {
      const double order = n[s] + 1.0, f = order - floor(order);
      for (int c = 0; c < nwl; ++c) {
        double sum = 0.0;
        for (int j = 0; j < nf; ++j) {
          const double term = sl_eye_phase_field(m, mode, nf, nwl, j, c, fields[s][j], f, rows[j][c][0], rows[j][c][1]);
          sum += fields[s][j] > 0.0f ? term : 0.0;
        }
        phase[c][s] = sum;
      }
    }
    return;
  }
#pragma GCC ivdep
  for (int s = 0; s < live; ++s) {
    const double order = n[s] + 1.0;
    const int k = (int)floor(order);
    const double f = order - k;
    const int i = (k < top ? k : top) - k_lo;
    for (int c = 0; c < nwl; ++c) {
      double sum = 0.0;
      for (int j = 0; j < nf; ++j) {
        const double term = sl_eye_phase_field(m, mode, nf, nwl, j, c, fields[s][j], f, rows[j][c][i], rows[j][c][i + 1]);
        sum += fields[s][j] > 0.0f ? term : 0.0;
      }
      phase[c][s] = sum;
    }
  }
}

#endif
