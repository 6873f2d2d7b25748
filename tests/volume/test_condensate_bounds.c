/* The box a default camera frames (sl_volume_condensate_boxes): a block of cloud of vertical
 * optical depth 2 under a domain-wide ice wisp of 0.05, an ice layer above the block in one of its
 * columns, and a lone ice layer elsewhere (a column of depth 0.15): the box is the block's cells,
 * up to that layer, written out by hand; the wisp and the lone layer stay out. With the wisp alone
 * no column qualifies. Several thresholds from one pass give each its own box. */
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
  const double want_lo[3] = {450.0, 250.0, 150.0}, want_hi[3] = {950.0, 650.0, 850.0};
  /* Three thresholds from one pass: 1, the block up to the layer above it; 0.1 takes in the lone column (20, 15) and its
   * layer at k = 6; 100 none. */
  const double taus[3] = {1.0, 0.1, 100.0};
  double box_lo[3][3], box_hi[3][3];
  int found[3];
  CHECK(sl_volume_condensate_boxes(&v, 3, taus, beta_min, box_lo, box_hi, found) == 1);
  CHECK(found[0] == 1 && found[1] == 1 && found[2] == 0);
  const double wide_hi[3] = {2050.0, 1550.0, 850.0};
  for (int a = 0; a < 3; ++a) {
    CHECK_CLOSE(box_lo[0][a], want_lo[a], 1e-12, 1e-9);
    CHECK_CLOSE(box_hi[0][a], want_hi[a], 1e-12, 1e-9);
    CHECK_CLOSE(box_lo[1][a], want_lo[a], 1e-12, 1e-9);
    CHECK_CLOSE(box_hi[1][a], wide_hi[a], 1e-12, 1e-9);
  }
  /* The wisp alone: no column reaches 1. */
  for (size_t q = 0; q < sl_volume_count(&v); ++q) v.eta[SL_CLOUD][q] = 0.0f;
  CHECK(sl_volume_condensate_boxes(&v, 1, taus, beta_min, box_lo, box_hi, found) == 0 && found[0] == 0);
  sl_volume_free(&v);
  return sl_test_finish("test_condensate_bounds");
}
