#include "lighting.h"
#include "sl_sample_physics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int sl_light_model_init(sl_light_model *m, const sl_scene *sc, sl_error *err)
{
  memset(m, 0, sizeof *m);
  m->mode = sc->lighting;
  m->xi = sc->xi;
  m->nwl = sc->atmosphere ? sc->atmosphere->count : SL_CHANNELS;
  if (m->nwl < 1 || m->nwl > SL_MAX_WAVELENGTHS)
    return sl_fail(err, SL_ERR_ARG, "renderer: %d wavelengths (1..%d)", m->nwl, SL_MAX_WAVELENGTHS);
  const int needs_optics = m->mode != SL_LIGHTING_LOW_ALBEDO;
  if (needs_optics && !sc->optics)
    return sl_fail(err, SL_ERR_ARG, "renderer: the multiple-scattering lighting needs particle tables");
  if (sc->optics && sl_optics_wavelength_count(sc->optics) != m->nwl)
    return sl_fail(err, SL_ERR_ARG, "renderer: the particle tables have %d wavelengths, the atmosphere %d",
                   sl_optics_wavelength_count(sc->optics), m->nwl);
  for (int k = 0; k < SL_VOLUME_SLOTS; ++k) {
    if (!sc->volume->eta[k]) continue;
    const sl_particle p = sl_volume_field_type(sc->volume, k);
    const double r_eff = sc->volume->effective_radius_m[k];
    const int j = m->nf++;
    m->field[j] = p;
    m->slot[j] = k;
    if (!sc->optics) {
      m->sigma_ext[j] = sl_particle_properties(p)->sigma_ext_m2;
      m->albedo_mean[j] = 1.0;
      for (int c = 0; c < m->nwl; ++c) m->albedo[j][c] = 1.0;
      continue;
    }
    double sigma = 0.0, albedo = 0.0;
    for (int c = 0; c < m->nwl; ++c) {
      const sl_phase_table *t = sl_optics_table_sized(sc->optics, p, r_eff, c);
      if (!t)
        return sl_fail(err, SL_ERR_ARG, "renderer: no particle table for %s (effective radius %g m) at wavelength %d",
                       sl_particle_name(p), r_eff, c);
      m->table[j][c] = t;
      m->albedo[j][c] = t->albedo;
      sigma += t->sigma_ext / m->nwl;
      albedo += t->albedo / m->nwl;
    }
    m->sigma_ext[j] = sigma;
    m->albedo_mean[j] = albedo;
    if (!needs_optics) continue;
    for (int c = 0; c < m->nwl; ++c) {
      const sl_phase_table *t = m->table[j][c];
      m->max_order[j][c] = t->max_order;
      if (t->max_order < 1)
        return sl_fail(err, SL_ERR_ARG, "renderer: the %s table has no scattering orders", sl_particle_name(p));
      double *lp = malloc((size_t)(t->max_order + 1) * sizeof(double));
      if (!lp) return sl_fail(err, SL_ERR_NOMEM, "renderer: out of memory");
      lp[0] = 0.0;
      for (int k = 1; k <= t->max_order; ++k) lp[k] = lp[k - 1] + log(t->albedo * t->forward[k]);
      m->log_product[j][c] = lp;
    }
  }
  return SL_OK;
}

void sl_light_model_subset(const sl_light_model *m, unsigned mask, sl_light_model *out)
{
  memset(out, 0, sizeof *out);
  out->mode = m->mode, out->nwl = m->nwl, out->xi = m->xi;
  for (int j = 0; j < m->nf; ++j) {
    if (!(mask >> j & 1u)) continue;
    const int k = out->nf++;
    out->field[k] = m->field[j];
    out->slot[k] = m->slot[j];
    out->sigma_ext[k] = m->sigma_ext[j];
    out->albedo_mean[k] = m->albedo_mean[j];
    for (int c = 0; c < m->nwl; ++c) {
      out->albedo[k][c] = m->albedo[j][c];
      out->table[k][c] = m->table[j][c];
      out->log_product[k][c] = m->log_product[j][c];
      out->max_order[k][c] = m->max_order[j][c];
    }
  }
}

void sl_light_model_free(sl_light_model *m)
{
  for (int j = 0; j < SL_MAX_FIELDS; ++j)
    for (int c = 0; c < SL_MAX_WAVELENGTHS; ++c) free(m->log_product[j][c]);
  memset(m, 0, sizeof *m);
}

double sl_log_forward_product(const sl_light_model *m, int j, int c, double n, double events)
{
  return sl_log_forward_product_at(m, (int)m->mode, m->nf, m->nwl, j, c, n, events);
}

void sl_light_fraction(const sl_light_model *m, const float *beta, double n, double len, double *fraction)
{
  sl_light_fraction_at(m, (int)m->mode, m->nf, m->nwl, beta, n, len, fraction);
}

void sl_eye_phase(const sl_light_model *m, const float *beta, double n, int angle_index, double angle_weight,
                  double *out)
{
  sl_eye_phase_at(m, (int)m->mode, m->nf, m->nwl, beta, n, angle_index, angle_weight, out);
}
