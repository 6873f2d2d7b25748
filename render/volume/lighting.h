/* The per-sample lighting of the slicer: the light-buffer step (Riley et al. 2004, eqs. 21-25)
 * and the eye-buffer phase term (eq. 26), for the multiple-scattering phase-function model and
 * the low-albedo model. Internal to render/volume. */
#ifndef SL_LIGHTING_H
#define SL_LIGHTING_H

#include "sl_optics.h"
#include "sl_renderer.h"

#define SL_MAX_FIELDS SL_VOLUME_MAX_FIELDS

typedef struct sl_light_model {
  sl_lighting mode;
  int nwl;                          /* wavelengths carried per sample */
  int nf;                           /* particle fields present in the volume */
  sl_particle field[SL_MAX_FIELDS]; /* each field's particle type */
  int slot[SL_MAX_FIELDS];          /* and its slot in the volume */
  double sigma_ext[SL_MAX_FIELDS];  /* m^2, mean over the wavelengths (extinction is grey) */
  double albedo_mean[SL_MAX_FIELDS];/* for the expected scattering count n (shared by all wavelengths) */
  double albedo[SL_MAX_FIELDS][SL_MAX_WAVELENGTHS];
  const sl_phase_table *table[SL_MAX_FIELDS][SL_MAX_WAVELENGTHS];
  /* log_product[j][c][k] = sum_{i=1..k} ln(albedo F_i): the log of eq. 24's product for the
   * first k scattering events, linear between integers; past N each event adds ln(albedo F_N). */
  double *log_product[SL_MAX_FIELDS][SL_MAX_WAVELENGTHS];
  int max_order[SL_MAX_FIELDS][SL_MAX_WAVELENGTHS]; /* N of each table */
  double xi;                        /* the user's back-scattering term (eq. 26), 1/sr */
} sl_light_model;

/* Builds the model for the fields present in v. optics may be NULL only for the low-albedo
 * model (Table 2's cross-sections, constant phase). */
int sl_light_model_init(sl_light_model *m, const sl_scene *scene, sl_error *err);
void sl_light_model_free(sl_light_model *m);

/* The model restricted to the fields in mask (bit j: m's field j), in m's order. For a sample whose
 * other fields are zero every function of sl_sample_physics.h gives bitwise the same result with
 * it (a zero field adds exact zeros to each sum, and its table terms are masked or skipped), over
 * fewer table reads. The tables stay m's: out is a view, valid while m is, and is not freed. */
void sl_light_model_subset(const sl_light_model *m, unsigned mask, sl_light_model *out);

/* ln of eq. 24's product of albedo * F_i over the scattering events from n to n + events of
 * field j at wavelength c, continuous in both (the "interpolating in n" that eq. 25 replaced). */
double sl_log_forward_product(const sl_light_model *m, int j, int c, double n, double events);

/* Intensity fraction left after a path `len` inside one slab for every wavelength, as
 * sl_log_light_step_at (sl_sample_physics.h) applies it, without updating anything. */
void sl_light_fraction(const sl_light_model *m, const float *beta, double n, double len, double *fraction);

/* Eq. 26's angular term (Ams_{n+1} + xi) per wavelength at the sample: the fields' Ams tables
 * weighted by their scattering coefficients (eq. 6), at the scattering angle given as the
 * table index and weight (hoisted per pixel), interpolated linearly in n. Times each field's
 * scattering coefficient: out[c] = sum_j beta_sca,j,c (Ams_{j,c}(n+1) + xi), m^-1 sr^-1. */
void sl_eye_phase(const sl_light_model *m, const float *beta, double n, int angle_index, double angle_weight,
                  double *out);

#endif
