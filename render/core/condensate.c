/* Where a storm's condensate is (sl_volume.h): the box a default camera frames. Wisps of ice or a
 * few droplets spread over a whole domain would make the renderer's content box (every non-empty
 * sample) the domain; the columns a viewer sees as cloud are those of vertical optical depth about
 * 1 or more. */
#include <math.h>
#include <stdlib.h>

#include "sl_particles.h"
#include "sl_volume.h"

int sl_volume_condensate_boxes(const sl_volume *v, int n, const double *tau_min, double beta_min, double (*lo)[3],
                               double (*hi)[3], int *found)
{
  for (int b = 0; b < n; ++b) found[b] = 0;
  /* The fields present, each with its cross-section (eq. 2's beta = eta sigma). */
  const float *field[SL_VOLUME_SLOTS];
  double sigma[SL_VOLUME_SLOTS];
  int nfield = 0;
  for (int k = 0; k < SL_VOLUME_SLOTS; ++k)
    if (v->eta[k]) field[nfield] = v->eta[k], sigma[nfield++] = sl_particle_properties(sl_volume_field_type(v, k))->sigma_ext_m2;
  /* Per column its optical depth and the lowest and highest level of beta >= beta_min. A row of
   * columns at a time, level by level, each field's row summed into the row's beta (loops along x
   * that vectorise; a column at a time strode nx ny apart and took a minute on the supercell's
   * grid, a test per slot and sample 12 s of CPU at 1000 x 1000 x 160); the rows in parallel. */
  const size_t columns = (size_t)v->nx * v->ny;
  double *tau = calloc(columns, sizeof *tau);
  int *k_lo = malloc(columns * sizeof *k_lo), *k_hi = malloc(columns * sizeof *k_hi);
  if (!tau || !k_lo || !k_hi) {
    free(tau), free(k_lo), free(k_hi);
    return 0;
  }
  for (size_t c = 0; c < columns; ++c) k_lo[c] = k_hi[c] = -1;
  /* Only the content box holds medium: the other columns and levels add nothing. */
  int box_lo[3], box_hi[3];
  const int box_any = sl_volume_content_samples(v, box_lo, box_hi);
  int no_memory = 0;
#pragma omp parallel
  {
    double *beta = malloc((size_t)v->nx * sizeof *beta);
    if (!beta) {
#pragma omp atomic write
      no_memory = 1;
    }
#pragma omp for schedule(static)
    for (int j = box_lo[1]; j <= box_hi[1]; ++j)
      for (int k = box_lo[2]; box_any && k <= box_hi[2] && beta; ++k) {
        const size_t q0 = sl_volume_index(v, 0, j, k), c0 = (size_t)j * v->nx;
        for (int i = box_lo[0]; i <= box_hi[0]; ++i) beta[i] = 0.0;
        for (int f = 0; f < nfield; ++f) {
          const float *eta = field[f] + q0;
          const double s = sigma[f];
          for (int i = box_lo[0]; i <= box_hi[0]; ++i) beta[i] += eta[i] > 0.0f ? eta[i] * s : 0.0;
        }
        for (int i = box_lo[0]; i <= box_hi[0]; ++i) {
          const size_t c = c0 + i;
          tau[c] += beta[i] * v->spacing[2];
          if (beta[i] >= beta_min) {
            if (k_lo[c] < 0) k_lo[c] = k;
            k_hi[c] = k;
          }
        }
      }
    free(beta);
  }
  if (no_memory) {
    free(tau), free(k_lo), free(k_hi);
    return 0;
  }
  /* Each threshold's box from the same column sums. */
  int any = 0;
  for (int b = 0; b < n; ++b) {
    int box_lo[3] = {0, 0, 0}, box_hi[3] = {0, 0, 0};
    for (int j = 0; j < v->ny; ++j)
      for (int i = 0; i < v->nx; ++i) {
        const size_t c = (size_t)j * v->nx + i;
        if (!(tau[c] >= tau_min[b]) || k_lo[c] < 0) continue;
        const int at[3][2] = {{i, i}, {j, j}, {k_lo[c], k_hi[c]}};
        for (int a = 0; a < 3; ++a) {
          if (!found[b] || at[a][0] < box_lo[a]) box_lo[a] = at[a][0];
          if (!found[b] || at[a][1] > box_hi[a]) box_hi[a] = at[a][1];
        }
        found[b] = 1;
      }
    for (int a = 0; a < 3 && found[b]; ++a) {
      lo[b][a] = v->origin[a] + (box_lo[a] - 0.5) * v->spacing[a];
      hi[b][a] = v->origin[a] + (box_hi[a] + 0.5) * v->spacing[a];
    }
    any |= found[b];
  }
  free(tau), free(k_lo), free(k_hi);
  return any;
}
