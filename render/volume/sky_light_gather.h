/* What the eye passes read of the skylight lattice (sky_light.h): M at a point, and the light a
 * batch of samples scatters from it toward the eye. */
#ifndef SL_SKY_LIGHT_GATHER_H
#define SL_SKY_LIGHT_GATHER_H

#include "renderer_internal.h"
#include "sky_light.h"
#include "sl_sample_physics.h"

/* M per wavelength at world point x, into out[0..nwl) (out has room for the stride): trilinear on
 * the lattice (clamped into it), weighted by the lattice's extinction, so that M at a cloud's
 * surface is the cloud's own and not that of the clear air beside it, whose light runs along the
 * surface (a horizon's light under an anvil never enters its base). */
static inline __attribute__((always_inline)) void sl__sky_light_at(const sl__sky_light *s, const double x[3],
                                                                   float *out)
{
  int i0[3];
  double f[3];
  sl__lattice_cell(&s->view, x, i0, f);
  const size_t sx = s->n[0] > 1 ? (size_t)s->stride : 0, sy = s->n[1] > 1 ? (size_t)s->n[0] * s->stride : 0;
  const size_t sz = s->n[2] > 1 ? (size_t)s->n[0] * s->n[1] * s->stride : 0;
  const float *c = s->radiance + (((size_t)i0[2] * s->n[1] + i0[1]) * s->n[0] + i0[0]) * s->stride;
  for (int g = 0; g < s->stride; g += 4) {
    const sl__v4f v = sl__trilinear_v4f(c + g, sx, sy, sz, (float)f[0], (float)f[1], (float)f[2]);
    memcpy(out + g, &v, sizeof v);
  }
  const float beta = out[s->nwl], inv = beta > 0.0f ? 1.0f / beta : 0.0f;
  for (int k = 0; k < s->nwl; ++k) out[k] *= inv;
}

/* The skylight a batch of samples sends toward the eye (sl_sky_step_light), added to radiance; fields
 * are packed for `model` (sl__batch_fields), nf its count, mode its mode. SL__SKY_BATCH is the rows'
 * length. */
#define SL__SKY_BATCH 32
static inline __attribute__((always_inline)) void sl__sky_light_add(const sl_light_model *model, const int mode,
                                                                    const int nf, const int nwl, const int live,
                                                                    float (*restrict fields)[SL_MAX_FIELDS],
                                                                    const double *restrict inv_beta,
                                                                    const double *restrict opacity,
                                                                    float (*restrict sky)[SL_MAX_WAVELENGTHS + 4],
                                                                    double (*restrict radiance)[SL__SKY_BATCH])
{
  for (int c = 0; c < nwl; ++c)
    for (int s = 0; s < live; ++s)
      radiance[c][s] += sl_sky_step_light(model, mode, nf, nwl, fields[s], c, opacity[s], inv_beta[s], sky[s][c]);
}

#endif
