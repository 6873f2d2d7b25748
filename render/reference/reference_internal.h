/* Internals shared by the reference's source files: the medium's prepared state and the
 * tracking routines every estimator uses. */
#ifndef SL_REFERENCE_INTERNAL_H
#define SL_REFERENCE_INTERNAL_H

#include "sl_legendre.h" /* SL_PI */
#include "sl_reference.h"

/* A tabulated phase function's sampler: the probability of each 0.1-degree cell of the
 * piecewise-linear ams[1], integrated exactly against sin(theta). */
typedef struct phase_sampler {
  sl_ref_phase_kind kind;
  double g;
  const sl_phase_table *table;
  double inv_total;  /* 1 / (integral of ams[1] over the sphere) = 1 / (1 - f) up to rounding */
  double *cdf;       /* n_angles entries: probability that theta < theta_j */
} phase_sampler;

struct sl_ref_medium {
  sl_ref_medium_desc desc;
  int nw, nc;
  double lo[3], hi[3], size[3];
  double content_lo[3], content_hi[3];
  double content_center[3];        /* centre of the box around non-empty samples (renderer's midplane anchor) */
  float *extinction[SL_REF_MAX_WAVELENGTHS];  /* effective total extinction per sample, m^-1 */
  sl_grid_view extinction_view[SL_REF_MAX_WAVELENGTHS];
  sl_grid_view density_view[SL_REF_MAX_COMPONENTS];
  double sigma_eff[SL_REF_MAX_COMPONENTS][SL_REF_MAX_WAVELENGTHS];
  double albedo_eff[SL_REF_MAX_COMPONENTS][SL_REF_MAX_WAVELENGTHS];
  phase_sampler phase[SL_REF_MAX_COMPONENTS][SL_REF_MAX_WAVELENGTHS];
  int block, nb[3];
  double block_size[3];
  float *majorant[SL_REF_MAX_WAVELENGTHS]; /* per majorant cell, x fastest */
};

typedef enum track_event {
  TRACK_COLLISION = 0,
  TRACK_TOP = 1,     /* left through the top face */
  TRACK_BOTTOM = 2,  /* left through the bottom face (absorbed there with a black surface) */
  TRACK_SIDE = 3     /* left through an open side (or circled a periodic medium too long) */
} track_event;

/* Delta tracking from x (inside or on the box) along unit d, through periodic sides. On a
 * collision x is moved there; on an escape x is the exit point. *travelled (may be NULL) gets
 * the distance covered. */
track_event ref_track(const sl_ref_medium *m, int w, double x[3], const double d[3], sl_ref_rng *rng,
                      double *travelled);
/* Ratio-tracking transmittance from x along d up to `length` metres (INFINITY: to the box's
 * boundary, through periodic sides), with Russian roulette once it is small. */
double ref_transmittance(const sl_ref_medium *m, int w, const double x[3], const double d[3], double length,
                         sl_ref_rng *rng);
/* The scattering component hit at x, chosen in proportion to its extinction there. */
int ref_choose_component(const sl_ref_medium *m, int w, const double x[3], sl_ref_rng *rng);
/* The density (1/sr) with which sl_ref_phase_sample draws a direction at cosine mu from the axis. */
double ref_phase_pdf(const sl_ref_medium *m, int c, int w, double mu);
/* A unit vector at angle acos(mu) from d, azimuth uniform. */
void ref_rotate(const double d[3], double mu, double phi, double out[3]);

#endif
