/* Optics that follow each cell's droplet sizes: the effective radius of cloud and rain varies across
 * a two-moment storm (small droplets in the updraught's base, large ones aloft and in the anvil), and
 * with it the glory, the corona, the fogbow and the rainbow's width. The renderer mixes the phase
 * functions of its fields in proportion to their scattering coefficients (Riley et al. 2004, eq. 6),
 * so a cell between two tabulated radii R_j < r < R_{j+1} is drawn as two fields of those radii whose
 * extinctions split the cell's in the ratio of ln r's position between them: the phase function,
 * albedo, Ams_n and F_n interpolated linearly in ln r, weighted by extinction, with no per-sample
 * cost beyond one more field. The total extinction stays the cell's own, 3 Q / (4 rho r) per unit
 * mass, with Q the neighbouring tables' (io/species.c has the rest of the formula). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "storm_internal.h"

/* Table radii lie on one lattice, 2^(k/8) um, so that frames of a series whose ranges overlap share
 * cached tables. */
#define LATTICE_PER_OCTAVE 8.0
/* The widest ratio between neighbouring tables, per type (test_size_interpolation, docs/OPTICS.md
 * "Sizes between tables": the mixture against the phase function computed at the midpoint radius
 * sends under 2 % of the scattered light the wrong way). Drizzle and rain drops' phase functions
 * change slowly with size (x of hundreds to thousands): 3 there does what 1.5 does for droplets. */
static double max_ratio(int type) { return type == SL_CLOUD ? 1.5 : 3.0; }
/* Extinction-weighted percentiles of ln r that bound the tables: the rest is clamped to the ends. */
#define TAIL 0.01
#define HISTOGRAM 512
#define LN_R_LO (-14.5) /* ln 0.5 um */
#define LN_R_HI (-3.0)  /* ln 5 cm */

static double lattice(double ln_r, double (*round_fn)(double))
{
  const double step = log(2.0) / LATTICE_PER_OCTAVE, zero = log(1e-6);
  return zero + step * round_fn((ln_r - zero) / step);
}

/* A range within one lattice step of its median takes one table there. */
static int narrow(double ln_lo, double ln_hi) { return ln_hi - ln_lo < 1.5 * log(2.0) / LATTICE_PER_OCTAVE; }

/* The extinction-weighted quantile of ln r over a histogram. */
static double quantile(const double *h, double total, double fraction)
{
  double acc = 0.0;
  for (int b = 0; b < HISTOGRAM; ++b) {
    acc += h[b];
    if (acc >= fraction * total) return LN_R_LO + (LN_R_HI - LN_R_LO) * (b + 0.5) / HISTOGRAM;
  }
  return LN_R_HI;
}

int sl_size_bins_split(sl_volume *v, float *const lnr_eta[SL_PARTICLE_COUNT], int max_fields, sl_size_bins *out,
                       sl_error *err)
{
  memset(out, 0, sizeof *out);
  /* Only the content box holds medium (sl_volume.h): rows of it, in the grid's order. */
  int box_lo[3], box_hi[3];
  if (!sl_volume_content_samples(v, box_lo, box_hi)) return SL_OK;
  const long rows = sl_volume_box_rows(box_lo, box_hi);
  const size_t row_length = (size_t)(box_hi[0] - box_lo[0] + 1);
  double lo[SL_PARTICLE_COUNT], hi[SL_PARTICLE_COUNT], mid[SL_PARTICLE_COUNT];
  int want[SL_PARTICLE_COUNT] = {0}, sized = 0;
  for (int t = 0; t < SL_PARTICLE_COUNT; ++t) {
    if (!lnr_eta[t] || !v->eta[t]) continue;
    double h[HISTOGRAM] = {0}, total = 0.0;
    for (long r = 0; r < rows; ++r)
      for (size_t i = sl_volume_box_row(v, box_lo, box_hi, r), end = i + row_length; i < end; ++i) {
        const double e = v->eta[t][i];
        if (!(e > 0.0)) continue;
        const double x = lnr_eta[t][i] / e;
        int b = (int)floor((x - LN_R_LO) / (LN_R_HI - LN_R_LO) * HISTOGRAM);
        b = b < 0 ? 0 : (b >= HISTOGRAM ? HISTOGRAM - 1 : b);
        h[b] += e, total += e;
      }
    if (!(total > 0.0)) continue;
    lo[t] = lattice(quantile(h, total, TAIL), floor);
    hi[t] = lattice(quantile(h, total, 1.0 - TAIL), ceil);
    mid[t] = lattice(quantile(h, total, 0.5), round);
    out->range_lo_m[t] = exp(quantile(h, total, TAIL));
    out->range_hi_m[t] = exp(quantile(h, total, 1.0 - TAIL));
    want[t] = 1;
    sized++;
  }
  if (!sized) return SL_OK;
  /* One table when the whole range is within one lattice step of the median; otherwise tables
   * until neighbours are at most max_ratio apart. The renderer carries SL_VOLUME_MAX_FIELDS fields
   * per sample (the GPU pass four), so the sizes share what the types leave: each further table
   * goes to the type whose neighbours are furthest apart for its ratio. */
  const int carried = max_fields > 0 && max_fields < SL_VOLUME_MAX_FIELDS ? max_fields : SL_VOLUME_MAX_FIELDS;
  int free_slots = carried - sl_volume_field_count(v);
  if (free_slots < 0) free_slots = 0;
  for (;;) {
    int worst = -1;
    double worst_excess = 1.0;
    for (int t = 0; t < SL_PARTICLE_COUNT; ++t) {
      if (!want[t] || narrow(lo[t], hi[t])) continue;
      const double excess = want[t] == 1 ? INFINITY : (hi[t] - lo[t]) / (want[t] - 1) / log(max_ratio(t));
      if (excess > worst_excess + 1e-9) worst = t, worst_excess = excess;
    }
    if (worst < 0) break;
    if (free_slots == 0) {
      /* Every type whose neighbours stay wider than its ratio got fewer tables than it asks. */
      for (int t = 0; t < SL_PARTICLE_COUNT; ++t) {
        if (!want[t] || narrow(lo[t], hi[t])) continue;
        out->limited[t] = want[t] == 1 || (hi[t] - lo[t]) / (want[t] - 1) > log(max_ratio(t)) + 1e-9;
      }
      break;
    }
    want[worst]++, free_slots--;
  }
  for (int t = 0; t < SL_PARTICLE_COUNT; ++t) {
    if (!want[t]) continue;
    double R[SL_VOLUME_MAX_FIELDS] = {0};
    int K = 0;
    if (want[t] == 1) {
      R[K++] = mid[t];
    } else {
      for (int j = 0; j < want[t]; ++j) {
        const double x = lattice(lo[t] + (hi[t] - lo[t]) * j / (want[t] - 1), round);
        if (K == 0 || x > R[K - 1] + 1e-9) R[K++] = x;
      }
    }
    const double r_own = sl_particle_properties((sl_particle)t)->effective_radius_m;
    int slot[SL_VOLUME_MAX_FIELDS];
    slot[0] = t;
    v->effective_radius_m[t] = exp(R[0]);
    for (int j = 1; j < K; ++j) {
      const int rc = sl_volume_add_sized_field(v, (sl_particle)t, exp(R[j]), &slot[j], err);
      if (rc) return rc;
    }
    /* eta counted the type's representative particles with the extinction per mass of the type's
     * own tables, 3 Q / (4 rho r_own); a table of radius R_j has 3 Q / (4 rho R_j): the share of
     * the cell's extinction that goes to it is R_j / r_own times as many particles. */
    float *eta = v->eta[t];
    for (long r = 0; r < rows; ++r)
      for (size_t i = sl_volume_box_row(v, box_lo, box_hi, r), end = i + row_length; i < end; ++i) {
        const double e = eta[i];
        if (!(e > 0.0)) continue;
        const double x = lnr_eta[t][i] / e;
        int j = 0;
        while (j + 2 < K && x > R[j + 1]) ++j;
        double w = K == 1 ? 0.0 : (x - R[j]) / (R[j + 1] - R[j]);
        w = w < 0.0 ? 0.0 : (w > 1.0 ? 1.0 : w);
        eta[i] = 0.0f;
        v->eta[slot[j]][i] += (float)((1.0 - w) * e * exp(R[j]) / r_own);
        if (w > 0.0) v->eta[slot[j + 1]][i] += (float)(w * e * exp(R[j + 1]) / r_own);
      }
    out->count[t] = K;
    for (int j = 0; j < K; ++j) out->radius_m[t][j] = exp(R[j]);
  }
  return SL_OK;
}
