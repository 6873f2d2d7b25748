/* The streaming load shared by every format: one model level at a time, each hydrometeor variable
 * becomes an extinction-equivalent number concentration and is deposited straight into the
 * uniform output grid by the conservative vertical remap. Peak memory is the output grid plus a
 * few horizontal slabs; nothing of the model's 3-D state is held. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "storm_internal.h"

/* Conservative remap of one model layer [a, b] of constant value `eta` onto output cells
 * [ground + k dz, ground + (k + 1) dz]: each cell gains eta times its overlap / dz, so the column's
 * particle path (sum of eta times thickness), and with it the water path, is the model's wherever
 * the output spans the model column. */
static void deposit_layer(float *column, size_t stride, int nzo, double ground, double dz, double a, double b,
                          double eta)
{
  if (eta == 0.0 || b <= a) return;
  int k0 = (int)floor((a - ground) / dz), k1 = (int)floor((b - ground) / dz);
  if (k0 < 0) k0 = 0;
  if (k1 > nzo - 1) k1 = nzo - 1;
  for (int k = k0; k <= k1; ++k) {
    const double z0 = ground + k * dz, z1 = z0 + dz;
    const double overlap = (b < z1 ? b : z1) - (a > z0 ? a : z0);
    if (overlap > 0.0) column[(size_t)k * stride] += (float)(eta * overlap / dz);
  }
}

int sl_remap_levels(const char *path, const sl_level_reader *r, const sl_subset *s, const sl_species *species,
                    int nspecies, double ground, double top, double dz, double dx, double dy, sl_storm_frame *frame,
                    sl_error *err)
{
  const int nx = s->nx, ny = s->ny;
  const size_t n2 = (size_t)nx * ny;
  int nzo = (int)ceil((top - ground) / dz);
  if (nzo < 1) nzo = 1;
  if (nzo > 4096)
    return sl_fail(err, SL_ERR_ARG, "%s: vertical spacing %g m gives %d levels, more than 4096", path, dz, nzo);
  const double origin[3] = {-0.5 * (nx - 1) * dx, -0.5 * (ny - 1) * dy, ground + 0.5 * dz};
  const double spacing[3] = {dx, dy, dz};
  int rc = sl_volume_init(&frame->volume, nx, ny, nzo, origin, spacing, err);
  if (rc) return rc;
  for (int i = 0; i < nspecies; ++i) {
    for (int b = 0; b < 2; ++b) {
      const int p = b ? species[i].cold : species[i].warm;
      if (!frame->volume.eta[p] && (rc = sl_volume_add_field(&frame->volume, (sl_particle)p, err))) return rc;
    }
    sl_field_stats *st = &frame->species_stats[i];
    st->present = 1, st->q_min = INFINITY, st->q_max = -INFINITY;
  }
  enum { ZLO, ZHI, RHO_D, RHO_M, TEMP, Q, QN, NBUF };
  double *buf[NBUF] = {0};
  for (int b = 0; b < NBUF; ++b)
    if (!(buf[b] = malloc(n2 * sizeof(double)))) {
      rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
      goto done;
    }
  double *zlo = buf[ZLO], *zhi = buf[ZHI];
  double *sums = calloc((size_t)nspecies, sizeof(double));
  if (!sums) {
    rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
    goto done;
  }
  if ((rc = r->interfaces(r->ctx, 0, zlo, err))) goto done_sums;
  for (int k = 0; k < s->nz; ++k) {
    if ((rc = r->interfaces(r->ctx, k + 1, zhi, err))) goto done_sums;
    for (size_t c = 0; c < n2; ++c)
      if (!(zhi[c] > zlo[c])) {
        rc = sl_fail(err, SL_ERR_DATA, "%s: heights do not increase upward at model level %d", path, s->k0 + k);
        goto done_sums;
      }
    if ((rc = r->air(r->ctx, k, buf[RHO_D], buf[RHO_M], buf[TEMP], err))) goto done_sums;
    for (int i = 0; i < nspecies; ++i) {
      const sl_species *sp = &species[i];
      double *q = buf[Q], *qn = buf[QN];
      if ((rc = r->field(r->ctx, sp->variable, k, q, err))) goto done_sums;
      if (sp->number_variable[0] && (rc = r->field(r->ctx, sp->number_variable, k, qn, err))) goto done_sums;
      sl_field_stats *st = &frame->species_stats[i];
      const double *rho_air = sp->per_moist_air ? buf[RHO_M] : buf[RHO_D];
      for (size_t c = 0; c < n2; ++c) {
        double v = q[c];
        if (v < st->q_min) st->q_min = v;
        if (v > st->q_max) st->q_max = v;
        if (v < 0.0) {
          st->negative_count++;
          v = 0.0;
        }
        if (v > 0.1) {
          rc = sl_fail(err, SL_ERR_DATA, "%s: %s = %g kg/kg at model level %d is not a physical mixing ratio", path,
                       sp->variable, v, s->k0 + k);
          goto done_sums;
        }
        sums[i] += v;
        if (v == 0.0) continue;
        const int target = buf[TEMP][c] < SL_FREEZING_K ? sp->cold : sp->warm;
        const double eta =
            sl_species_eta(sp, target, rho_air[c], v, buf[RHO_D][c], sp->number_variable[0] ? qn[c] : -1.0);
        float *column = frame->volume.eta[target] + c;
        deposit_layer(column, n2, nzo, ground, dz, zlo[c], zhi[c], eta);
      }
    }
    double *t = zlo;
    zlo = zhi, zhi = t;
  }
  for (int i = 0; i < nspecies; ++i) {
    sl_field_stats *st = &frame->species_stats[i];
    st->q_mean = sums[i] / ((double)n2 * s->nz);
    frame->species[i] = species[i];
    const int own = species[i].radius_m == sl_particle_properties((sl_particle)species[i].warm)->radius_m;
    if (own && !frame->stats[species[i].warm].present) frame->stats[species[i].warm] = *st;
  }
  frame->nspecies = nspecies;
done_sums:
  free(sums);
done:
  for (int b = 0; b < NBUF; ++b) free(buf[b]);
  return rc;
}
