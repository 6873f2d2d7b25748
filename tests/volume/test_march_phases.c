/* Eq. 26's angular term for a batch of the light-volume march's steps (march_phases.h), which reads
 * each table once a batch at the ray's angle for the orders the batch spans, against
 * sl_eye_phase_at per step, which reads the tables itself: equal to the last bit for batches whose
 * orders agree, span a few orders, span more than the rows hold, lie past the tables' last order
 * or straddle it, start at order 0, and hold absent fields; with the low-albedo model too. */
#include <math.h>
#include <stdio.h>

#include "coarse_optics.h"
#include "march_phases.h"
#include "renderer_internal.h"
#include "sl_optics.h"
#include "sl_renderer.h"
#include "sl_testing.h"

static unsigned long long rng = 88172645463325252ULL;
static double uniform(void)
{
  rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
  return (double)(rng >> 11) / 9007199254740992.0;
}

/* The batch's phases against sl_eye_phase_at lane by lane; returns the lanes that differ. */
static int differing_lanes(const sl_light_model *m, int live, float (*fields)[SL_MAX_FIELDS], const double *n,
                           int angle_index, double angle_weight)
{
  double phase[SL_MAX_WAVELENGTHS][SL__MARCH_PHASE_BATCH];
  sl__march_phases(m, (int)m->mode, m->nf, m->nwl, live, fields, n, angle_index, angle_weight, phase);
  int wrong = 0;
  for (int s = 0; s < live; ++s) {
    double want[SL_MAX_WAVELENGTHS];
    sl_eye_phase_at(m, (int)m->mode, m->nf, m->nwl, fields[s], n[s], angle_index, angle_weight, want);
    for (int c = 0; c < m->nwl; ++c)
      if (!(phase[c][s] == want[c])) {
        wrong++;
        break;
      }
  }
  return wrong;
}

int main(void)
{
  sl_error err = {0};
  sl_volume v;
  const double origin[3] = {0, 0, 0}, spacing[3] = {100, 100, 100};
  if (!CHECK(sl_volume_init(&v, 4, 4, 4, origin, spacing, &err) == SL_OK)) return sl_test_finish("test_march_phases");
  CHECK(sl_volume_add_field(&v, SL_CLOUD, &err) == SL_OK);
  CHECK(sl_volume_add_field(&v, SL_ICE, &err) == SL_OK);
  for (size_t i = 0; i < sl_volume_count(&v); ++i) v.eta[SL_CLOUD][i] = 1e8f, v.eta[SL_ICE][i] = 1e5f;
  sl_optics_tables *optics = coarse_optics((1u << SL_CLOUD) | (1u << SL_ICE), &err);
  if (!CHECK_MSG(optics != NULL, err.message)) return sl_test_finish("test_march_phases");
  for (int lighting = 0; lighting < 2; ++lighting) {
    sl_scene sc = {.volume = &v, .optics = optics, .xi = 0.01};
    sc.lighting = lighting ? SL_LIGHTING_MULTIPLE : SL_LIGHTING_LOW_ALBEDO;
    sl_sun_direction(40.0, 200.0, sc.sun_direction);
    for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0;
    sl_renderer *r = sl_renderer_create(&sc, &err);
    if (!CHECK_MSG(r != NULL, err.message)) break;
    const sl_light_model *m = &r->model;
    CHECK_MSG(m->nf == 2, "two fields: cloud and ice");
    const int n_angles = lighting ? m->table[0][0]->n_angles : 2;
    int top = 0;
    for (int j = 0; j < m->nf; ++j)
      for (int c = 0; c < m->nwl; ++c) top = m->max_order[j][c] > top ? m->max_order[j][c] : top;
    /* Batches by the orders n + 1 of their steps: [lowest, lowest + spread). */
    const struct {
      double lowest, spread;
      const char *what;
    } kinds[] = {{3.1, 0.8, "one order"},          {0.0, 6.0, "a few orders"},
                 {0.0, 13.9, "fourteen orders"},    {0.0, 15.9, "sixteen orders"},
                 {0.0, 40.0, "more orders than the rows"},
                 {top + 50.0, 30.0, "past the last"}, {top - 4.0, 12.0, "across the last"},
                 {0.0, 0.0, "order 0"}};
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k)
      for (int trial = 0; trial < 40; ++trial) {
        const int live = trial % 4 == 0 ? 1 : trial % 4 == 1 ? SL__MARCH_PHASE_BATCH : 1 + (int)(uniform() * 31);
        float fields[SL__MARCH_PHASE_BATCH][SL_MAX_FIELDS] = {{0}};
        double n[SL__MARCH_PHASE_BATCH];
        for (int s = 0; s < live; ++s) {
          /* Either field may be absent from a step (the batch's subsets leave its tables out). */
          const int held = (int)(uniform() * 3);
          fields[s][0] = held != 1 ? (float)(1e-3 * uniform()) : 0.0f;
          fields[s][1] = held != 0 ? (float)(1e-4 * uniform()) : 0.0f;
          n[s] = kinds[k].lowest + kinds[k].spread * uniform() - 1.0;
        }
        const int angle_index = (int)(uniform() * (n_angles - 1));
        const double angle_weight = trial % 3 == 0 ? 0.0 : trial % 3 == 1 ? 1.0 : uniform();
        const int wrong = differing_lanes(m, live, fields, n, angle_index, angle_weight);
        char what[160];
        snprintf(what, sizeof what, "%s, %s: %d of %d steps differ from sl_eye_phase_at",
                 lighting ? "multiple scattering" : "low albedo", kinds[k].what, wrong, live);
        CHECK_MSG(wrong == 0, what);
      }
    sl_renderer_destroy(r);
  }
  sl_optics_free(optics);
  sl_volume_free(&v);
  return sl_test_finish("test_march_phases");
}
