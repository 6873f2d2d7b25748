/* An isotropic point source in an infinite homogeneous medium: the light field
 * the atmospheric point spread function of render/apsf models. By symmetry the radiance is the
 * same at every point of the sphere of radius R around the source, so instead of a detector at
 * one point (whose 1/r^2 estimator has infinite variance) every crossing of the whole sphere is
 * scored: the power crossing it in directions dOmega is 4 pi R^2 L |mu| dOmega, hence each
 * crossing adds weight / |mu| to the radiance of its angular bin (docs/REFERENCE.md). */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "sl_guards.h"
#include "reference_internal.h"
#include "sl_legendre.h"

#define CHUNK 1024
/* Low: a small-albedo medium must still carry its photons to a second scattering. */
#define ROULETTE_WEIGHT 1e-3

void sl_ref_point_options_defaults(sl_ref_point_options *o)
{
  memset(o, 0, sizeof *o);
  o->optical_distance = 2.0;
  o->albedo = 1.0;
  o->g = 0.0;
  o->bins = 90;
  o->photons = 100000;
  o->seed = 1;
}

void sl_ref_point_result_free(sl_ref_point_result *r)
{
  free(r->theta_lo_deg), free(r->theta_hi_deg), free(r->radiance), free(r->se_radiance), free(r->apsf),
      free(r->se_apsf);
  memset(r, 0, sizeof *r);
}

static double hg_sample_mu(double g, double u)
{
  if (fabs(g) < 1e-6) return 1.0 - 2.0 * u;
  const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
  const double m = (1.0 + g * g - s * s) / (2.0 * g);
  return sl_clamp_cosine(m);
}

/* One photon: adds weight/|mu| of every scattered crossing to bin_tally (touched bins listed in
 * touched[], count returned) and its net outward weight to *net. */
static int trace_photon(const sl_ref_point_options *o, long index, double *bin_tally, int *touched, double *net)
{
  const double R = o->optical_distance, R2 = R * R;
  const double dtheta = SL_PI / o->bins;
  const double transport_mfp = 1.0 / (1.0 - o->g * o->albedo);
  sl_ref_rng rng = sl_ref_rng_make(o->seed, (unsigned long long)index, 0x706f696e74ull, 0);
  double x[3] = {0.0, 0.0, 0.0}, d[3];
  {
    const double mu = 1.0 - 2.0 * sl_ref_rng_uniform(&rng), phi = 2.0 * SL_PI * sl_ref_rng_uniform(&rng);
    const double s = sl_safe_sqrt(1.0 - mu * mu);
    d[0] = s * cos(phi), d[1] = s * sin(phi), d[2] = mu;
  }
  double weight = 1.0;
  int scatterings = 0, ntouched = 0;
  *net = 0.0;
  for (;;) {
    const double s = -log(1.0 - sl_ref_rng_uniform(&rng)); /* sigma = 1: lengths in mean free paths */
    /* Crossings of the sphere |x + t d| = R for 0 < t <= s. */
    const double b = x[0] * d[0] + x[1] * d[1] + x[2] * d[2];
    const double c = x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - R2;
    const double disc = b * b - c;
    if (disc > 0.0) {
      const double root = sqrt(disc);
      const double ts[2] = {-b - root, -b + root};
      for (int k = 0; k < 2; ++k) {
        const double t = ts[k];
        if (!(t > 0.0 && t <= s)) continue;
        const double mu = (b + t) / R; /* d . (x + t d) / R */
        *net += mu > 0.0 ? weight : -weight;
        if (scatterings == 0) continue; /* the unscattered beam is the Dirac, kept apart */
        const double amu = fabs(mu) > 1e-12 ? fabs(mu) : 1e-12;
        int bin = (int)(acos(sl_clamp_cosine(mu)) / dtheta);
        bin = bin >= o->bins ? o->bins - 1 : bin;
        if (bin_tally[bin] == 0.0) touched[ntouched++] = bin;
        bin_tally[bin] += weight / amu;
      }
      /* Bounded sphere: the first outward crossing within this flight leaves the medium. */
      if (o->bounded && ts[1] > 0.0 && ts[1] <= s) return ntouched;
    }
    for (int a = 0; a < 3; ++a) x[a] += s * d[a];
    weight *= o->albedo;
    ++scatterings;
    /* Roulette: low weights, and photons far outside the sphere. They may come back, so they are
     * played for, not dropped; far enough (8 transport mean free paths) that returns are rare,
     * because a survivor's grown weight is what it brings back (roulette nearer made bins with
     * single heavy tallies). */
    const double r = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    double q = 1.0;
    if (weight < ROULETTE_WEIGHT) q = weight / ROULETTE_WEIGHT;
    if (r > R + 8.0 * transport_mfp) q *= 0.5;
    if (q < 1.0) {
      if (sl_ref_rng_uniform(&rng) >= q) break;
      weight /= q;
    }
    double nd[3];
    ref_rotate(d, hg_sample_mu(o->g, sl_ref_rng_uniform(&rng)), 2.0 * SL_PI * sl_ref_rng_uniform(&rng), nd);
    d[0] = nd[0], d[1] = nd[1], d[2] = nd[2];
    if (ntouched >= o->bins) break; /* cannot happen: each bin is listed once */
  }
  return ntouched;
}

int sl_ref_point_source(const sl_ref_point_options *o, sl_ref_point_result *out, sl_error *err)
{
  memset(out, 0, sizeof *out);
  if (!(o->optical_distance > 0.0) || !isfinite(o->optical_distance))
    return sl_fail(err, SL_ERR_ARG, "point source: optical distance %g must be positive", o->optical_distance);
  if (!(o->albedo >= 0.0 && o->albedo <= 1.0))
    return sl_fail(err, SL_ERR_ARG, "point source: albedo %g outside [0, 1]", o->albedo);
  if (!(fabs(o->g) < 1.0)) return sl_fail(err, SL_ERR_ARG, "point source: g = %g outside (-1, 1)", o->g);
  if (o->bins < 1 || o->bins > 100000) return sl_fail(err, SL_ERR_ARG, "point source: %d bins (1..100000)", o->bins);
  if (o->photons < 2) return sl_fail(err, SL_ERR_ARG, "point source: %ld photons; at least 2", o->photons);
  const int nb = o->bins;
  const long nchunks = (o->photons + CHUNK - 1) / CHUNK;
  const size_t stride = 2 * (size_t)nb + 2;
  double *sums = calloc((size_t)nchunks * stride, sizeof(double));
  out->theta_lo_deg = malloc(nb * sizeof(double));
  out->theta_hi_deg = malloc(nb * sizeof(double));
  out->radiance = malloc(nb * sizeof(double));
  out->se_radiance = malloc(nb * sizeof(double));
  out->apsf = malloc(nb * sizeof(double));
  out->se_apsf = malloc(nb * sizeof(double));
  int failed = !sums || !out->theta_lo_deg || !out->theta_hi_deg || !out->radiance || !out->se_radiance ||
               !out->apsf || !out->se_apsf;
  const double t0 = omp_get_wtime();
  if (!failed) {
#pragma omp parallel
    {
      /* Per-thread workspace, allocated once. */
      double *tally = calloc(nb, sizeof(double));
      int *touched = malloc(nb * sizeof(int));
      if (!tally || !touched) {
#pragma omp atomic write
        failed = 1;
      }
#pragma omp for schedule(dynamic, 1)
      for (long ch = 0; ch < nchunks; ++ch) {
        if (!tally || !touched) continue;
        double *s = sums + (size_t)ch * stride;
        const long end = (ch + 1) * CHUNK < o->photons ? (ch + 1) * CHUNK : o->photons;
        for (long i = ch * CHUNK; i < end; ++i) {
          double net;
          const int nt = trace_photon(o, i, tally, touched, &net);
          for (int k = 0; k < nt; ++k) {
            const int bin = touched[k];
            s[bin] += tally[bin];
            s[nb + bin] += tally[bin] * tally[bin];
            tally[bin] = 0.0;
          }
          s[2 * nb] += net;
          s[2 * nb + 1] += net * net;
        }
      }
      free(tally);
      free(touched);
    }
  }
  if (failed) {
    free(sums);
    sl_ref_point_result_free(out);
    return sl_fail(err, SL_ERR_NOMEM, "point source: out of memory for %d bins", nb);
  }
  double *total = calloc(stride, sizeof(double));
  if (!total) {
    free(sums);
    sl_ref_point_result_free(out);
    return sl_fail(err, SL_ERR_NOMEM, "point source: out of memory");
  }
  for (long ch = 0; ch < nchunks; ++ch)
    for (size_t k = 0; k < stride; ++k) total[k] += sums[(size_t)ch * stride + k];
  free(sums);
  const double n = (double)o->photons, R = o->optical_distance;
  const double area = 4.0 * SL_PI * R * R;
  for (int b = 0; b < nb; ++b) {
    const double lo = b * SL_PI / nb, hi = (b + 1) * SL_PI / nb;
    const double solid_angle = 2.0 * SL_PI * (cos(lo) - cos(hi));
    const double mean = total[b] / n, var = fmax(0.0, total[nb + b] / n - mean * mean) * n / (n - 1.0);
    const double scale = 1.0 / (area * solid_angle);
    out->theta_lo_deg[b] = lo * 180.0 / SL_PI;
    out->theta_hi_deg[b] = hi * 180.0 / SL_PI;
    out->radiance[b] = mean * scale;
    out->se_radiance[b] = sqrt(var / n) * scale;
    /* render/apsf's S: L = I0 sigma^2 S / (4 pi) with I0 = 1 / (4 pi), sigma = 1. */
    out->apsf[b] = 16.0 * SL_PI * SL_PI * out->radiance[b];
    out->se_apsf[b] = 16.0 * SL_PI * SL_PI * out->se_radiance[b];
  }
  const double net_mean = total[2 * nb] / n;
  out->net_flux = net_mean;
  out->se_net_flux = sqrt(fmax(0.0, total[2 * nb + 1] / n - net_mean * net_mean) / (n - 1.0));
  out->direct_irradiance = exp(-R) / area;
  out->bins = nb;
  out->photons = o->photons;
  out->seconds = omp_get_wtime() - t0;
  free(total);
  return SL_OK;
}
