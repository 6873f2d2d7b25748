/* The particle path of one column of a loaded storm: the sum over its cells of eta * particle mass
 * * dz (kg m-2), the quantity the vertical remap conserves. For single-moment species it is the
 * water path; a sized species counts particles with the extinction of its type's own tables, and
 * its fields of other sizes hold R / r_own times as many for the same extinction (io/size_bins.c),
 * so each counts eta * r_own / R. Shared by the reader tests. */
#ifndef SL_TEST_COLUMN_PATH_H
#define SL_TEST_COLUMN_PATH_H
#include "sl_storm.h"

static inline double sl_test_column_path(const sl_storm_frame *f, int i, int j)
{
  double w = 0.0;
  for (int s = 0; s < SL_VOLUME_SLOTS; ++s) {
    if (!f->volume.eta[s]) continue;
    const sl_particle p = sl_volume_field_type(&f->volume, s);
    const double r_own = sl_particle_properties(p)->effective_radius_m;
    const double scale = f->volume.effective_radius_m[s] > 0.0 ? r_own / f->volume.effective_radius_m[s] : 1.0;
    for (int k = 0; k < f->volume.nz; ++k)
      w += f->volume.eta[s][sl_volume_index(&f->volume, i, j, k)] * scale * sl_particle_mass(p) * f->volume.spacing[2];
  }
  return w;
}
#endif
