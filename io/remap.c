/* The load shared by every format: a block of model levels at a time (blocks that follow the
 * files' compressed chunks, so each chunk is inflated once), each hydrometeor becomes an
 * extinction-equivalent number concentration and is deposited straight into the uniform output
 * grid by the conservative vertical remap. Held beside the output, for one block: interface
 * heights, densities and a freezing flag, and one hydrometeor variable (with its number). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sl_large_alloc.h"
#include "storm_internal.h"

/* Conservative remap of one model layer [a, b] of constant value `eta` onto output cells
 * [ground + k dz, ground + (k + 1) dz]: each cell gains eta times its overlap / dz, so the column's
 * particle path (sum of eta times thickness), and with it the water path, is the model's wherever
 * the output spans the model column. The levels written widen *k_lo .. *k_hi (the frame's
 * content box). Returns 1 when it added a non-zero value (the column then holds medium: every value
 * added is positive). */
static int deposit_layer(float *column, size_t stride, int nzo, double ground, double dz, double a, double b,
                         double eta, int *k_lo, int *k_hi)
{
  int added = 0;
  if (eta == 0.0 || b <= a) return 0;
  /* Clamped as doubles: a corrupt height far outside the grid must not overflow the int cast. */
  const double u0 = floor((a - ground) / dz), u1 = floor((b - ground) / dz);
  const int k0 = u0 < 0.0 ? 0 : u0 > nzo - 1 ? nzo - 1 : (int)u0;
  const int k1 = u1 < 0.0 ? -1 : u1 > nzo - 1 ? nzo - 1 : (int)u1;
  for (int k = k0; k <= k1; ++k) {
    const double z0 = ground + k * dz, z1 = z0 + dz;
    const double overlap = (b < z1 ? b : z1) - (a > z0 ? a : z0);
    if (overlap > 0.0) {
      const float add = (float)(eta * overlap / dz);
      column[(size_t)k * stride] += add;
      added |= add != 0.0f;
      if (k < *k_lo) *k_lo = k;
      if (k > *k_hi) *k_hi = k;
    }
  }
  return added;
}

/* One block of levels as the deposit reads it: the block's interfaces (z, n2 apart per level, nk + 1
 * levels), the air's densities and freezing flags per cell, the columns' sinking (drop, or NULL),
 * the output lattice (nzo levels of dz from ground) and the species' effective-radius sums. */
typedef struct remap_block {
  const char *path;
  int level;    /* the file's model level of the block's first (for messages) */
  int k0, nk;   /* the block: levels k0 .. k0 + nk - 1 of the subset */
  size_t n2;
  const double *z, *drop;
  const float *rho_dry, *rho_moist;
  const unsigned char *frozen;
  int nzo;
  double ground, dz;
  float **lnr_eta;
  float *q, *qn; /* scratch: the species' variable and its number */
  int *box_lo, *box_hi; /* the samples deposited so far (the frame's content box), widened here */
  int *held;            /* per particle type: 1 once a deposit left a non-zero value in its field */
} remap_block;

/* Starts species i's stats (frame->species_stats[i]) before its first block. */
static void species_stats_start(sl_field_stats *st)
{
  memset(st, 0, sizeof *st);
  st->present = 1, st->q_min = INFINITY, st->q_max = -INFINITY;
  st->r_eff_min = INFINITY, st->r_eff_max = 0.0;
}

/* Whether cell i3's mixing ratio v (or its number qn) is refused: not finite, or beyond what
 * advection noise and physics allow (remap_species_block says which). */
static inline int cell_refused(double v, int number_var, double qn)
{
  return !isfinite(v) || v < -0.01 || v > 0.1 || (number_var && !isfinite(qn));
}

/* One block of species sp, read, as its checks, stats and deposits: per column, its levels in
 * order, so every output sample receives its adds in the serial order and the fields do not depend
 * on the threads. Columns are independent (each writes only its own output column), so rows of
 * them are shared among the threads, dynamically: a thread that another process keeps off its
 * core leaves its rows to the other. Ranges, counts, the content box and which types were written
 * are reductions of exact comparisons and integers; the sum of mixing ratios is taken per row of a
 * level (row_sum) and those in the cells' order, so it depends neither on the threads nor on the
 * blocks. Returns the least refused cell, or the block's cell count where none is. */
static size_t deposit_species_block(const remap_block *x, const sl_species *sp, sl_storm_frame *frame,
                                    sl_field_stats *st, double *row_sum)
{
  const size_t n2 = x->n2, n3 = n2 * (size_t)x->nk;
  const int nk = x->nk, nzo = x->nzo, nx = frame->volume.nx, ny = (int)(n2 / (size_t)nx);
  const double ground = x->ground, dz = x->dz;
  const float *rho_air = sp->per_moist_air ? x->rho_moist : x->rho_dry;
  const int number_var = sp->number_variable[0] != 0;
  double q_min = st->q_min, q_max = st->q_max, r_min = st->r_eff_min, r_max = st->r_eff_max;
  long negative = 0, number_negative = 0, number_missing = 0;
  int lo0 = x->box_lo[0], lo1 = x->box_lo[1], lo2 = x->box_lo[2];
  int hi0 = x->box_hi[0], hi1 = x->box_hi[1], hi2 = x->box_hi[2];
  int held_warm = 0, held_cold = 0;
  size_t refused = n3;
  float *const warm_eta = frame->volume.eta[sp->warm], *const cold_eta = frame->volume.eta[sp->cold];
  float *const warm_lnr = x->lnr_eta[sp->warm], *const cold_lnr = x->lnr_eta[sp->cold];
#pragma omp parallel for schedule(dynamic, 4) reduction(min : q_min, r_min, lo0, lo1, lo2, refused) \
    reduction(max : q_max, r_max, hi0, hi1, hi2, held_warm, held_cold) \
    reduction(+ : negative, number_negative, number_missing)
  for (int j = 0; j < ny; ++j)
    for (int l = 0; l < nk; ++l) {
      double sum = 0.0;
      for (int i = 0; i < nx; ++i) {
        const size_t c = (size_t)j * nx + i, i3 = (size_t)l * n2 + c;
        double v = x->q[i3];
        /* Zero's sign is dropped (-0 + 0 is +0): which of two equal extremes a reduction keeps
         * would otherwise depend on the threads. */
        if (v + 0.0 < q_min) q_min = v + 0.0;
        if (v + 0.0 > q_max) q_max = v + 0.0;
        const double qn = number_var ? x->qn[i3] : 0.0;
        if (cell_refused(v, number_var, qn)) {
          if (i3 < refused) refused = i3;
          continue;
        }
        /* Advection leaves small negatives (WRF's are ~1e-6 kg/kg): clamped and counted. */
        if (v < 0.0) negative++, v = 0.0;
        double number = -1.0; /* none */
        if (number_var) {
          number = qn;
          if (number < 0.0) number_negative++, number = 0.0;
          if (number == 0.0 && v > 0.0) number_missing++;
        }
        sum += v;
        if (v == 0.0) continue;
        const int cold = x->frozen[i3] != 0;
        const int target = cold ? sp->cold : sp->warm;
        double r_eff;
        const double eta = sl_species_eta(sp, target, rho_air[i3], v, x->rho_dry[i3], number, &r_eff);
        if (r_eff > 0.0 && v > 1e-6) {
          if (r_eff < r_min) r_min = r_eff;
          if (r_eff > r_max) r_max = r_eff;
        }
        /* A column that sinks by the earth's curvature deposits lower in the grid. */
        const double sink = x->drop ? x->drop[c] : 0.0;
        const double a = x->z[i3] - sink, b = x->z[i3 + n2] - sink;
        int k_lo = nzo, k_hi = -1;
        if (deposit_layer((cold ? cold_eta : warm_eta) + c, n2, nzo, ground, dz, a, b, eta, &k_lo, &k_hi)) {
          if (cold) held_cold = 1;
          else held_warm = 1;
        }
        float *lnr = cold ? cold_lnr : warm_lnr;
        if (lnr)
          deposit_layer(lnr + c, n2, nzo, ground, dz, a, b,
                        eta * log(r_eff > 0.0 ? r_eff : sl_particle_properties((sl_particle)target)->effective_radius_m),
                        &k_lo, &k_hi);
        if (k_lo <= k_hi) {
          if (i < lo0) lo0 = i;
          if (i > hi0) hi0 = i;
          if (j < lo1) lo1 = j;
          if (j > hi1) hi1 = j;
          if (k_lo < lo2) lo2 = k_lo;
          if (k_hi > hi2) hi2 = k_hi;
        }
      }
      row_sum[(size_t)l * ny + j] = sum;
    }
  st->q_min = q_min, st->q_max = q_max, st->r_eff_min = r_min, st->r_eff_max = r_max;
  st->negative_count += negative, st->number_negative += number_negative, st->number_missing += number_missing;
  x->box_lo[0] = lo0, x->box_lo[1] = lo1, x->box_lo[2] = lo2;
  x->box_hi[0] = hi0, x->box_hi[1] = hi1, x->box_hi[2] = hi2;
  if (held_warm) x->held[sp->warm] = 1;
  if (held_cold) x->held[sp->cold] = 1;
  return refused;
}

/* One block of species sp (index i) read, checked and deposited into the frame's fields
 * (deposit_species_block): mixing ratios below zero clamped and counted, non-finite or unphysical
 * values refused naming the level of the first; its stats accumulated into frame->species_stats[i],
 * its sum of mixing ratios into *sum. row_sum: scratch of a double per row of the block. */
static int remap_species_block(const remap_block *x, const sl_level_reader *r, const sl_species *sp, int i,
                               sl_storm_frame *frame, double *sum, double *row_sum, sl_error *err)
{
  const char *path = x->path;
  const size_t n2 = x->n2;
  int rc;
  if ((rc = r->field(r->ctx, sp->variable, x->k0, x->nk, x->q, err))) return rc;
  if (sp->number_variable[0] && (rc = r->field(r->ctx, sp->number_variable, x->k0, x->nk, x->qn, err))) return rc;
  const size_t bad = deposit_species_block(x, sp, frame, &frame->species_stats[i], row_sum);
  if (bad == n2 * (size_t)x->nk) {
    for (size_t k = 0; k < (size_t)x->nk * (n2 / (size_t)frame->volume.nx); ++k) *sum += row_sum[k];
    return SL_OK;
  }
  const double v = x->q[bad];
  const int level = x->level + (int)(bad / n2);
  if (!isfinite(v))
    return sl_fail(err, SL_ERR_DATA, "%s: %s is not a number at model level %d (a missing value the file does not "
                   "declare as _FillValue or missing_value)", path, sp->variable, level);
  /* Below -0.01 kg/kg, the bound the CF vapour has, it is not noise but a wrong field or wrong units. */
  if (v < -0.01)
    return sl_fail(err, SL_ERR_DATA, "%s: %s = %g kg/kg at model level %d is not a physical mixing ratio "
                   "(beyond the clamping of advection noise, -0.01)", path, sp->variable, v, level);
  if (v > 0.1)
    return sl_fail(err, SL_ERR_DATA, "%s: %s = %g kg/kg at model level %d is not a physical mixing ratio", path,
                   sp->variable, v, level);
  return sl_fail(err, SL_ERR_DATA, "%s: %s is not a number at model level %d", path, sp->number_variable, level);
}

/* Ends species sp's stats (index i) after its last block, over the subset's n3 cells. */
static void species_stats_finish(const sl_species *sp, int i, size_t n3, double sum, sl_storm_frame *frame)
{
  sl_field_stats *st = &frame->species_stats[i];
  if (!(st->r_eff_max > 0.0)) st->r_eff_min = st->r_eff_max = 0.0;
  st->q_mean = sum / (double)n3;
  frame->species[i] = *sp;
  if (!frame->stats[sp->warm].present) frame->stats[sp->warm] = *st;
}

/* Work arrays per block: at 1000 x 1000 columns a level of them is some 40 MB. */
#define REMAP_BLOCK_BYTES ((size_t)64 << 20)

/* The end of the block of levels that starts at k (of nz): as many levels as REMAP_BLOCK_BYTES
 * holds, rounded to whole layers of the files' chunks (down, but at least to the first layer's
 * end) so that no chunk is inflated twice. */
static int block_end(const sl_level_reader *r, int k, int nz, size_t n2)
{
  int end;
  if (r && r->block_levels > 0) {
    end = k + r->block_levels;
  } else {
    const size_t fit = REMAP_BLOCK_BYTES / ((n2 > 0 ? n2 : 1) * SL_REMAP_BYTES_PER_CELL);
    end = k + (fit < 1 ? 1 : fit > (size_t)nz ? nz : (int)fit);
    const int e = r ? r->chunk_levels : 1;
    if (e > 1) {
      const int below = end - (((end + r->chunk_phase) % e) + e) % e; /* the last layer start <= end */
      end = below > k ? below : below + e;
    }
  }
  return end < nz ? end : nz;
}

int sl_remap_block_levels(const sl_level_reader *r, int nz, size_t n2)
{
  int most = 0;
  for (int k = 0; k < nz;) {
    const int e = block_end(r, k, nz, n2);
    if (e - k > most) most = e - k;
    k = e;
  }
  return most;
}

/* Model only what the scene needs: a type that holds nothing at this time (BOMEX's ice, the
 * supercell's ice and snow at 10 minutes) gets no field, so no tables and no per-sample work. A
 * storm with nothing at all keeps its first field, empty, and renders as the sky. Which fields
 * hold anything the deposits said (held): a scan would read a whole empty field. */
static void drop_empty_fields(sl_storm_frame *frame, float **lnr_eta, const int held[SL_PARTICLE_COUNT])
{
  int any = 0, first = -1;
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
    if (frame->volume.eta[p]) {
      if (first < 0) first = p;
      any |= held[p];
    }
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
    if (frame->volume.eta[p] && !held[p] && (any || p != first)) {
      sl_volume_drop_field(&frame->volume, p);
      free(lnr_eta[p]);
      lnr_eta[p] = NULL;
    }
}

int sl_remap_levels(const char *path, const sl_level_reader *r, const sl_subset *s, const sl_species *species,
                    int nspecies, double ground, double top, double dz, const double spacing_h[2],
                    const double corner[2], const double *drop, int max_fields, sl_storm_frame *frame,
                    sl_error *err)
{
  const int nx = s->nx, ny = s->ny, nz = s->nz;
  const size_t n2 = (size_t)nx * ny, n3 = n2 * nz;
  const double levels = ceil((top - ground) / dz);
  if (!isfinite(levels))
    return sl_fail(err, SL_ERR_DATA, "%s: the grid's bottom (%g m), top (%g m) or spacing (%g m) is not finite", path,
                   ground, top, dz);
  if (levels > 4096)
    return sl_fail(err, SL_ERR_ARG, "%s: vertical spacing %g m gives %.0f levels, more than 4096", path, dz, levels);
  const int nzo = levels < 1.0 ? 1 : (int)levels;
  int moist = 0, number = 0;
  for (int i = 0; i < nspecies; ++i) moist |= species[i].per_moist_air, number |= species[i].number_variable[0] != 0;
  const int nb = sl_remap_block_levels(r, nz, n2);
  const size_t nbc = (size_t)nb * n2;
  /* Per block: interface heights (double: the remap's conservation rests on them), densities and
   * the freezing flag, one hydrometeor variable (and its number) at a time. Each is written whole
   * every block, so on huge pages: a first write per 4 KiB page cost this VM a fault each. */
  double *z = sl__huge_alloc(nbc * sizeof(double) + n2 * sizeof(double));
  float *rho_dry = sl__huge_alloc(nbc * sizeof(float)), *rho_moist = moist ? sl__huge_alloc(nbc * sizeof(float)) : NULL;
  float *q = sl__huge_alloc(nbc * sizeof(float)), *qn = number ? sl__huge_alloc(nbc * sizeof(float)) : NULL;
  unsigned char *frozen = sl__huge_alloc(nbc);
  double *sums = calloc((size_t)nspecies + 1, sizeof(double));
  double *row_sum = malloc(((size_t)nb * ny + 1) * sizeof(double));
  float *lnr_eta[SL_PARTICLE_COUNT] = {0};
  int rc = SL_OK;
  if (!z || !rho_dry || (moist && !rho_moist) || !q || (number && !qn) || !frozen || !sums || !row_sum) {
    rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory for %d x %d x %d cells", path, nx, ny, nb);
    goto done;
  }
  const double dx = spacing_h[0], dy = spacing_h[1];
  const double origin[3] = {corner ? corner[0] : -0.5 * (nx - 1) * dx, corner ? corner[1] : -0.5 * (ny - 1) * dy,
                            ground + 0.5 * dz};
  const double spacing[3] = {dx, dy, dz};
  if ((rc = sl_volume_init(&frame->volume, nx, ny, nzo, origin, spacing, err))) goto done;
  for (int i = 0; i < nspecies; ++i)
    for (int b = 0; b < 2; ++b) {
      const int p = b ? species[i].cold : species[i].warm;
      if (!frame->volume.eta[p] && (rc = sl_volume_add_field(&frame->volume, (sl_particle)p, err))) goto done;
    }
  /* Cloud and rain with sizes from the microphysics: beside eta, the sum of eta ln(r_eff) per cell,
   * from which io/size_bins.c draws the optics of each cell's sizes. */
  for (int i = 0; i < nspecies; ++i) {
    const int p = species[i].warm;
    if ((p == SL_CLOUD || p == SL_RAIN) && sl_species_sized(&species[i]) && !lnr_eta[p] &&
        !(lnr_eta[p] = calloc(sl_volume_count(&frame->volume), sizeof(float)))) {
      rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory for the effective-radius field", path);
      goto done;
    }
  }
  for (int i = 0; i < nspecies; ++i) species_stats_start(&frame->species_stats[i]);
  int box_lo[3] = {nx, ny, nzo}, box_hi[3] = {-1, -1, -1}, held[SL_PARTICLE_COUNT] = {0};
  /* Each cell's deposit needs only its own level's heights, air and value: blocks of levels are the
   * outer loop, so the work arrays hold a block, and each variable is read once across them. */
  for (int k0 = 0, k1, last = 0; k0 < nz; last = k1 - k0, k0 = k1) {
    k1 = block_end(r, k0, nz, n2);
    const int nk = k1 - k0;
    const size_t cells = (size_t)nk * n2;
    /* The block's bottom interfaces are the last block's top ones. */
    if (k0 > 0) memmove(z, z + (size_t)last * n2, n2 * sizeof(double));
    if ((rc = k0 == 0 ? r->interfaces(r->ctx, 0, nk + 1, z, err) : r->interfaces(r->ctx, k0 + 1, nk, z + n2, err)))
      goto done;
    size_t falling = cells;
#pragma omp parallel for simd schedule(dynamic, SL_IO_CHUNK) reduction(min : falling) if (cells > SL_IO_CHUNK)
    for (size_t i = 0; i < cells; ++i)
      if (!(z[i + n2] > z[i]) && i < falling) falling = i;
    if (falling < cells) {
      rc = sl_fail(err, SL_ERR_DATA, "%s: heights do not increase upward at model level %d", path,
                   s->k0 + k0 + (int)(falling / n2));
      goto done;
    }
    if ((rc = r->air(r->ctx, k0, nk, rho_dry, rho_moist, frozen, err))) goto done;
    const remap_block x = {path, s->k0 + k0, k0, nk, n2, z, drop, rho_dry, rho_moist, frozen, nzo, ground, dz,
                           lnr_eta, q, qn, box_lo, box_hi, held};
    for (int i = 0; i < nspecies; ++i)
      if ((rc = remap_species_block(&x, r, &species[i], i, frame, &sums[i], row_sum, err))) goto done;
  }
  for (int i = 0; i < nspecies; ++i) species_stats_finish(&species[i], i, n3, sums[i], frame);
  frame->volume.content_known = 1;
  for (int a = 0; a < 3; ++a) frame->volume.content_lo[a] = box_lo[a], frame->volume.content_hi[a] = box_hi[a];
  frame->nspecies = nspecies;
  drop_empty_fields(frame, lnr_eta, held);
  rc = sl_size_bins_split(&frame->volume, lnr_eta, max_fields, &frame->sizes, err);
done:
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p) free(lnr_eta[p]);
  free(z);
  free(rho_dry);
  free(rho_moist);
  free(q);
  free(qn);
  free(frozen);
  free(sums);
  free(row_sum);
  return rc;
}
