/* A thick eye segment's profile and its parts' fields on the CPU (the slicer's eye_batch.h and
 * the light-volume march): the parts' bounds themselves are sl_segment_parts, shared with the GPU. */
#ifndef SL_SEGMENT_PARTS_H
#define SL_SEGMENT_PARTS_H

#include "renderer_internal.h"
#include "sl_sample_physics.h"

/* The fields at a thick segment's profile points (sl__segment_profile), kept for its parts'
 * (sl__segment_part_fields), which read them at those points: with more than one field, whose
 * total the profile sums from them. */
typedef struct sl__segment_profile_fields {
  float v[SL_PART_PROFILE][SL__FIELD_LANES];
} sl__segment_profile_fields;

/* The total extinction at the middles of SL_PART_PROFILE steps of `step` from t_near along the
 * ray o + t d, and the optical depth from t_near at each profile point (no end point is read: a
 * segment may end on the box's face, where the medium stops); returns the whole optical depth.
 * With more than one field each point's fields go to *kept. */
static inline __attribute__((always_inline)) double sl__segment_profile(const sl_renderer *r, const int nf, const double o[3],
                                                                        const double d[3], double t_near,
                                                                        double step,
                                                                        double step_beta[SL_PART_PROFILE],
                                                                        double tau[SL_PART_PROFILE + 1],
                                                                        sl__segment_profile_fields *kept)
{
  tau[0] = 0.0;
  for (int k = 0; k < SL_PART_PROFILE; ++k) {
    const double t = t_near + (k + 0.5) * step;
    const double x[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
    if (nf > 1) {
      /* sl__total_extinction_n's sum, of the fields kept */
      sl__sample_fields_n(r, nf, x, kept->v[k]);
      double total = 0.0;
      for (int j = 0; j < nf; ++j) total += kept->v[k][j];
      step_beta[k] = total;
    } else {
      step_beta[k] = sl__total_extinction_n(r, nf, x);
    }
    tau[k + 1] = tau[k] + step * step_beta[k];
  }
  return tau[SL_PART_PROFILE];
}

/* The fields of the part from optical depth tau_a to tau_b (length len) of a segment profiled by
 * sl__segment_profile: their mix at the profile step that holds the middle of the part's optical
 * depth (sl_segment_part_mix_step: a point inside the medium, where the part's middle may lie in
 * clear air), scaled to the part's mean extinction on the profile, into fields[0..nf-1]; returns
 * that mean, or 0 where the mix holds no medium. With more than one field the profile's own
 * fields at that step (kept); with one, read there. */
static inline __attribute__((always_inline)) double sl__segment_part_fields(
    const sl_renderer *r, const int nf, const double o[3], const double d[3], double t_near, double step,
    const double step_beta[SL_PART_PROFILE], const double tau[SL_PART_PROFILE + 1],
    const sl__segment_profile_fields *kept, double tau_a, double tau_b, double len, float *fields)
{
  const int k_mix = sl_segment_part_mix_step(tau, step_beta, 0.5 * (tau_a + tau_b));
  if (nf > 1) {
    for (int j = 0; j < nf; ++j) fields[j] = kept->v[k_mix][j];
  } else {
    const double t_mix = t_near + (k_mix + 0.5) * step;
    const double x[3] = {o[0] + t_mix * d[0], o[1] + t_mix * d[1], o[2] + t_mix * d[2]};
    sl__sample_fields_n(r, nf, x, fields);
  }
  double beta = 0.0;
  for (int j = 0; j < nf; ++j) beta += fields[j];
  if (!(beta > 0.0)) return 0.0;
  const double mean = (tau_b - tau_a) / len, scale = mean / beta;
  for (int j = 0; j < nf; ++j) fields[j] = (float)(fields[j] * scale);
  return mean;
}

#endif
