/* Skylight on the volume (sky_light.c): the blue sky dome's light scattered by the cloud, which
 * Riley et al. 2004 leave as future work and without which a cloud's faces turned from the sun
 * are black. Built once per sun on a lattice over the content box, read by both eye passes.
 *
 * The approximation (docs/ACCURACY.md, "Skylight"): the diffuse radiance at x is the sky's
 * radiance averaged over directions, each direction weighted by the chance that light leaves x
 * that way, taken as the two-stream diffuse transmittance 1 / (1 + 3/4 tau_tr) over the transport
 * optical depth tau_tr = integral of beta (1 - omega g) from x to the box's edge (similarity
 * scaling); the eye then gathers it with an isotropic phase function:
 *   M(x) = sum_k Omega_k w_k L_k / sum_k Omega_k w_k,   in-scattered = beta_sca M.
 * Limits it meets exactly: a thin cloud scatters the sky's mean radiance (single scattering with
 * an isotropic phase function, tau omega L for a constant sky); a conservative cloud inside a
 * uniform sky is invisible (M = L everywhere); through a thick slab lit from one side M falls
 * linearly with depth, as the two-stream solution. Not modelled: the phase function's anisotropy
 * for skylight (the forward glow of a thin cloud against a bright horizon), absorption between
 * scatterings beyond the sample's own albedo.
 *
 * Diffuse sunlight (sl_scene.diffuse_sunlight) rides on the same lattice and closure. The sun is
 * one more source on the dome, of irradiance E (the sunlight at the sample's height through the
 * air): the whole sunlight's mean radiance at x is E w_sun / sum_k Omega_k w_k, with w_sun the
 * escape weight over the transport depth toward the sun. The light buffer already carries the
 * similarity-scaled beam, whose mean radiance is E e^-tau_sun / 4 pi; the lattice adds the rest,
 * the light the cloud has scattered out of the buffer's forward cone:
 *   D(x) = E [w_sun / sum_k Omega_k w_k - e^-tau_sun / 4 pi]+,   in-scattered = beta_sca D,
 * which vanishes for an isolated thin sample (w = 1 everywhere, sum 4 pi) and dominates inside
 * thick cloud and on faces in its own shadow. It replaces eq. 26's constant xi, which stood in for
 * that light. Not modelled: the diffuse light's anisotropy (its net flux away from the sun, which
 * brightens a slab's base seen from below beyond the mean radiance). */
#ifndef SL_SKY_LIGHT_H
#define SL_SKY_LIGHT_H

#include "sl_renderer.h"
#include "sl_status.h"
#include "sl_volume.h"

struct sl_renderer;

/* Whether scene sc takes the diffuse sunlight (never in the single-scattering low-albedo model). */
static inline int sl__diffuse_sunlight_on(const sl_scene *sc)
{
  return sc->diffuse_sunlight && sc->lighting != SL_LIGHTING_LOW_ALBEDO;
}
/* Whether scene sc's eye passes gather a diffuse lattice: the sky's light, the diffuse sunlight, or
 * both. */
static inline int sl__diffuse_lattice(const sl_scene *sc) { return sc->skylight || sl__diffuse_sunlight_on(sc); }

typedef struct sl__sky_light {
  int n[3];            /* lattice samples along each axis */
  double origin[3];    /* sample (0, 0, 0) */
  double spacing[3];   /* between samples (a multiple of the grid's) */
  sl_grid_view view;   /* the same lattice as the renderer's look-ups take it (no data) */
  int nwl, stride;     /* wavelengths; floats per sample (nwl + 1 rounded up to 4) */
  /* Per sample, x fastest: beta M per wavelength, then beta (the lattice's transport extinction
   * plus a floor, sky_light.c), so that a look-up interpolates M weighted by the extinction
   * (sky_light_gather.h); NULL: no diffuse light. */
  float *radiance;
} sl__sky_light;

/* Builds r->sky for r's sun, atmosphere and extinction (replaces what it held): the sky's light
 * where sl_scene.skylight asks, the diffuse sunlight where sl__diffuse_sunlight_on. Without the
 * sun up, radiance stays NULL (no sky). */
int sl__sky_light_build(struct sl_renderer *r, sl_error *err);
void sl__sky_light_free(sl__sky_light *s);

#endif
