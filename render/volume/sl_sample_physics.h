/* The per-sample physics of the volume renderer, written once in a subset of C11 that also
 * compiles as GLSL 1.50: the light step of Riley et al. 2004 (eqs. 21, 24, 25), the eye
 * gather's angular term (eq. 26) with its table look-ups, the closed-form single-scattering
 * moments of one eye segment, the eye march's step over the light volume, the light sweep's
 * look-up weights, and the resolve of the volume layer through the air in front (sec. 5). The CPU renderer (lighting.c, C) and the GPU pass (shaders/,
 * embedded text of this very file) call the same functions, so they cannot drift apart
 * (tests/gpu checks the embedded text against this file and the GLSL results against C).
 *
 * The subset: no pointers, no structs, no double-only library calls (sl_exp, sl_log, ... map to
 * the float or double versions), arrays only as fixed-size parameters (SL_IN_ARRAY /
 * SL_OUT_ARRAY), integer casts through SL_INT, no literal suffixes, no const locals (GLSL wants
 * constant initializers there), no GLSL keywords as names (in, out, sample, input, ...). The
 * particle model (tables, albedos, xi) is reached through accessor macros: fields of sl_light_model in C, uniforms and
 * texelFetch in GLSL (shaders/volume_model.glsl defines those before including this file). */
#ifndef SL_SAMPLE_PHYSICS_H
#define SL_SAMPLE_PHYSICS_H

#ifndef SL_GLSL
/* ---- C ---- */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "lighting.h"

#ifndef SL_REAL
#define SL_REAL double
#endif
#ifdef SL_REAL_IS_FLOAT
#define sl_exp expf
#define sl_log logf
#define sl_atan2 atan2f
#define sl_floor floorf
#define sl_ceil ceilf
#define sl_pow powf
#define sl_fabs fabsf
#define sl_fmin fminf
#define sl_fmax fmaxf
#define sl_expm1 expm1f
#else
#define sl_exp exp
#define sl_log log
#define sl_atan2 atan2
#define sl_floor floor
#define sl_ceil ceil
#define sl_pow pow
#define sl_fabs fabs
#define sl_fmin fmin
#define sl_fmax fmax
#define sl_expm1 expm1
#endif
/* Always inlined: the renderer's passes are compiled once per field and wavelength count
 * (renderer.c), and the counts reach these loops as constants only through inlining. */
#define SL_INLINE static inline __attribute__((always_inline))
#define SL_UNROLL _Pragma("GCC unroll 16")
#define SL_INT(x) ((int)(x))
#define SL_MIN_INT(a, b) ((a) < (b) ? (a) : (b))
#define SL_TO_REAL(x) ((SL_REAL)(x))
#define SL_IN_ARRAY(T, name, n) const T name[n]
#define SL_OUT_ARRAY(T, name, n) T name[n]
#define SL_IN_VEC3(name) const SL_REAL name[3]
/* The model: one pointer in C, uniforms in GLSL. In C the field and wavelength counts travel
 * beside it (m->nf, m->nwl, or constants where the caller is specialised for them). */
#define SL_UNUSED __attribute__((unused))
#define SL_MODEL_PARAM \
  const sl_light_model *m, SL_UNUSED const int sl_mode, SL_UNUSED const int sl_nf, SL_UNUSED const int sl_nwl,
#define SL_MODEL_ARG m, sl_mode, sl_nf, sl_nwl,
#define SL_NF (sl_nf)
#define SL_NWL (sl_nwl)
#define SL_MODE (sl_mode)
#define SL_XI (m->xi)
#define SL_ALBEDO_MEAN(j) (m->albedo_mean[j])
#define SL_ALBEDO(j, c) (m->albedo[j][c])
#define SL_MAX_ORDER(j, c) (m->max_order[j][c])
#define SL_LOG_PRODUCT(j, c, k) (m->log_product[j][c][k])
#define SL_FORWARD(j, c, k) (m->table[j][c]->forward[k])
/* An int index (orders x angles is far below 2^31), so that a vectorised loop gathers over 32-bit
 * offsets. */
#define SL_AMS(j, c, k, i) (m->table[j][c]->ams[(k) * m->table[j][c]->n_angles + (i)])
/* Ams at angle rows i and i + 1 into lo and hi (as SL_AMS twice): one 8-byte load of the two
 * neighbouring floats, which a loop over samples vectorises as one 64-bit gather where two reads
 * are two 32-bit gathers (the eye pass's table look-ups are mostly these gathers). */
#define SL_AMS_PAIR(j, c, k, i, lo, hi) sl__float_pair(&SL_AMS(j, c, k, i), &(lo), &(hi))
#if __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "sl__float_pair takes the lower address as the low half"
#endif
static inline __attribute__((always_inline)) void sl__float_pair(const float *p, SL_REAL *lo, SL_REAL *hi)
{
  uint64_t bits;
  memcpy(&bits, p, sizeof bits);
  const uint32_t b0 = (uint32_t)bits, b1 = (uint32_t)(bits >> 32);
  float f0, f1;
  memcpy(&f0, &b0, sizeof f0);
  memcpy(&f1, &b1, sizeof f1);
  *lo = f0, *hi = f1;
}
#define SL_MODE_LOW_ALBEDO SL_LIGHTING_LOW_ALBEDO
#define SL_MODE_EQ25 SL_LIGHTING_MULTIPLE_EQ25
#define SL_PI 3.14159265358979323846
#else
/* ---- GLSL: the includer defines SL_MAX_FIELDS, SL_MAX_WAVELENGTHS and the model accessors
 * (SL_NF ... SL_AMS, SL_MODE_*) first. ---- */
#define SL_REAL float
#define sl_exp exp
#define sl_log log
#define sl_atan2 atan
#define sl_floor floor
#define sl_ceil ceil
#define sl_pow pow
#define sl_fabs abs
#define sl_fmin min
#define sl_fmax max
/* GLSL has no expm1, and exp(x) - 1 in float keeps only ~6e-8 / |x| of relative accuracy: below
 * |x| = 1e-3 the series to x^3 (truncation below 5e-14). */
float sl_expm1(float x) { return abs(x) < 1e-3 ? x * (1.0 + x * (0.5 + x * (1.0 / 6.0))) : exp(x) - 1.0; }
#define SL_INLINE
#define SL_UNROLL
#define SL_INT(x) int(x)
#define SL_MIN_INT(a, b) min(a, b)
#define SL_TO_REAL(x) float(x)
#define SL_IN_ARRAY(T, name, n) in T name[n]
#define SL_OUT_ARRAY(T, name, n) out T name[n]
#define SL_IN_VEC3(name) in vec3 name
#define SL_MODEL_PARAM
#define SL_MODEL_ARG
#define SL_PI 3.14159265358979323846
#endif

/* Scattering events per metre of the particle mix: sum_j albedo_j beta_j, the rate at which the
 * expected scattering count grows along the sunlight (eq. 21). */
SL_INLINE SL_REAL sl_scattering_per_metre(SL_MODEL_PARAM SL_IN_ARRAY(float, beta, SL_MAX_FIELDS))
{
  SL_REAL total = 0.0;
  SL_UNROLL
  for (int j = 0; j < SL_NF; ++j) total += SL_ALBEDO_MEAN(j) * beta[j];
  return total;
}

/* Riley et al. 2004, eq. 21: the expected scattering count after a path len through the sample. */
SL_INLINE SL_REAL sl_expected_scatter_count(SL_MODEL_PARAM SL_IN_ARRAY(float, beta, SL_MAX_FIELDS), SL_REAL n,
                                            SL_REAL len)
{
  return n + sl_scattering_per_metre(SL_MODEL_ARG beta) * len;
}

/* sum_{i=1..x} ln(albedo F_i) of field j at wavelength c, for a real number of events x >= 0:
 * linear between integers; past the table's last order N each event adds ln(albedo F_N), which
 * is the line through orders N - 1 and N carried on, so one interpolation serves both (no
 * branch: the per-sample loops over fields and wavelengths stay straight). */
SL_INLINE SL_REAL sl_log_product_at(SL_MODEL_PARAM int j, int c, SL_REAL x)
{
  int k = SL_MIN_INT(SL_INT(x), SL_MAX_ORDER(j, c) - 1);
  SL_REAL lo = SL_LOG_PRODUCT(j, c, k);
  return lo + (x - SL_TO_REAL(k)) * (SL_LOG_PRODUCT(j, c, k + 1) - lo);
}

/* Riley et al. 2004, eq. 24: ln prod_{i=n+1}^{n+events} albedo F_i of field j at wavelength c,
 * continuous in n and events (the interpolation in n that eq. 25 replaced). */
SL_INLINE SL_REAL sl_log_forward_product_at(SL_MODEL_PARAM int j, int c, SL_REAL n, SL_REAL events)
{
  return sl_log_product_at(SL_MODEL_ARG j, c, n + events) - sl_log_product_at(SL_MODEL_ARG j, c, n);
}

/* The fraction of the light per wavelength kept in the forward beam after a path len through a
 * sample of extinction beta[j] per field (m^-1) that the light reaches having scattered n times
 * on average, as its logarithm log_kept[c].
 *
 * Riley et al. 2004, eq. 24, prints T + (1 - T) prod_{i=n+1}^{n+m} albedo F_i with T the
 * slab's transparency and m its expected number of scattering events: the scattered light
 * passes through as many events as the slab holds on average. In a thin slab that product is
 * 1 - O(m), so the slab keeps 1 - O(tau^2) of the light: the first-order loss vanishes, and
 * the transport depends on how thick the slabs are, tending to no attenuation at all as they
 * thin (a 10-deep cloud with albedo F = 0.9 keeps 0.35 of the light in one slab, 0.52 in ten,
 * 0.90 in a hundred; test_light_step). Averaged over the slab's random number K of
 * interactions (Poisson, mean tau = ext len), each keeping the light with albedo F, the kept
 * fraction is E[(albedo F)^K] = exp(-tau (1 - albedo F)): the same for one slab as for two
 * halves, 1 - tau (1 - albedo F) when thin (the unscattered light plus the once-scattered light
 * kept forward) and within a few per cent of the printed form in the thick slabs the paper
 * used. Here albedo F is the geometric mean per event over the slab's events from n on
 * (continuous in n: the interpolation that eq. 25 replaced), each field
 * weighted by its share of the events (exact for one field; a mix along a path has no exact
 * per-field split). Eq. 25 (`--lighting eq25`) stays as printed, the paper's GPU workaround;
 * the low-albedo model keeps the plain transparency. The logarithm is finite (at most the
 * optical depth), so the CPU's eye pass takes a whole batch's exponentials in one loop. */
SL_INLINE void sl_light_fraction_exponents(SL_MODEL_PARAM SL_IN_ARRAY(float, beta, SL_MAX_FIELDS), SL_REAL n,
                                           SL_REAL len, SL_OUT_ARRAY(SL_REAL, log_kept, SL_MAX_WAVELENGTHS))
{
  SL_REAL ext = 0.0;
  SL_UNROLL
  for (int j = 0; j < SL_NF; ++j) ext += beta[j];
  SL_REAL depth = ext * len;
  if (SL_MODE == SL_MODE_LOW_ALBEDO) {
    SL_UNROLL
    for (int c = 0; c < SL_NWL; ++c) log_kept[c] = -depth;
    return;
  }
  SL_REAL rate = sl_scattering_per_metre(SL_MODEL_ARG beta);
  SL_REAL events = rate * len;
  SL_REAL per_event = rate > 0.0 ? 1.0 / rate : 0.0;
  /* Without a scatterer here the light keeps only the transparency. A selection rather than an
   * early return, with every table look-up unconditional, so that the CPU's loop over a slice's
   * samples vectorises (the mode is the same for all samples: the CPU compiles a loop per mode). */
  bool scatters = ext > 0.0 && rate > 0.0;
  /* Each field's share of the events, albedo_j beta_j / rate (the same at every wavelength). */
  SL_REAL share[SL_MAX_FIELDS];
  SL_UNROLL
  for (int j = 0; j < SL_MAX_FIELDS; ++j) share[j] = 0.0;
  SL_UNROLL
  for (int j = 0; j < SL_NF; ++j) share[j] = SL_ALBEDO_MEAN(j) * beta[j] * per_event;
  /* Eq. 24's log product per event is taken over at least a hundredth of an event, so that a
   * thin slab gets the slope at n without dividing a difference of nearly equal sums by nearly
   * zero (in float, on the GPU, that difference would be all rounding). */
  SL_REAL span = events > 0.01 ? events : 0.01;
  SL_REAL per_span = 1.0 / span;
  SL_UNROLL
  for (int c = 0; c < SL_NWL; ++c) {
    SL_REAL log_fraction = -depth;
    if (SL_MODE == SL_MODE_EQ25) {
      /* Riley et al. 2004, eq. 25 as printed: the worst-case order's forward fraction to the
       * power of the slab's scattering count. */
      int order = SL_INT(sl_floor(n + 1.0 + events));
      SL_REAL f = 0.0, a = 0.0;
      SL_UNROLL
      for (int j = 0; j < SL_NF; ++j) {
        int N = SL_MAX_ORDER(j, c);
        f += share[j] * SL_FORWARD(j, c, order < 0 ? 0 : (order > N ? N : order));
        a += share[j] * SL_ALBEDO(j, c);
      }
      SL_REAL transparency = sl_exp(-depth);
      SL_REAL fraction = transparency + (1.0 - transparency) * (a * f > 0.0 ? sl_exp(events * sl_log(a * f)) : 0.0);
      log_fraction = fraction > 0.0 ? sl_log(fraction) : -depth;
    } else {
      SL_REAL log_product = 0.0;
      SL_UNROLL
      for (int j = 0; j < SL_NF; ++j) {
        /* A field without a share adds nothing (its product may be -inf where F_i is 0). */
        SL_REAL term = share[j] * sl_log_forward_product_at(SL_MODEL_ARG j, c, n, span);
        log_product += share[j] > 0.0 ? term : 0.0;
      }
      log_fraction = -depth * (1.0 - sl_exp(log_product * per_span));
    }
    log_kept[c] = scatters ? log_fraction : -depth;
  }
}

/* The fraction of the light per wavelength left after a path len through the sample (eq. 24 as
 * above, eq. 25, or the transparency). */
SL_INLINE void sl_light_fraction_at(SL_MODEL_PARAM SL_IN_ARRAY(float, beta, SL_MAX_FIELDS), SL_REAL n, SL_REAL len,
                                    SL_OUT_ARRAY(SL_REAL, fraction, SL_MAX_WAVELENGTHS))
{
  SL_REAL log_kept[SL_MAX_WAVELENGTHS];
  sl_light_fraction_exponents(SL_MODEL_ARG beta, n, len, log_kept);
  SL_UNROLL
  for (int c = 0; c < SL_NWL; ++c) fraction[c] = sl_exp(log_kept[c]);
}

/* Field j's Ams table at wavelength c and order k (its last order where k is past it) at the
 * scattering angle of grid row angle_index and weight angle_weight, linear between the rows. */
SL_INLINE SL_REAL sl_ams_at_angle(SL_MODEL_PARAM int j, int c, int k, int angle_index, SL_REAL angle_weight)
{
  int N = SL_MAX_ORDER(j, c);
  int kk = k > N ? N : k;
  SL_REAL a0, a1;
  SL_AMS_PAIR(j, c, kk, angle_index, a0, a1);
  return a0 + angle_weight * (a1 - a0);
}

/* Field j's share of eq. 26's angular term at wavelength c (below): its scattering coefficient
 * times Ams_{n+1} plus xi, Ams linear in the order between its values ams_k and ams_k1 at the
 * orders around n + 1 (fraction f past the lower). */
SL_INLINE SL_REAL sl_eye_phase_field(SL_MODEL_PARAM int j, int c, SL_REAL beta, SL_REAL f, SL_REAL ams_k,
                                     SL_REAL ams_k1)
{
  return SL_ALBEDO(j, c) * beta * ((1.0 - f) * ams_k + f * ams_k1 + SL_XI);
}

/* Riley et al. 2004, eq. 26's angular term per wavelength at a sample whose light has scattered
 * n times: the fields' Ams_{n+1} (linear in n) plus xi, weighted by each field's scattering
 * coefficient (eq. 6): result[c] = sum_j albedo_j,c beta_j (Ams_j,c(n+1) + xi), m^-1 sr^-1. The
 * scattering angle comes as the angular grid's index and weight (fixed along a ray). */
SL_INLINE void sl_eye_phase_at(SL_MODEL_PARAM SL_IN_ARRAY(float, beta, SL_MAX_FIELDS), SL_REAL n, int angle_index,
                               SL_REAL angle_weight, SL_OUT_ARRAY(SL_REAL, result, SL_MAX_WAVELENGTHS))
{
  if (SL_MODE == SL_MODE_LOW_ALBEDO) {
    SL_REAL isotropic = sl_scattering_per_metre(SL_MODEL_ARG beta) / (4.0 * SL_PI);
    SL_UNROLL
    for (int c = 0; c < SL_NWL; ++c) result[c] = isotropic;
    return;
  }
  /* The event that sends the light to the eye is the (n+1)-th. */
  SL_REAL order = n + 1.0;
  int k = SL_INT(sl_floor(order));
  SL_REAL f = order - SL_TO_REAL(k);
  SL_UNROLL
  for (int c = 0; c < SL_NWL; ++c) {
    SL_REAL sum = 0.0;
    SL_UNROLL
    for (int j = 0; j < SL_NF; ++j) {
      SL_REAL a0 = sl_ams_at_angle(SL_MODEL_ARG j, c, k, angle_index, angle_weight);
      SL_REAL a1 = sl_ams_at_angle(SL_MODEL_ARG j, c, k + 1, angle_index, angle_weight);
      /* A selection, not a skip, so that the CPU's loop over a batch's samples vectorises; a
       * field absent here adds nothing (its tables are finite, and read in bounds). */
      SL_REAL term = sl_eye_phase_field(SL_MODEL_ARG j, c, beta[j], f, a0, a1);
      sum += beta[j] > 0.0 ? term : 0.0;
    }
    result[c] = sum;
  }
}

/* The phase tables' grid position of the scattering angle between the sunlight's direction and a
 * view direction, from the length of their cross product and their dot product (unit vectors):
 * theta = atan2(|sun x d|, sun . d) keeps its digits next to 0 and 180 degrees, where the acos of
 * the dot product loses them (float most of all), times the grid's inverse step. */
SL_INLINE SL_REAL sl_angle_grid_position(SL_REAL cross_length, SL_REAL cosine, SL_REAL inv_step)
{
  return sl_atan2(cross_length, cosine) * inv_step;
}

/* The table row at or below grid position u, the last but one at most, and the weight of the row
 * above it (at most 1). */
SL_INLINE int sl_angle_row(SL_REAL u, int n_angles) { return SL_MIN_INT(SL_INT(u), n_angles - 2); }
SL_INLINE SL_REAL sl_angle_weight(SL_REAL u, int row)
{
  SL_REAL w = u - SL_TO_REAL(row);
  return w > 1.0 ? 1.0 : w;
}

/* Steps of max_step that cover a ray's span through the volume, the last one shortened to end at
 * the span's end (sl_march_step_end). A span of a whole number of steps (a ray entering and
 * leaving through opposite faces of the box, whose size is a whole number of grid cells) must not
 * gain a sliver of a step from the last bit of rounding, which would differ between float and
 * double. */
SL_INLINE int sl_march_steps(SL_REAL span, SL_REAL max_step)
{
  return SL_INT(sl_ceil(span / max_step - 1e-3));
}

/* Where the march's step that ends at step index `end_step` ends along a ray marched from t0 to t1
 * in nsteps steps of dt: on the lattice t0 + k dt, the last at t1. The steps are not stretched to
 * fit the span: a stretched step moves every sample wherever the step count changes from one
 * pixel to the next (by up to half a step halfway along), and on a thick face, whose surface lies
 * within a step, that drew speckle (tests/volume/test_march_streaks.c). */
SL_INLINE SL_REAL sl_march_step_end(SL_REAL t0, SL_REAL dt, SL_REAL t1, int end_step, int nsteps)
{
  return end_step >= nsteps ? t1 : t0 + SL_TO_REAL(end_step) * dt;
}

/* One of sl_segment_scatter_moments_exp's two moments (which = 0 or 1) times a scale s, given s
 * and s e with e = exp(-beta rate len): the caller forms s e as one exponential, so that a rate far
 * below 0 (light that grows by hundreds of e-folds along the segment, from a shadowed near end to
 * a lit far one) does not overflow e while s underflows to 0 (inf times 0: NaN pixels, seen in
 * thick slabs at a low sun). As a value: a loop over samples that stores a moment through an
 * array does not vectorise (GCC 12 will not if-convert it), one that takes the values does. Near
 * x = beta rate len = 0 the Taylor series to x^6 (truncation below 2e-9): the closed form of the
 * second moment cancels to second order there, which in float costs 1e-3 of relative accuracy
 * already at x = 1e-2. Both forms are computed, each where it stays finite (the series at 0 and
 * the closed form at 1 where the other is used), and blended by a 0/1 weight: no branch, so that
 * the CPU's batch loop vectorises. */
SL_INLINE SL_REAL sl_segment_scatter_moment_scaled(int which, SL_REAL beta, SL_REAL len, SL_REAL rate, SL_REAL s,
                                                   SL_REAL se)
{
  SL_REAL x = beta * rate * len;
  SL_REAL taylor = x * x < 0.0625 ? 1.0 : 0.0;
  SL_REAL xt = x * taylor;
  SL_REAL xs = x + taylor * (1.0 - x);
  SL_REAL series, closed;
  if (which == 0) {
    series = 1.0 - xt * (1.0 / 2.0 - xt * (1.0 / 6.0 - xt * (1.0 / 24.0 - xt * (1.0 / 120.0 -
                                                                   xt * (1.0 / 720.0 - xt * (1.0 / 5040.0))))));
    closed = (s - se) / xs;
  } else {
    series = 0.5 - xt * (1.0 / 3.0 - xt * (1.0 / 8.0 - xt * (1.0 / 30.0 - xt * (1.0 / 144.0 -
                                                                   xt * (1.0 / 840.0 - xt * (1.0 / 5760.0))))));
    closed = (s - se * (1.0 + xs)) / (xs * xs);
  }
  return beta * len * (taylor * s * series + (1.0 - taylor) * closed);
}

/* The moment itself (s = 1): e = exp(-beta rate len) given. */
SL_INLINE SL_REAL sl_segment_scatter_moment_exp(int which, SL_REAL beta, SL_REAL len, SL_REAL rate, SL_REAL e)
{
  return sl_segment_scatter_moment_scaled(which, beta, len, rate, 1.0, e);
}

/* Single scattering over one eye segment of length len with constant extinction beta, when the
 * light reaching the point u metres along it is attenuated by exp(-beta (rate - 1) u) on top of
 * the eye's exp(-beta u): result[0] = beta int_0^len exp(-beta rate u) du and
 * result[1] = (beta / len) int_0^len u exp(-beta rate u) du, the weights of a light value that is
 * constant along the segment and one that grows linearly from 0 to 1. rate may be <= 0. The
 * caller gives e = exp(-beta rate len) (the CPU takes a sample's exponentials for every
 * wavelength at once); the Taylor branch does not use it. */
SL_INLINE void sl_segment_scatter_moments_exp(SL_REAL beta, SL_REAL len, SL_REAL rate, SL_REAL e,
                                               SL_OUT_ARRAY(SL_REAL, result, 2))
{
  result[0] = sl_segment_scatter_moment_exp(0, beta, len, rate, e);
  result[1] = sl_segment_scatter_moment_exp(1, beta, len, rate, e);
}

/* sl_segment_scatter_moments_exp, taking the exponential itself. */
SL_INLINE void sl_segment_scatter_moments(SL_REAL beta, SL_REAL len, SL_REAL rate, SL_OUT_ARRAY(SL_REAL, result, 2))
{
  sl_segment_scatter_moments_exp(beta, len, rate, sl_exp(-beta * rate * len), result);
}

/* ---- A thick eye segment's parts in optical depth (the slicer's eye_batch.h, the march's
 * light_volume_march.c and shaders/volume_eye.glsl) ---- */

/* A segment is taken whole where it is optically thin (below SL_PART_THIN at its middle and at
 * its far end; a march's step: at the next step's middle), else in parts whose bounds lie at
 * optical depths 1/8, 1/4, 1/2 and 1 from where the medium starts in it (optical depth
 * SL_PART_CLEAR), then the rest, found on a profile of its total extinction at SL_PART_PROFILE
 * equal steps. A thick segment's light comes from its first mean free path, and a
 * cloud's surface is a ramp of extinction within one grid cell: parts fixed in length put that
 * surface at a different place in its part wherever the samples fall, which draws bands along
 * slices and streaks across a march's rays; parts fixed in optical depth follow the surface.
 * Behind a front already below SL_PART_DEEP of transparency a thick segment is one part, as a
 * thin one is (what lies there adds less than that). */
#define SL_PART_THIN 0.0625
#define SL_PART_DEPTH 0.125
#define SL_PARTS_MAX 5
#define SL_PART_PROFILE 8
#define SL_PART_CLEAR 1e-4
#define SL_PART_DEEP 1e-3

/* The parts of a segment from t_near to t_far profiled at SL_PART_PROFILE steps of `step` (tau:
 * the optical depth from t_near at each profile point, tau[SL_PART_PROFILE] > 0 the whole): their
 * bounds along the ray t_at[0..parts] and in optical depth tau_at[0..parts] (tau piecewise linear
 * between the profile's points); returns parts. The first part starts at the profile point before
 * the medium does (a clear stretch before it belongs to no part); the last takes the segment's
 * clear end too and ends at t_far exactly, so that the next segment's light look-up is shared. */
SL_INLINE int sl_segment_parts(SL_IN_ARRAY(SL_REAL, tau, SL_PART_PROFILE + 1), SL_REAL t_near, SL_REAL step,
                               SL_REAL t_far, SL_OUT_ARRAY(SL_REAL, t_at, SL_PARTS_MAX + 1),
                               SL_OUT_ARRAY(SL_REAL, tau_at, SL_PARTS_MAX + 1))
{
  SL_REAL depth = tau[SL_PART_PROFILE];
  int parts = 0, k = 0;
  while (k < SL_PART_PROFILE - 1 && tau[k + 1] < SL_PART_CLEAR) k++;
  t_at[0] = t_near + SL_TO_REAL(k) * step;
  tau_at[0] = 0.0;
  SL_REAL bound = SL_PART_DEPTH;
  while (parts < SL_PARTS_MAX && tau_at[parts] < depth) {
    SL_REAL want = parts == SL_PARTS_MAX - 1 || bound > depth ? depth : bound;
    while (k < SL_PART_PROFILE - 1 && tau[k + 1] < want) k++;
    SL_REAL span = tau[k + 1] - tau[k];
    SL_REAL frac = span > 0.0 ? sl_fmin(sl_fmax((want - tau[k]) / span, 0.0), 1.0) : 1.0;
    parts++;
    t_at[parts] = t_near + (SL_TO_REAL(k) + frac) * step;
    tau_at[parts] = want;
    bound *= 2.0;
  }
  t_at[parts] = t_far;
  return parts;
}

/* The profile step whose fields stand for the part whose optical depth's middle is tau_mid: the
 * first that reaches it and holds medium (a point inside the medium, where the part's middle may
 * lie in clear air). The part takes that step's mix of fields, scaled to its own mean extinction. */
SL_INLINE int sl_segment_part_mix_step(SL_IN_ARRAY(SL_REAL, tau, SL_PART_PROFILE + 1),
                                       SL_IN_ARRAY(SL_REAL, step_beta, SL_PART_PROFILE), SL_REAL tau_mid)
{
  int k = 0;
  while (k < SL_PART_PROFILE - 1 && !(tau[k + 1] >= tau_mid && step_beta[k] > 0.0)) k++;
  return k;
}

/* ---- The eye march over the light volume (light_volume_march.c, shaders/volume_eye.glsl) ---- */

/* The longest step along a ray of direction d (unit) that stays within 1/samples of a grid cell
 * (spacing per axis) along every axis: the light volume holds the light at the grid's resolution,
 * and a finer march keeps optically thick surfaces from speckling. */
SL_INLINE SL_REAL sl_march_max_step(SL_IN_VEC3(spacing), SL_IN_VEC3(d), SL_REAL samples)
{
  SL_REAL dt = 3.0e38;
  for (int a = 0; a < 3; ++a)
    if (sl_fabs(d[a]) > 1e-12) dt = sl_fmin(dt, spacing[a] / (samples * sl_fabs(d[a])));
  return dt;
}

/* The opacity of an eye step through extinction beta (m^-1) over dt (m), 1 - exp(-beta dt), with
 * no cancellation in a thin step where the library has expm1; 1 minus it is the step's
 * transparency and the exponential the segment moments take (sl_segment_scatter_moments_exp). */
SL_INLINE SL_REAL sl_step_opacity(SL_REAL beta, SL_REAL dt) { return -sl_expm1(-beta * dt); }

/* The light an eye step sends toward the eye at one wavelength per unit of sunlight reaching it
 * (eq. 26 integrated over the step in closed form): the light state linear from l0 to l1 between
 * the step's ends, weighted by the step's moments m0 and m1 (sl_segment_scatter_moments at rate 1:
 * no attenuation inside the step beyond the eye's), times the angular term phase (m^-1 sr^-1,
 * sl_eye_phase_at) per metre of extinction (inv_beta = 1 / beta: the moments carry beta). */
SL_INLINE SL_REAL sl_march_step_light(SL_REAL l0, SL_REAL l1, SL_REAL m0, SL_REAL m1, SL_REAL phase, SL_REAL inv_beta)
{
  return (l0 * m0 + (l1 - l0) * m1) * phase * inv_beta;
}

/* The skylight a step of opacity `opacity` scatters toward the eye at wavelength c from the diffuse
 * sky radiance `sky` there (render/volume/sky_light.h: isotropic phase function): the opacity times
 * the fields' single-scattering albedo sum_j beta_j omega_jc / beta (inv_beta = 1 / beta) times the
 * radiance, the integral of beta_sca e^(-beta t) sky over the step for fields and sky constant
 * across it. */
SL_INLINE SL_REAL sl_sky_step_light(SL_MODEL_PARAM SL_IN_ARRAY(float, beta, SL_MAX_FIELDS), int c, SL_REAL opacity,
                                    SL_REAL inv_beta, SL_REAL sky)
{
  SL_REAL scattering = 0.0;
  SL_UNROLL
  for (int j = 0; j < SL_NF; ++j) scattering += beta[j] * SL_ALBEDO(j, c);
  return opacity * scattering * inv_beta * sky;
}

/* ---- The light volume's sweep (light_volume_sweep.c, shaders/volume_light_sweep.glsl) ---- */

/* ln I of light that is gone, the least the sweep stores: exp(-80) is below any radiance of note. */
#define SL_LOG_FLOOR (-80.0)

/* Whether the point at fractional sample coordinates (u, w) of a plane of n1 x n2 samples lies in
 * the plane's footprint, half a sample beyond its outermost samples: where a sample's sun ray
 * crossed the previous plane, or outside it entered through a side face. */
SL_INLINE bool sl_sweep_in_plane(SL_REAL u, SL_REAL w, SL_REAL n1, SL_REAL n2)
{
  return !(u < -0.5 || w < -0.5 || u > n1 - 0.5 || w > n2 - 0.5);
}

/* Between the plane's outermost samples and the box's faces the light has just entered: the weight
 * of fresh sunlight (ln I = 0, n = 0) in the state there, 0 at the outermost sample rising to 1 at
 * the face half a sample beyond, instead of holding the edge sample's state. */
SL_INLINE SL_REAL sl_sweep_fresh_weight(SL_REAL u, SL_REAL w, SL_REAL n1, SL_REAL n2)
{
  SL_REAL fresh = 0.0;
  if (u < 0.0) fresh = sl_fmax(fresh, -2.0 * u);
  if (u > n1 - 1.0) fresh = sl_fmax(fresh, 2.0 * (u - (n1 - 1.0)));
  if (w < 0.0) fresh = sl_fmax(fresh, -2.0 * w);
  if (w > n2 - 1.0) fresh = sl_fmax(fresh, 2.0 * (w - (n2 - 1.0)));
  return fresh > 1.0 ? 1.0 : fresh;
}

/* ---- The resolve of the volume layer (resolve.c, shaders/volume_resolve.glsl) ---- */

/* Where along a pixel's ray the air in front of the volume ends (Riley et al. 2004, sec. 5: the
 * volume's light is seen through the air to the content's midplane): the midplane at distance
 * `mid` along the view axis, over the ray's cosine `along` with that axis, kept within the ray's
 * span [t0, t1] through the content; the span's middle for a ray across the axis. */
SL_INLINE SL_REAL sl_resolve_split(SL_REAL along, SL_REAL mid, SL_REAL t0, SL_REAL t1)
{
  SL_REAL t = sl_fabs(along) > 1e-12 ? mid / along : 0.5 * (t0 + t1);
  return t < t0 ? t0 : t > t1 ? t1 : t;
}

/* The volume layer at one wavelength: its accumulated light acc seen through the air's
 * transparency front_t up to the split, plus the air's own light `front` over that stretch, which
 * the volume's coverage (1 - its transparency) carries: where the volume covers nothing the air in
 * front is the background's, drawn with it. */
SL_INLINE SL_REAL sl_resolve_layer(SL_REAL acc, SL_REAL coverage, SL_REAL front, SL_REAL front_t)
{
  return front_t * acc + coverage * front;
}

/* The layer's depth from its opacity-weighted depth sum: `none` (infinity) where it covers almost
 * nothing, since the sum over a coverage near 0 is all rounding. */
SL_INLINE SL_REAL sl_resolve_depth(SL_REAL depth_sum, SL_REAL coverage, SL_REAL none)
{
  return coverage > 1e-4 ? depth_sum / coverage : none;
}

#ifndef SL_GLSL
/* C only (it updates through a pointer): one light step through a chord len of a sample with
 * per-field extinction beta, on the state at state[o...] that holds ln I per wavelength and n:
 * ln I gains the log of eq. 24's (or 25's) kept fraction, which is an exponent already (no
 * exponential), then n grows by eq. 21. The state is reached by an int offset so that a loop of
 * these steps over scattered texels vectorises (gathers and scatters). The slicer's light buffer
 * and the light volume's sweep take it; the GPU sweep writes the same lines in GLSL around
 * sl_light_fraction_exponents. */
SL_INLINE void sl_log_light_step_at(SL_MODEL_PARAM const float beta[SL_MAX_FIELDS], SL_REAL len, float *state, int o)
{
  SL_REAL n = state[o + SL_NWL];
  SL_REAL log_kept[SL_MAX_WAVELENGTHS];
  sl_light_fraction_exponents(SL_MODEL_ARG beta, n, len, log_kept);
  SL_UNROLL
  for (int c = 0; c < SL_NWL; ++c) state[o + c] = (float)(state[o + c] + log_kept[c]);
  if (SL_MODE != SL_MODE_LOW_ALBEDO) state[o + SL_NWL] = (float)sl_expected_scatter_count(SL_MODEL_ARG beta, n, len);
}
#endif

#endif
