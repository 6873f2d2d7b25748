/* The Monte Carlo reference: a spectral volumetric path tracer over the same lattice,
 * particle tables, sun, sky and camera as the fast renderer (render/volume), so that the only
 * difference between the two is how multiple scattering is treated. docs/REFERENCE.md derives
 * every estimator and lists the validation.
 *
 * Plan once, sample many (STYLE.md): sl_ref_medium_create() builds the per-wavelength extinction
 * grids, the coarse majorant grid walked by a DDA (empty space costs nothing) and the phase
 * samplers; the estimators below are then reentrant and allocation-free per path.
 *
 *   sl_ref_fluxes        domain-averaged reflectance, transmittance, absorptance of a collimated
 *                        sun (the quantities radiative-transfer intercomparisons publish)
 *   sl_ref_render        progressive image of the volume layer for an sl_camera (same pixel, same
 *                        ray as the fast renderer), with per-pixel standard errors
 *   sl_ref_point_source  angular radiance of an isotropic point source in an infinite homogeneous
 *                        medium at optical distance T (the glow model's validation)
 *
 * Randomness: every path draws from a counter-based generator keyed by (seed, pixel or photon,
 * sample, wavelength), and sums are formed in a fixed order, so results are bitwise identical
 * for any number of threads. Nothing prints, exits or keeps global state. */
#ifndef SL_REFERENCE_H
#define SL_REFERENCE_H

#include <stddef.h>

#include "sl_image.h"
#include "sl_optics.h"
#include "sl_renderer.h" /* sl_camera: the reference draws exactly the fast renderer's rays */
#include "sl_sky.h"
#include "sl_status.h"
#include "sl_volume.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SL_REF_MAX_WAVELENGTHS 16
#define SL_REF_MAX_COMPONENTS SL_VOLUME_MAX_FIELDS /* one per field of the volume */

/* ---- phase functions ------------------------------------------------------------------------ */

typedef enum sl_ref_phase_kind {
  SL_REF_PHASE_ISOTROPIC = 0,
  SL_REF_PHASE_HG = 1,       /* Henyey-Greenstein with asymmetry g */
  SL_REF_PHASE_RAYLEIGH = 2, /* Riley et al. 2004, eq. 1 */
  SL_REF_PHASE_TABLE = 3     /* render/optics: P = delta[1] dirac + ams[1] (docs/OPTICS.md) */
} sl_ref_phase_kind;

typedef struct sl_ref_phase {
  sl_ref_phase_kind kind;
  double g;                     /* HG only, in (-1, 1) */
  const sl_phase_table *table;  /* TABLE only; not owned, must outlive the medium */
} sl_ref_phase;

/* ---- media ---------------------------------------------------------------------------------- */

typedef enum sl_ref_interpolation {
  SL_REF_TRILINEAR = 0, /* sl_grid_sample: what render/volume sees (storms) */
  SL_REF_CELL = 1       /* piecewise constant per cell (benchmark clouds are given that way) */
} sl_ref_interpolation;

typedef enum sl_ref_lateral {
  SL_REF_OPEN = 0,     /* light leaving through a side is gone */
  SL_REF_PERIODIC = 1  /* it re-enters through the opposite side (infinite repetition in x, y) */
} sl_ref_lateral;

/* One scattering species: extinction (m^-1) = density * sigma[w]. */
typedef struct sl_ref_component {
  const float *density;   /* per lattice sample (x fastest); NULL: 1 everywhere. Not owned. */
  double sigma[SL_REF_MAX_WAVELENGTHS];  /* extinction per unit density */
  double albedo[SL_REF_MAX_WAVELENGTHS]; /* single-scattering albedo, 0..1 */
  sl_ref_phase phase[SL_REF_MAX_WAVELENGTHS];
} sl_ref_component;

typedef struct sl_ref_medium_desc {
  int n[3];                /* samples along x, y, z (cell-centred, as sl_volume) */
  double origin[3];        /* world position of sample (0,0,0), m */
  double spacing[3];       /* m */
  int n_wavelengths;
  double wavelength_nm[SL_REF_MAX_WAVELENGTHS];
  int n_components;
  sl_ref_component component[SL_REF_MAX_COMPONENTS];
  sl_ref_interpolation interpolation;
  sl_ref_lateral lateral;
  int black_surface;       /* 1: the box's bottom face absorbs all light reaching it */
  int majorant_block;      /* lattice samples per majorant cell along each axis; 0: 8 */
} sl_ref_medium_desc;

typedef struct sl_ref_medium sl_ref_medium;

void sl_ref_medium_desc_defaults(sl_ref_medium_desc *d);
sl_ref_medium *sl_ref_medium_create(const sl_ref_medium_desc *d, sl_error *err);
/* A storm: one component per field present in v (eta, m^-3) with the tables' sigma_ext, albedo
 * and phase at every wavelength of the tables (at most SL_REF_MAX_WAVELENGTHS), trilinear, open
 * sides, no surface. v and tables must outlive the medium. */
sl_ref_medium *sl_ref_medium_from_volume(const sl_volume *v, const sl_optics_tables *tables, sl_error *err);
void sl_ref_medium_destroy(sl_ref_medium *m);

int sl_ref_medium_wavelength_count(const sl_ref_medium *m);
double sl_ref_medium_wavelength(const sl_ref_medium *m, int w);
void sl_ref_medium_bounds(const sl_ref_medium *m, double lo[3], double hi[3]);
/* The box around samples with extinction, one cell of margin (the whole box when all are empty):
 * sl_renderer_content_bounds's definition, so sl_camera_frame frames both renderers alike. */
void sl_ref_medium_content_bounds(const sl_ref_medium *m, double lo[3], double hi[3]);
/* Extinction (m^-1) at x for wavelength w with the forward Dirac of tabulated phase functions
 * removed (sigma (1 - albedo f), docs/REFERENCE.md "Forward peaks"); 0 outside the box. */
double sl_ref_extinction(const sl_ref_medium *m, int w, const double x[3]);
/* Transmittance of the segment x -> x + len d (len may be INFINITY: to the box's boundary,
 * through periodic sides) by ratio tracking, with the given random stream. */
typedef struct sl_ref_rng {
  unsigned long long key, counter;
} sl_ref_rng;
sl_ref_rng sl_ref_rng_make(unsigned long long seed, unsigned long long stream_a, unsigned long long stream_b,
                           unsigned long long stream_c);
double sl_ref_rng_uniform(sl_ref_rng *r); /* in [0, 1) with 53 random bits */

/* Phase function value (1/sr) of component c at wavelength w without its forward Dirac, normalised
 * to 1 over the sphere, and a sample of it: returns the weight value/pdf (1 except for tables,
 * whose within-cell sampling is uniform in solid angle). */
double sl_ref_phase_eval(const sl_ref_medium *m, int c, int w, double cos_theta);
double sl_ref_phase_sample(const sl_ref_medium *m, int c, int w, const double in[3], sl_ref_rng *rng,
                           double out[3]);

/* ---- fluxes (item 4) ------------------------------------------------------------------------ */

typedef struct sl_ref_flux_options {
  double sun_zenith_deg;    /* 0 <= zenith < 90 */
  double sun_azimuth_deg;   /* direction the sun stands in, clockwise from north (+y) */
  int wavelength_index;
  long photons;
  unsigned long long seed;
  int max_scatter;          /* 0: unlimited; n: paths stop after n scatterings (counted absorbed) */
} sl_ref_flux_options;

/* Fractions of the collimated irradiance falling on the box's top face (per unit horizontal
 * area, averaged over the face); reflectance + transmittance + absorptance + side = 1. */
typedef struct sl_ref_fluxes_result {
  double reflectance, transmittance, absorptance, side; /* side: leaves through open sides */
  double direct_transmittance;  /* part of transmittance never scattered */
  double se_reflectance, se_transmittance, se_absorptance, se_side; /* Monte Carlo standard errors */
  double mean_scatterings;
  long photons;
  double seconds;
} sl_ref_fluxes_result;

void sl_ref_flux_options_defaults(sl_ref_flux_options *o);
int sl_ref_fluxes(const sl_ref_medium *m, const sl_ref_flux_options *o, sl_ref_fluxes_result *out, sl_error *err);

/* ---- images (items 1, 2) -------------------------------------------------------------------- */

typedef struct sl_ref_scene {
  const sl_ref_medium *medium;
  double sun_direction[3];          /* toward the sun, world ENU */
  /* As in sl_scene: sunlight attenuated to each scattering point's height (eq. 12), aerial
   * perspective split at the volume's midplane, sky behind it, the sun's disk. Its wavelengths
   * must be the medium's. NULL: no air; sun_irradiance reaches the box, sky_radiance is constant. */
  const sl_atmosphere *atmosphere;
  double sun_irradiance[SL_REF_MAX_WAVELENGTHS];
  double sky_radiance[SL_REF_MAX_WAVELENGTHS];
  int skylight;        /* 1: scattered paths that leave the box collect the sky */
  int max_scatter;     /* 0: unlimited; 1: single scattering; n: at most n scatterings */
  int roulette_depth;  /* scatterings before Russian roulette may end a path; 0: 16 */
  /* 1: next-event estimation of the sun alone. By default every scattering also proposes a
   * direction from its phase function centred on the sun and combines the two estimates of the
   * next vertex's sunlight by multiple importance sampling (docs/REFERENCE.md): without it,
   * strongly forward-peaked phase functions (cloud droplets: 400/sr within a degree) make
   * fireflies. Both are unbiased. */
  int next_event_only;
  unsigned long long seed;
} sl_ref_scene;

void sl_ref_scene_defaults(sl_ref_scene *s);

/* Progressive state of one camera's image: per pixel and wavelength the running sums of the
 * volume layer's radiance samples (and their squares), of the volume's transparency and of
 * the first-collision depth. Render calls add samples; the estimate is always their mean. */
typedef struct sl_ref_accum {
  int width, height, n_wavelengths;
  long samples;        /* per pixel and wavelength so far */
  double *sum, *sum2;  /* [pixel][wavelength] */
  double *transparency_sum; /* [pixel][wavelength] */
  double *depth_sum, *depth_weight; /* [pixel] */
  double seconds;
} sl_ref_accum;

int sl_ref_accum_init(sl_ref_accum *a, int width, int height, int n_wavelengths, sl_error *err);
void sl_ref_accum_free(sl_ref_accum *a);

typedef struct sl_ref_budget {
  long samples;          /* samples per pixel and wavelength to add (> 0) */
  double max_seconds;    /* stop early after this wall time (0: no limit); whole passes only */
  void (*progress)(void *user, double fraction);
  void *progress_user;
} sl_ref_budget;

/* Adds budget->samples samples (in passes of one sample per pixel, so a time limit still leaves
 * every pixel with the same count) to acc for this camera. */
int sl_ref_render(const sl_ref_scene *scene, const sl_camera *camera, const sl_ref_budget *budget,
                  sl_ref_accum *acc, sl_error *err);

/* The estimate as the fast renderer's volume layer: premultiplied RGB of
 * V' = T_front V + (1 - T_vol) L_front, alpha = 1 - transparency, depth. With 3 wavelengths the
 * channels are taken as they are (650, 515, 440 nm = R, G, B); otherwise through sl_cie (white
 * balanced). stderr_rgb (3 floats per pixel, may be NULL) receives the standard error of each
 * channel's mean. */
int sl_ref_accum_image(const sl_ref_accum *acc, const sl_ref_medium *m, sl_image *layer, float *stderr_rgb,
                       sl_error *err);
/* The background the layer goes over: whole-ray sky plus the sun's disk (or the constant sky),
 * as sl_renderer_background, in the medium's channels mapped as above. */
int sl_ref_background(const sl_ref_scene *scene, const sl_camera *camera, sl_image *img, sl_error *err);

/* ---- point source (item 3) ------------------------------------------------------------------ */

typedef struct sl_ref_point_options {
  double optical_distance;  /* T = sigma R */
  double albedo;
  double g;                 /* Henyey-Greenstein asymmetry */
  int bins;                 /* in mu = cos(theta), uniform in theta from 0 to 180 degrees */
  long photons;
  unsigned long long seed;
  int bounded;              /* 1: medium only inside the sphere of radius R, vacuum outside (the
                               paper's milk bowl and its Monte Carlo check): a photon leaving the
                               sphere is scored and ends. 0: infinite medium. */
} sl_ref_point_options;

/* Radiance at distance R = T / sigma from an isotropic point source of unit power (radiant
 * intensity I0 = 1 / (4 pi)), with sigma = 1 (lengths in mean free paths), as a function of the
 * angle theta between the light's propagation direction and the outward radial direction
 * (theta = 0: looking straight at the source), averaged over each bin; the unscattered beam is
 * apart (a Dirac at theta = 0 carrying the irradiance e^{-T} / (4 pi T^2)). apsf[] is the same
 * in the normalisation of render/apsf (S of sl_apsf.h: L = I0 sigma^2 S / (4 pi), i.e.
 * S = 16 pi^2 L here). net_flux: outward power through the sphere (1 when nothing is absorbed). */
typedef struct sl_ref_point_result {
  int bins;
  double *theta_lo_deg, *theta_hi_deg, *radiance, *se_radiance, *apsf, *se_apsf;
  double direct_irradiance;
  double net_flux, se_net_flux;
  long photons;
  double seconds;
} sl_ref_point_result;

void sl_ref_point_options_defaults(sl_ref_point_options *o);
int sl_ref_point_source(const sl_ref_point_options *o, sl_ref_point_result *out, sl_error *err);
void sl_ref_point_result_free(sl_ref_point_result *r);

#ifdef __cplusplus
}
#endif
#endif
