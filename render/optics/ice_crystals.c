/* Randomly oriented hexagonal ice crystals by geometric-optics ray tracing, plus Fraunhofer
 * diffraction (the approach of Takano & Liou 1989, J. Atmos. Sci. 46, 3, and Macke et al.
 * 1996, without polarisation tracking: each interface uses the unpolarised Fresnel
 * reflectance (|r_s|^2 + |r_p|^2) / 2).
 *
 * Habits (aspect ratio = length L / diameter D across the corners):
 *   columns L/D = 3, plates L/D = 0.2, mixed in equal shares of geometric cross-section.
 * Refraction through 60-degree prism wedges (side faces) makes the 22-degree halo, through
 * 90-degree wedges (side and basal face) the 46-degree halo; with n falling towards red, red
 * deviates least and sits on the inner edge.
 * Energy: for a large non-absorbing particle Q_ext = 2, half diffracted, half refracted or
 * reflected (extinction paradox). Diffraction is that of a disk with the mean projected area
 * of the crystal (a convex body's mean projected area is a quarter of its surface, Cauchy).
 * Size: the equivalent radius of sl_particles.h (Table 2's cross-section), which only sets
 * the diffraction width and the (tiny) absorption. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sl_guards.h"
#include "optics_internal.h"
#include "sl_legendre.h"
#include "sl_refractive.h"

#define ICE_COLUMN_ASPECT 3.0
#define ICE_PLATE_ASPECT 0.2
#define ICE_MAX_EVENTS 64
#define ICE_SMOOTH_DEG 0.25 /* Gaussian smoothing of the ray histogram (1 sigma) */
#define ICE_CHUNKS 64       /* fixed work units: the result does not depend on thread count */

typedef struct rng {
  uint64_t s[4];
} rng;

static uint64_t splitmix64(uint64_t *x)
{
  uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

static void rng_seed(rng *r, uint64_t seed)
{
  for (int i = 0; i < 4; ++i) r->s[i] = splitmix64(&seed);
}

static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

/* xoshiro256** (Blackman & Vigna 2018) */
static double rng_uniform(rng *r)
{
  uint64_t *s = r->s;
  const uint64_t result = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = rotl(s[3], 45);
  return (double)(result >> 11) * 0x1.0p-53;
}

typedef struct prism {
  double n[8][3]; /* outward normals: 6 sides, top, bottom */
  double h[8];    /* plane offsets n.p = h */
  double area[8];
  double a, c;    /* corner radius, half length */
} prism;

static void prism_init(prism *P, double aspect)
{
  /* Scale-free: D = 2a = 1. */
  const double a = 0.5, c = 0.5 * aspect * 2.0 * a;
  P->a = a;
  P->c = c;
  for (int k = 0; k < 6; ++k) {
    const double phi = SL_PI / 6.0 + k * SL_PI / 3.0;
    P->n[k][0] = cos(phi);
    P->n[k][1] = sin(phi);
    P->n[k][2] = 0.0;
    P->h[k] = a * sqrt(3.0) / 2.0;
    P->area[k] = a * 2.0 * c;
  }
  for (int k = 6; k < 8; ++k) {
    P->n[k][0] = P->n[k][1] = 0.0;
    P->n[k][2] = k == 6 ? 1.0 : -1.0;
    P->h[k] = c;
    P->area[k] = 1.5 * sqrt(3.0) * a * a;
  }
}

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double fresnel_unpolarised(double n1, double n2, double cos_i, double cos_t)
{
  const double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  const double rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

static void point_on_face(const prism *P, int f, rng *r, double *p)
{
  if (f < 6) {
    const double *n = P->n[f];
    const double u = (rng_uniform(r) - 0.5) * P->a, z = (2.0 * rng_uniform(r) - 1.0) * P->c;
    p[0] = n[0] * P->h[f] - n[1] * u;
    p[1] = n[1] * P->h[f] + n[0] * u;
    p[2] = z;
    return;
  }
  const double ymax = P->a * sqrt(3.0) / 2.0;
  for (;;) {
    const double x = (2.0 * rng_uniform(r) - 1.0) * P->a, y = (2.0 * rng_uniform(r) - 1.0) * ymax;
    if (sqrt(3.0) * fabs(x) + fabs(y) <= sqrt(3.0) * P->a) {
      p[0] = x;
      p[1] = y;
      p[2] = P->n[f][2] * P->c;
      return;
    }
  }
}

/* One ray; returns the weight that leaves and its direction in out (weight 0 if lost). */
static double trace_ray(const prism *P, double m, double absorption_per_length, rng *r, double *d_in, double *out)
{
  /* Uniform incidence direction: a fixed sun on randomly oriented crystals. */
  const double cz = 2.0 * rng_uniform(r) - 1.0, phi = 2.0 * SL_PI * rng_uniform(r), sz = sl_safe_sqrt(1.0 - cz * cz);
  double d[3] = {sz * cos(phi), sz * sin(phi), cz};
  memcpy(d_in, d, sizeof d);
  /* Entry face with probability proportional to its projected area. */
  double proj[8], total = 0.0;
  for (int f = 0; f < 8; ++f) {
    const double c = -dot(P->n[f], d);
    proj[f] = c > 0.0 ? c * P->area[f] : 0.0;
    total += proj[f];
  }
  double pick = rng_uniform(r) * total;
  int f = 0;
  while (f < 7 && pick >= proj[f]) pick -= proj[f++];
  double p[3];
  point_on_face(P, f, r, p);
  const double *n = P->n[f];
  double cos_i = -dot(n, d);
  double sin_t2 = (1.0 - cos_i * cos_i) / (m * m);
  double cos_t = sl_safe_sqrt(1.0 - sin_t2);
  if (rng_uniform(r) < fresnel_unpolarised(1.0, m, cos_i, cos_t)) {
    for (int i = 0; i < 3; ++i) out[i] = d[i] + 2.0 * cos_i * n[i];
    return 1.0;
  }
  const double eta = 1.0 / m;
  for (int i = 0; i < 3; ++i) d[i] = eta * d[i] + (eta * cos_i - cos_t) * n[i];
  double weight = 1.0;
  for (int event = 0; event < ICE_MAX_EVENTS; ++event) {
    double t_exit = INFINITY;
    int exit_face = -1;
    for (int k = 0; k < 8; ++k) {
      const double dn = dot(P->n[k], d);
      if (dn <= 1e-12) continue;
      const double t = (P->h[k] - dot(P->n[k], p)) / dn;
      if (t < t_exit) {
        t_exit = t;
        exit_face = k;
      }
    }
    if (exit_face < 0) return 0.0;
    if (t_exit < 0.0) t_exit = 0.0;
    for (int i = 0; i < 3; ++i) p[i] += t_exit * d[i];
    weight *= exp(-absorption_per_length * t_exit);
    n = P->n[exit_face];
    cos_i = dot(n, d);
    sin_t2 = m * m * (1.0 - cos_i * cos_i);
    if (sin_t2 >= 1.0) { /* total internal reflection */
      for (int i = 0; i < 3; ++i) d[i] -= 2.0 * cos_i * n[i];
      continue;
    }
    cos_t = sqrt(1.0 - sin_t2);
    if (rng_uniform(r) < fresnel_unpolarised(m, 1.0, cos_i, cos_t)) {
      for (int i = 0; i < 3; ++i) d[i] -= 2.0 * cos_i * n[i];
      continue;
    }
    for (int i = 0; i < 3; ++i) out[i] = m * d[i] - (m * cos_i - cos_t) * n[i];
    return weight;
  }
  return 0.0; /* trapped: dropped and counted as absorbed (rare: < 1e-4 of the rays) */
}

/* J1 by its integral representation J1(z) = (1/pi) int_0^pi cos(tau - z sin tau) dtau; the
 * trapezoid rule is spectrally accurate for this periodic integrand with > z + 30 nodes. */
static double bessel_j1(double z)
{
  const int M = 32 + (int)(1.2 * z);
  double s = 0.0;
  for (int i = 0; i <= M; ++i) {
    const double tau = SL_PI * i / M, w = (i == 0 || i == M) ? 0.5 : 1.0;
    s += w * cos(tau - z * sin(tau));
  }
  return s / M;
}

/* Fraunhofer diffraction by a disk of radius a, P = (ka)^2/(4 pi) [2 J1(z)/z]^2, z = ka sin
 * theta, averaged over a grid cell (its rings are finer than the grid for mm-sized crystals;
 * beyond z = 60 the ring-averaged envelope 4/(pi z^3) is used). */
static double disk_diffraction_cell(double ka, double theta, double h)
{
  const int S = 16;
  double s = 0.0;
  for (int i = 0; i < S; ++i) {
    const double t = fmax(0.0, theta + h * ((i + 0.5) / S - 0.5));
    const double z = ka * sin(t);
    double v;
    if (t > 0.5 * SL_PI)
      v = 0.0; /* Fraunhofer diffraction is a forward (small-angle) phenomenon */
    else if (z < 1e-8)
      v = 1.0;
    else if (z > 60.0)
      v = 4.0 / (SL_PI * z * z * z);
    else {
      const double q = 2.0 * bessel_j1(z) / z;
      v = q * q;
    }
    s += v;
  }
  return ka * ka / (4.0 * SL_PI) * s / S;
}

int optics_ice_crystals(double wavelength_nm, const optics_grid *g, long rays, unsigned long long seed,
                        optics_raw_phase *out, sl_error *err)
{
  if (rays < ICE_CHUNKS) return sl_fail(err, SL_ERR_ARG, "optics: ice needs at least %d rays", ICE_CHUNKS);
  double m, m_im;
  sl_ice_index(wavelength_nm, &m, &m_im);
  const int J = g->n_angles;
  const double h = g->step_rad;
  const sl_particle_props *props = sl_particle_properties(SL_ICE);
  double *hist = calloc((size_t)ICE_CHUNKS * (size_t)(J + 2), sizeof(double));
  if (!hist) return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory for the ice histogram");

  prism habits[2];
  prism_init(&habits[0], ICE_COLUMN_ASPECT);
  prism_init(&habits[1], ICE_PLATE_ASPECT);
  /* Absorption per unit length in crystal units: the crystal's diameter D = 1 is scaled so
   * that its mean projected area matches the equivalent radius of sl_particles.h. */
  double scale[2];
  for (int k = 0; k < 2; ++k) {
    double surface = 0.0;
    for (int f = 0; f < 8; ++f) surface += habits[k].area[f];
    const double mean_projected = surface / 4.0; /* in crystal units */
    scale[k] = sqrt(SL_PI * props->radius_m * props->radius_m / mean_projected);
  }
  const double absorption = 4.0 * SL_PI * m_im / (wavelength_nm * 1e-9);
  const uint64_t wl_key = (uint64_t)llround(wavelength_nm * 1000.0);

#pragma omp parallel for schedule(dynamic, 1)
  for (int c = 0; c < ICE_CHUNKS; ++c) {
    double *hc = hist + (size_t)c * (size_t)(J + 2);
    rng r;
    rng_seed(&r, seed ^ (wl_key * 0x9e3779b97f4a7c15ULL) ^ ((uint64_t)c << 48));
    const long begin = rays * c / ICE_CHUNKS, end = rays * (c + 1) / ICE_CHUNKS;
    for (long i = begin; i < end; ++i) {
      for (int k = 0; k < 2; ++k) {
        double d_in[3], d_out[3];
        const double w = trace_ray(&habits[k], m, absorption * scale[k], &r, d_in, d_out);
        hc[J] += 1.0;
        if (w <= 0.0) continue;
        const double len = sqrt(dot(d_out, d_out));
        const double cs = sl_clamp_cosine(dot(d_in, d_out) / len);
        int bin = (int)lround(acos(cs) / h);
        if (bin > J - 1) bin = J - 1;
        hc[bin] += w;
        hc[J + 1] += w;
      }
    }
  }
  double *counts = calloc((size_t)J, sizeof(double));
  double *p_go = calloc((size_t)J, sizeof(double));
  if (!counts || !p_go) {
    free(hist), free(counts), free(p_go);
    return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory");
  }
  double launched = 0.0, left = 0.0;
  for (int c = 0; c < ICE_CHUNKS; ++c) {
    const double *hc = hist + (size_t)c * (size_t)(J + 2);
    for (int j = 0; j < J; ++j) counts[j] += hc[j];
    launched += hc[J];
    left += hc[J + 1];
  }
  free(hist);
  /* Density per steradian in each cell [theta_j - h/2, theta_j + h/2], normalised to the
   * energy that left the crystal; the forward cell (undeviated rays through parallel faces)
   * stays unsmoothed: the truncation turns it into the forward Dirac. */
  double *density = calloc((size_t)J, sizeof(double));
  if (!density) {
    free(counts), free(p_go);
    return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory");
  }
  for (int j = 0; j < J; ++j) {
    const double t0 = fmax(0.0, g->theta[j] - 0.5 * h), t1 = fmin(SL_PI, g->theta[j] + 0.5 * h);
    const double solid = 2.0 * SL_PI * (cos(t0) - cos(t1));
    density[j] = counts[j] / (left * solid);
  }
  /* Gaussian smoothing in theta, weighted by solid angle so that energy is conserved. */
  const int half_width = (int)ceil(4.0 * ICE_SMOOTH_DEG * SL_PI / 180.0 / h);
  const double sigma = ICE_SMOOTH_DEG * SL_PI / 180.0;
  p_go[0] = density[0];
  for (int j = 1; j < J; ++j) {
    double s = 0.0, ws = 0.0;
    for (int k = j - half_width; k <= j + half_width; ++k) {
      if (k < 1 || k >= J) continue;
      const double dt = (k - j) * h, w = exp(-0.5 * dt * dt / (sigma * sigma)) * sin(fmax(g->theta[k], 0.5 * h));
      s += w * density[k];
      ws += w;
    }
    p_go[j] = s / ws;
  }
  /* Diffraction: equal share of extinction with the geometric part. */
  const double ka = 2.0 * SL_PI / (wavelength_nm * 1e-9) * props->radius_m;
  const double go_share = left / launched; /* energy that left the crystals, per unit cross-section */
  for (int j = 0; j < J; ++j) {
    const double pd = disk_diffraction_cell(ka, g->theta[j], h);
    out->p[j] = (go_share * p_go[j] + pd) / (go_share + 1.0);
  }
  out->sigma_ext = props->sigma_ext_m2;
  out->albedo = (go_share + 1.0) / 2.0;
  out->asymmetry = NAN;
  free(counts), free(p_go), free(density);
  return SL_OK;
}
