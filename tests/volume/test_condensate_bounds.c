/* The box a default camera frames (sl_volume_condensate_bounds): a block of cloud of vertical
 * optical depth 2 under a domain-wide ice wisp of 0.05, an ice layer above the block in one of its
 * columns, and a lone ice layer elsewhere (a column of depth 0.15): the box is the block's cells,
 * up to that layer, written out by hand; the wisp and the lone layer stay out. With the wisp alone
 * no column qualifies. */
#include <math.h>

#include "sl_particles.h"
#include "sl_testing.h"
#include "sl_volume.h"

enum { NX = 30, NY = 20, NZ = 10 };

int main(void)
{
  sl_error err = {0};
  sl_volume v;
  const double origin[3] = {0.0, 0.0, 0.0}, spacing[3] = {100.0, 100.0, 100.0};
  CHECK(sl_volume_init(&v, NX, NY, NZ, origin, spacing, &err) == SL_OK);
  CHECK(sl_volume_add_field(&v, SL_CLOUD, &err) == SL_OK && sl_volume_add_field(&v, SL_ICE, &err) == SL_OK);
  const double s_cloud = sl_particle_properties(SL_CLOUD)->sigma_ext_m2;
  const double s_ice = sl_particle_properties(SL_ICE)->sigma_ext_m2;
  const double beta_min = 1e-4;
  /* The wisp: extinction 5e-5 per metre at every sample (below beta_min), 0.05 a column. */
  for (size_t q = 0; q < sl_volume_count(&v); ++q) v.eta[SL_ICE][q] = (float)(5e-5 / s_ice);
  /* The block: i 5..9, j 3..6, k 2..5, 4 levels of 5e-3 per metre: a column of 2 (plus the wisp). */
  for (int k = 2; k <= 5; ++k)
    for (int j = 3; j <= 6; ++j)
      for (int i = 5; i <= 9; ++i) v.eta[SL_CLOUD][sl_volume_index(&v, i, j, k)] = (float)(5e-3 / s_cloud);
  /* Above the block in column (7, 4): ice of 2e-4 per metre at k = 8, within the box. */
  v.eta[SL_ICE][sl_volume_index(&v, 7, 4, 8)] = (float)(2e-4 / s_ice);
  /* Elsewhere, (20, 15): ice of 1e-3 per metre at k = 6, a column of 0.15: not a cloud a viewer sees. */
  v.eta[SL_ICE][sl_volume_index(&v, 20, 15, 6)] = (float)(1e-3 / s_ice);
  /* A NaN sample in the wisp is no extinction. */
  v.eta[SL_ICE][sl_volume_index(&v, 25, 2, 1)] = NAN;
  double lo[3], hi[3];
  CHECK(sl_volume_condensate_bounds(&v, 1.0, beta_min, lo, hi) == 1);
  const double want_lo[3] = {450.0, 250.0, 150.0}, want_hi[3] = {950.0, 650.0, 850.0};
  for (int a = 0; a < 3; ++a) {
    CHECK_CLOSE(lo[a], want_lo[a], 1e-12, 1e-9);
    CHECK_CLOSE(hi[a], want_hi[a], 1e-12, 1e-9);
  }
  /* The wisp alone: no column reaches 1. */
  for (size_t q = 0; q < sl_volume_count(&v); ++q) v.eta[SL_CLOUD][q] = 0.0f;
  CHECK(sl_volume_condensate_bounds(&v, 1.0, beta_min, lo, hi) == 0);
  sl_volume_free(&v);
  return sl_test_finish("test_condensate_bounds");
}
