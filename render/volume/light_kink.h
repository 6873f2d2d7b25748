/* The light's kink at a cloud's surface between light-buffer texels (light_kink), and where each
 * texel's ray enters the medium (texel_entry, light_kink.c). Used by the slicer's eye pass under a
 * low sun. */
#ifndef SL_LIGHT_KINK_H
#define SL_LIGHT_KINK_H

#include "slicer.h"

/* Where a light texel's ray o + u prop enters the medium between `first` and `last` (its occupied
 * stretch): where its optical depth reaches SL__ENTRY_DEPTH; NaN when it does not. */
double sl__texel_entry(const sl_renderer *r, const double o[3], const double prop[3], double first, double last,
                       double step);

/* The sun's elevation (degrees) below which the slicer places the light's kink at surfaces
 * (light_kink): flat tops under a low sun are where texel rows meet a surface kilometres apart. */
#define KINK_SUN_ELEVATION 15.0
/* Texel widths that a cell's entries must spread over along the rays for light_kink. */
#define KINK_SPREAD 4.0
/* The least difference in ln I or n between a cell's texels for light_kink. */
#define KINK_MIN_FALL 0.25f

/* The light at a cloud's surface between light texels. Where a flat top meets the sunlight at a
 * grazing angle, one texel row's ray runs just above the top (ln I = 0) while the next entered it
 * kilometres upwind and has lost tens of optical depths; ln I interpolated between them put the
 * surface's light anywhere between the two, one stripe per row (Katrina's lid at dawn,
 * DESIGN-NOTES.md), and the light of a top whose density ramps up over one grid level is decided
 * within the first texel row's spacing. Each texel knows where its ray entered the medium
 * (texel_entry) and the state there; the distance e its ray has run inside since is linear across
 * texels under a planar surface, so its bilinear interpolation e* is exact where that of ln I is
 * not. Where a cell's texels straddle the entry (some e > 0, some e <= 0), or have all entered but
 * the nearest less than the cell's spread of entries ago (past a ramped top ln I is not yet linear
 * in e there), the point's light is rebuilt from its own entry: the texels' states at entry
 * interpolated (the ones not yet in give their current state, which has not changed since the
 * sunlight came in), and when e* > 0 the light steps (eq. 24, eq. 21) along the last e* of its ray
 * to the plane, sampled every half grid cell at their middles (exact for extinction linear along
 * the ray, as a top's ramp between two levels is). A texel whose ray never enters is left out of
 * the interpolations. Only in cells marked grazing (slicer_passes), under a low sun.
 * Replaces value[c], c <= nwl, the bilinear state at (u, v) in the cell whose first texel's state
 * is at t, for the point p on the slice plane where a ray has run e_plane - g; returns 0 (value
 * untouched) where none of its texels has entered. */
static inline __attribute__((always_inline)) int light_kink(const sl_renderer *r, const int nf, const int nwl,
                                                            const light_buffer *L, ptrdiff_t di, ptrdiff_t dj,
                                                            ptrdiff_t t, double u, double v, double e_plane,
                                                            const double p[3], const double prop[3], double step,
                                                            double *value)
{
  const int stride = nwl + 1;
  const ptrdiff_t off[4] = {t, t + di, t + dj, t + di + dj};
  const double w[4] = {(1.0 - u) * (1.0 - v), u * (1.0 - v), (1.0 - u) * v, u * v};
  double e[4], inside = 0.0, outside = 0.0, known = 0.0;
  for (int k = 0; k < 4; ++k) {
    e[k] = e_plane - L->entry_g[off[k] / stride];
    if (e[k] > 0.0) inside += w[k] * e[k];
    else if (e[k] <= 0.0) outside += w[k] * e[k];
    known += e[k] == e[k] ? w[k] : 0.0;
  }
  if (!(inside > 0.0)) return 0;
  /* Where ln I and n differ little between the texels, their interpolation cannot be far off (at
   * most that difference, at a kink) and is kept: an optically thin medium's. */
  float lo = INFINITY, hi = -INFINITY, n_lo = INFINITY, n_hi = -INFINITY;
  for (int k = 0; k < 4; ++k)
    if (e[k] == e[k]) {
      lo = fminf(lo, L->state[off[k]]), hi = fmaxf(hi, L->state[off[k]]);
      n_lo = fminf(n_lo, L->state[off[k] + nwl]), n_hi = fmaxf(n_hi, L->state[off[k] + nwl]);
    }
  if (!(hi - lo > KINK_MIN_FALL || n_hi - n_lo > KINK_MIN_FALL)) return 0;
  /* The weights over the texels whose rays enter: one that never does (it passes above a top or
   * beside a wall) says nothing of where a point with medium in the cell entered. */
  const double renorm = 1.0 / known;
  inside *= renorm, outside *= renorm;
  float state[SL_MAX_WAVELENGTHS + 1];
  for (int c = 0; c < stride; ++c) {
    double at_entry = 0.0;
    for (int k = 0; k < 4; ++k) {
      if (e[k] != e[k]) continue;
      /* A texel past its entry whose step there was not taken (no medium at its middle) has kept
       * no entry state: its state is still the one at entry. */
      const int kept = e[k] > 0.0 && L->entry_state[off[k] + stride - 1] >= 0.0f;
      at_entry += w[k] * (kept ? L->entry_state[off[k] + c] : L->state[off[k] + c]);
    }
    state[c] = (float)(at_entry * renorm);
  }
  const double e_star = inside + outside;
  if (e_star > 0.0) {
    const double parts = ceil(e_star / step);
    const int n = parts < 1.0 ? 1 : parts > 16.0 ? 16 : (int)parts;
    const double len = e_star / n;
    const sl_light_model *m = &r->model;
    for (int i = 0; i < n; ++i) {
      const double back = e_star - (i + 0.5) * len;
      const double x[3] = {p[0] - back * prop[0], p[1] - back * prop[1], p[2] - back * prop[2]};
      float bj[SL_MAX_FIELDS];
      if (!sl__sample_fields_n(r, nf, x, bj)) continue;
#define KINK_STEP(model, mode, count) sl_log_light_step_at(model, mode, count, nwl, bj, len, state, 0)
      SL_WITH_BATCH_MODEL(m, m, nf, nf, KINK_STEP);
#undef KINK_STEP
      /* Past e^-80 in every wavelength no light is left to shape (the n of no light is moot). */
      int lit = 0;
      for (int c = 0; c < nwl; ++c) lit |= state[c] > -80.0f;
      if (!lit) break;
    }
  }
  for (int c = 0; c < stride; ++c) value[c] = state[c];
  return 1;
}

#endif
