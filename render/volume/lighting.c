#include "lighting.h"

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
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p) {
    if (!sc->volume->eta[p]) continue;
    const int j = m->nf++;
    m->field[j] = (sl_particle)p;
    if (!sc->optics) {
      m->sigma_ext[j] = sl_particle_properties((sl_particle)p)->sigma_ext_m2;
      m->albedo_mean[j] = 1.0;
      for (int c = 0; c < m->nwl; ++c) m->albedo[j][c] = 1.0;
      continue;
    }
    double sigma = 0.0, albedo = 0.0;
    for (int c = 0; c < m->nwl; ++c) {
      const sl_phase_table *t = sl_optics_table(sc->optics, (sl_particle)p, c);
      if (!t)
        return sl_fail(err, SL_ERR_ARG, "renderer: no particle table for %s at wavelength %d",
                       sl_particle_name((sl_particle)p), c);
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
        return sl_fail(err, SL_ERR_ARG, "renderer: the %s table has no scattering orders", sl_particle_name((sl_particle)p));
      double *lp = malloc((size_t)(t->max_order + 1) * sizeof(double));
      if (!lp) return sl_fail(err, SL_ERR_NOMEM, "renderer: out of memory");
      lp[0] = 0.0;
      for (int k = 1; k <= t->max_order; ++k) lp[k] = lp[k - 1] + log(t->albedo * t->forward[k]);
      m->log_product[j][c] = lp;
    }
  }
  return SL_OK;
}

void sl_light_model_free(sl_light_model *m)
{
  for (int j = 0; j < SL_MAX_FIELDS; ++j)
    for (int c = 0; c < SL_MAX_WAVELENGTHS; ++c) free(m->log_product[j][c]);
  memset(m, 0, sizeof *m);
}

/* The cumulative log product at a real number of events x >= 0, linear between integers. */
static double log_product_at(const sl_light_model *m, int j, int c, double x)
{
  const double *lp = m->log_product[j][c];
  const int N = m->max_order[j][c];
  if (x >= N) return lp[N] + (x - N) * (lp[N] - lp[N - 1]);
  const int k = (int)x;
  return lp[k] + (x - k) * (lp[k + 1] - lp[k]);
}

double sl_log_forward_product(const sl_light_model *m, int j, int c, double n, double events)
{
  /* Riley et al. 2004, eq. 24: prod_{i=n+1}^{n+events} albedo F_i, with the product taken over a
   * continuous count of events so that fractional n and events interpolate. */
  return log_product_at(m, j, c, n + events) - log_product_at(m, j, c, n);
}

/* Scattering events per metre of the mix and each field's share of them (eq. 6's weights). */
static double scattering_mix(const sl_light_model *m, const float *beta, double *share)
{
  double total = 0.0;
  for (int j = 0; j < m->nf; ++j) total += m->albedo_mean[j] * beta[j];
  for (int j = 0; j < m->nf; ++j) share[j] = total > 0.0 ? m->albedo_mean[j] * beta[j] / total : 0.0;
  return total;
}

void sl_light_fraction(const sl_light_model *m, const float *beta, double n, double len, double *fraction)
{
  double ext = 0.0;
  for (int j = 0; j < m->nf; ++j) ext += beta[j];
  const double transparency = exp(-ext * len);
  if (m->mode == SL_LIGHTING_LOW_ALBEDO || !(ext > 0.0)) {
    for (int c = 0; c < m->nwl; ++c) fraction[c] = transparency;
    return;
  }
  double share[SL_MAX_FIELDS];
  const double events = scattering_mix(m, beta, share) * len;
  for (int c = 0; c < m->nwl; ++c) {
    double kept;
    if (m->mode == SL_LIGHTING_MULTIPLE_EQ25) {
      /* Riley et al. 2004, eq. 25: the worst-case order's forward fraction to the power of the
       * slab's scattering count (the paper's GPU workaround). */
      const int order = (int)floor(n + 1.0 + events);
      double f = 0.0, a = 0.0;
      for (int j = 0; j < m->nf; ++j) {
        f += share[j] * sl_phase_table_forward(m->table[j][c], order);
        a += share[j] * m->albedo[j][c];
      }
      kept = pow(a * f, events);
    } else {
      /* Eq. 24 with a mix: each field's product weighted geometrically by its share of the
       * events (exact for one field; a mix along a path has no exact per-field split). */
      double log_kept = 0.0;
      for (int j = 0; j < m->nf; ++j)
        if (share[j] > 0.0) log_kept += share[j] * sl_log_forward_product(m, j, c, n, events);
      kept = exp(log_kept);
    }
    /* Eq. 24: what passes unscattered, plus the scattered part that stays in the forward
     * hemisphere through every event of the slab. */
    fraction[c] = transparency + (1.0 - transparency) * kept;
  }
}

void sl_light_step(const sl_light_model *m, const float *beta, double len, float *I, float *n)
{
  double fraction[SL_MAX_WAVELENGTHS];
  sl_light_fraction(m, beta, *n, len, fraction);
  for (int c = 0; c < m->nwl; ++c) I[c] = (float)(I[c] * fraction[c]);
  if (m->mode != SL_LIGHTING_LOW_ALBEDO) {
    double share[SL_MAX_FIELDS];
    /* Riley et al. 2004, eq. 21: the expected number of scattering events accumulates the
     * scattering optical depth from the sun. */
    *n = (float)(*n + scattering_mix(m, beta, share) * len);
  }
}

void sl_eye_phase(const sl_light_model *m, const float *beta, double n, int angle_index, double angle_weight,
                  double *out)
{
  if (m->mode == SL_LIGHTING_LOW_ALBEDO) {
    double sca = 0.0;
    for (int j = 0; j < m->nf; ++j) sca += m->albedo_mean[j] * beta[j];
    for (int c = 0; c < m->nwl; ++c) out[c] = sca / (4.0 * M_PI);
    return;
  }
  /* Riley et al. 2004, eq. 26: the light reaching the sample has scattered n times on average;
   * the event that sends it to the eye is the (n+1)-th, so Ams_{n+1}, linear in n. */
  const double order = n + 1.0;
  const int k = (int)floor(order);
  const double f = order - k;
  for (int c = 0; c < m->nwl; ++c) {
    double sum = 0.0;
    for (int j = 0; j < m->nf; ++j) {
      if (!(beta[j] > 0.0f)) continue;
      const sl_phase_table *t = m->table[j][c];
      const int k0 = k > t->max_order ? t->max_order : k, k1 = k + 1 > t->max_order ? t->max_order : k + 1;
      const float *r0 = t->ams + (size_t)k0 * t->n_angles, *r1 = t->ams + (size_t)k1 * t->n_angles;
      const double a0 = r0[angle_index] + angle_weight * (r0[angle_index + 1] - r0[angle_index]);
      const double a1 = r1[angle_index] + angle_weight * (r1[angle_index + 1] - r1[angle_index]);
      /* Eq. 6: each field's distribution weighted by its scattering coefficient. */
      sum += m->albedo[j][c] * beta[j] * ((1.0 - f) * a0 + f * a1 + m->xi);
    }
    out[c] = sum;
  }
}
