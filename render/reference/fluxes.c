/* Domain-averaged reflectance, transmittance and absorptance of a collimated sun: the quantities
 * plane-parallel tables and the I3RC intercomparison publish. Photons enter uniformly over the
 * box's top face; absorption is scored where it happens (the weight times 1 - albedo at every
 * collision, the weight then carrying on times the albedo), so every photon
 * splits its unit energy exactly between the four tallies and energy balance is checked without
 * noise from the absorption. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "reference_internal.h"

/* Photons per chunk: sums are formed per chunk and chunks are added in order, so the result does
 * not depend on how chunks were spread over threads. */
#define CHUNK 2048
/* Weights below this are played for by Russian roulette; deep albedo-1 paths from ROULETTE_DEPTH. */
#define ROULETTE_WEIGHT 0.1
#define ROULETTE_DEPTH 100000
#define ROULETTE_DEEP_SURVIVAL 0.99

enum { T_R, T_T, T_A, T_S, T_DIRECT, T_SCAT, T_COUNT };

void sl_ref_flux_options_defaults(sl_ref_flux_options *o)
{
  memset(o, 0, sizeof *o);
  o->photons = 100000;
  o->seed = 1;
}

/* One photon's tallies. */
static void trace_photon(const sl_ref_medium *m, const sl_ref_flux_options *o, const double dir0[3], long index,
                         double tally[T_COUNT])
{
  const int w = o->wavelength_index;
  sl_ref_rng rng = sl_ref_rng_make(o->seed, (unsigned long long)index, (unsigned long long)w, 0x666c7578ull);
  double x[3] = {m->lo[0] + m->size[0] * sl_ref_rng_uniform(&rng), m->lo[1] + m->size[1] * sl_ref_rng_uniform(&rng),
                 m->hi[2]};
  double d[3] = {dir0[0], dir0[1], dir0[2]};
  double weight = 1.0;
  int scatterings = 0;
  for (int k = 0; k < T_COUNT; ++k) tally[k] = 0.0;
  for (;;) {
    const track_event ev = ref_track(m, w, x, d, &rng, NULL);
    if (ev == TRACK_TOP) {
      tally[T_R] += weight;
      break;
    }
    if (ev == TRACK_BOTTOM) {
      tally[T_T] += weight;
      if (scatterings == 0) tally[T_DIRECT] += weight;
      break;
    }
    if (ev == TRACK_SIDE) {
      tally[T_S] += weight;
      break;
    }
    const int c = ref_choose_component(m, w, x, &rng);
    const double albedo = m->albedo_eff[c][w];
    tally[T_A] += weight * (1.0 - albedo);
    weight *= albedo;
    ++scatterings;
    if (o->max_scatter > 0 && scatterings >= o->max_scatter) {
      tally[T_A] += weight;
      break;
    }
    double q = 1.0;
    if (weight < ROULETTE_WEIGHT) q = weight / ROULETTE_WEIGHT;
    else if (scatterings > ROULETTE_DEPTH) q = ROULETTE_DEEP_SURVIVAL;
    if (q < 1.0) {
      /* What roulette removes is neither reflected nor transmitted: it is scored as absorbed in
       * expectation only, so the weight of a survivor grows by 1/q. */
      if (sl_ref_rng_uniform(&rng) >= q) break;
      weight /= q;
    }
    double nd[3];
    weight *= sl_ref_phase_sample(m, c, w, d, &rng, nd);
    d[0] = nd[0], d[1] = nd[1], d[2] = nd[2];
  }
  tally[T_SCAT] = scatterings;
}

int sl_ref_fluxes(const sl_ref_medium *m, const sl_ref_flux_options *o, sl_ref_fluxes_result *out, sl_error *err)
{
  memset(out, 0, sizeof *out);
  if (!(o->sun_zenith_deg >= 0.0 && o->sun_zenith_deg < 90.0))
    return sl_fail(err, SL_ERR_ARG, "fluxes: sun zenith angle %g degrees is outside [0, 90)", o->sun_zenith_deg);
  if (o->wavelength_index < 0 || o->wavelength_index >= m->nw)
    return sl_fail(err, SL_ERR_ARG, "fluxes: wavelength index %d out of range (0..%d)", o->wavelength_index, m->nw - 1);
  if (o->photons < 2) return sl_fail(err, SL_ERR_ARG, "fluxes: %ld photons; at least 2 are needed", o->photons);
  const double th = o->sun_zenith_deg * SL_PI / 180.0, az = o->sun_azimuth_deg * SL_PI / 180.0;
  /* Propagation direction: away from a sun at that azimuth (clockwise from north = +y). */
  const double dir0[3] = {-sin(th) * sin(az), -sin(th) * cos(az), -cos(th)};
  const long nchunks = (o->photons + CHUNK - 1) / CHUNK;
  double *sums = calloc((size_t)nchunks * 2 * T_COUNT, sizeof(double));
  if (!sums) return sl_fail(err, SL_ERR_NOMEM, "fluxes: out of memory");
  const double t0 = omp_get_wtime();
#pragma omp parallel for schedule(dynamic, 1)
  for (long ch = 0; ch < nchunks; ++ch) {
    double *s = sums + (size_t)ch * 2 * T_COUNT;
    const long end = (ch + 1) * CHUNK < o->photons ? (ch + 1) * CHUNK : o->photons;
    for (long i = ch * CHUNK; i < end; ++i) {
      double tally[T_COUNT];
      trace_photon(m, o, dir0, i, tally);
      for (int k = 0; k < T_COUNT; ++k) {
        s[k] += tally[k];
        s[T_COUNT + k] += tally[k] * tally[k];
      }
    }
  }
  double total[2 * T_COUNT] = {0};
  for (long ch = 0; ch < nchunks; ++ch)
    for (int k = 0; k < 2 * T_COUNT; ++k) total[k] += sums[(size_t)ch * 2 * T_COUNT + k];
  free(sums);
  const double n = (double)o->photons;
  double mean[T_COUNT], se[T_COUNT];
  for (int k = 0; k < T_COUNT; ++k) {
    mean[k] = total[k] / n;
    const double var = fmax(0.0, total[T_COUNT + k] / n - mean[k] * mean[k]) * n / (n - 1.0);
    se[k] = sqrt(var / n);
  }
  out->reflectance = mean[T_R], out->se_reflectance = se[T_R];
  out->transmittance = mean[T_T], out->se_transmittance = se[T_T];
  out->absorptance = mean[T_A], out->se_absorptance = se[T_A];
  out->side = mean[T_S], out->se_side = se[T_S];
  out->direct_transmittance = mean[T_DIRECT];
  out->mean_scatterings = mean[T_SCAT];
  out->photons = o->photons;
  out->seconds = omp_get_wtime() - t0;
  return SL_OK;
}
