/* The water path of one column of a loaded storm: the sum over its cells of eta * particle mass
 * * dz (kg m-2), the quantity the vertical remap conserves. Shared by the reader tests. */
#ifndef SL_TEST_COLUMN_PATH_H
#define SL_TEST_COLUMN_PATH_H
#include "sl_storm.h"

static inline double sl_test_column_path(const sl_storm_frame *f, int i, int j)
{
  double w = 0.0;
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
    for (int k = 0; f->volume.eta[p] && k < f->volume.nz; ++k)
      w += f->volume.eta[p][sl_volume_index(&f->volume, i, j, k)] * sl_particle_mass((sl_particle)p) *
           f->volume.spacing[2];
  return w;
}
#endif
