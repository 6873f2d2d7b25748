/* The slicer's eye pass over a batch of a tile's samples in one slice (Riley et al. 2004, eq. 26):
 * the samples' parts and fields, their geometry and light-buffer values, their table look-ups and
 * exponentials, and their compositing into the pixels, each a small stage over one eye_batch whose
 * loops over the samples vectorise. */
#ifndef SL_EYE_BATCH_H
#define SL_EYE_BATCH_H

#include "light_kink.h"
#include "segment_parts.h"
#include "sky_light_gather.h"
#include "sl_sample_physics.h"
#include "slicer.h"
#include "vector_math.h"

/* Samples of a tile in a slice whose exponentials the eye pass takes at once: a multiple of the
 * vector width, and few enough that the batch's arrays stay in the L1 cache at 16 wavelengths (at
 * a whole tile, 256, the 16-wavelength eye pass ran 1.4x slower). */
#define EYE_BATCH 32
_Static_assert(EYE_BATCH == SL__SKY_BATCH, "the skylight gather's rows are an eye batch");

/* The parts an eye sample's segment is taken in (sl_segment_parts: one where it is optically
 * thin, else parts fixed in optical depth from a profile of its total extinction), so that they
 * follow a thick cloud's surface wherever the slab's planes cut it: parts fixed in length drew
 * bands along the slices on thick surfaces (tests/volume/test_stripes). */
/* The optical depth of a part's light path within its slab, at its own extinction, above which
 * the path's own medium is integrated (eye_batch_light). */
#define EYE_PATH_DEPTH 0.05
/* The light buffer's ln I below which, at both ends of a part and every wavelength, its light path
 * is not integrated (eye_dark): e^-40 = 4e-18 of the sunlight. */
#define EYE_DARK_LOG (-40.0)

/* Whether pixel q's ray, front to back, is already so deep in the medium (its transparency below
 * SL_PART_DEEP) that a thick segment there is taken as one part at its middle's fields, with its
 * part's own extinction along its light path, as thin ones are. */
static inline int eye_deep(const slicer_frame *f, const int nwl, const int q)
{
  return !f->back_to_front && f->acc[(size_t)q * (nwl + 2) + nwl] < SL_PART_DEEP;
}

/* The table look-ups of a batch of eye samples, in one loop over the samples that vectorises
 * (gathers), as the light pass's steps do: per sample the exponents of eq. 24's fraction over its
 * probe path, the expected scattering count at its middle (eq. 21) and eq. 26's angular term there,
 * times the sunlight over the extinction (sun_per_beta) as the segment gather's source. The
 * samples are independent (ivdep). */
static inline __attribute__((always_inline)) void eye_batch_phases(
    const sl_light_model *restrict m, const int mode, const int nf, const int nwl, const int live,
    float (*restrict fields)[SL_MAX_FIELDS], const double *restrict n, const double *restrict probe,
    const double *restrict path_mid, const int *restrict angle_index, const double *restrict angle_weight,
    double (*restrict sun_per_beta)[EYE_BATCH], double (*restrict log_kept)[EYE_BATCH],
    double (*restrict source)[EYE_BATCH])
{
#pragma GCC ivdep
  for (int s = 0; s < live; ++s) {
    double lk[SL_MAX_WAVELENGTHS], phase[SL_MAX_WAVELENGTHS];
    sl_light_fraction_exponents(m, mode, nf, nwl, fields[s], n[s], probe[s], lk);
    const double n_sample =
        mode != SL_LIGHTING_LOW_ALBEDO ? sl_expected_scatter_count(m, mode, nf, nwl, fields[s], n[s], path_mid[s]) : n[s];
    sl_eye_phase_at(m, mode, nf, nwl, fields[s], n_sample, angle_index[s], angle_weight[s], phase);
    for (int c = 0; c < nwl; ++c) {
      log_kept[c][s] = lk[c];
      /* scatter_over_segment integrates beta * ...; the source per unit extinction is the phase
       * term (beta_sca Ams) over beta. */
      source[c][s] = phase[c] * sun_per_beta[c][s];
    }
  }
}

/* The eye pass's exponentials for a batch of samples (of one tile in one slice), every wavelength:
 * the opacity of each sample's segment, the slab's effective extinction (the log of the light it
 * keeps over the probe path, eq. 24, per metre), and the closed-form gather of
 * sl_segment_scatter_moments; radiance[c][s] is the light sample s sends toward the eye at
 * wavelength c before the eye's own attenuation in front of it. Loops over the samples inside
 * loops over the wavelengths, each branch-free, so that every one vectorises (libmvec's exp and
 * expm1) whatever the wavelength count. */
static inline __attribute__((always_inline)) void eye_batch_radiance(
    const int nwl, const int live, const double *restrict beta, const double *restrict inv_beta,
    const double *restrict len, const double *restrict inv_len, const double *restrict inv_probe,
    const double *restrict path_near, const double *restrict light_rate, double (*restrict log_kept)[EYE_BATCH],
    double (*restrict l0)[EYE_BATCH], double (*restrict l1)[EYE_BATCH], double (*restrict source)[EYE_BATCH],
    double *restrict opacity, double (*restrict radiance)[EYE_BATCH])
{
#pragma omp simd
  for (int s = 0; s < live; ++s) opacity[s] = -expm1(-beta[s] * len[s]);
  for (int c = 0; c < nwl; ++c) {
    const double *restrict lk = log_kept[c], *restrict a0 = l0[c], *restrict a1 = l1[c], *restrict src = source[c];
    double *restrict out = radiance[c];
#pragma omp simd
    for (int s = 0; s < live; ++s) {
      const double slab_extinction = -lk[s] * inv_probe[s];
      /* The light along the segment: the buffer's values (ln I) at its ends, log-linear between them
       * (exact where the light falls off exponentially across the buffer, as it does into a
       * cloud; taken linear, it overestimated the light where a thick segment crosses a shadow's
       * edge, across which the buffer falls by up to e^-34 in the bundled storm, and showed the
       * slices as a hatch), times the slab's own attenuation. */
      const double decay = (a0[s] - a1[s]) * inv_len[s];
      const double rate = 1.0 + (slab_extinction * light_rate[s] + decay) * inv_beta[s];
      /* The light entering at the near end, and that times e^-x (x = beta rate len) as one
       * exponential: the log of the far end's light times the segment's transparency, never above
       * 0, where e^-x alone overflows when the light grows by hundreds of e-folds along a thick
       * segment (sl_segment_scatter_moment_scaled). */
      const double near = a0[s] - slab_extinction * path_near[s];
      const double gathered = sl_segment_scatter_moment_scaled(0, beta[s], len[s], rate, exp(near),
                                                               exp(near - beta[s] * rate * len[s]));
      out[s] = gathered * src[s];
    }
  }
}


/* A batch of up to EYE_BATCH sample parts of one eye tile in one slice: per part, and per
 * wavelength and part, in separate arrays that the stages' loops read as vectors. Every array is
 * a multiple of 64 bytes long and the struct 64-byte aligned, so each array starts on a cache
 * line, as the vector loads want. */
typedef struct __attribute__((aligned(64))) eye_batch {
  double mid[EYE_BATCH], len[EYE_BATCH], beta[EYE_BATCH]; /* ray distance, length, extinction */
  double inv_beta[EYE_BATCH], inv_len[EYE_BATCH], inv_probe[EYE_BATCH], path_near[EYE_BATCH];
  double light_rate[EYE_BATCH], depth[EYE_BATCH], opacity[EYE_BATCH];
  double n[EYE_BATCH], n_far[EYE_BATCH], probe[EYE_BATCH], path_mid[EYE_BATCH];
  double tu[2][EYE_BATCH], tv[2][EYE_BATCH], sun_frac[EYE_BATCH];
  double angle_weight[EYE_BATCH];
  double log_kept[SL_MAX_WAVELENGTHS][EYE_BATCH], l0[SL_MAX_WAVELENGTHS][EYE_BATCH];
  double l1[SL_MAX_WAVELENGTHS][EYE_BATCH], source[SL_MAX_WAVELENGTHS][EYE_BATCH];
  double radiance[SL_MAX_WAVELENGTHS][EYE_BATCH], sun[SL_MAX_WAVELENGTHS][EYE_BATCH];
  double sky_t[EYE_BATCH]; /* ray distance of the skylight's look-up for the part's segment */
  float sky[EYE_BATCH][SL_MAX_WAVELENGTHS + 4]; /* the skylight's M for each part (its segment's) */
  int texel[2][EYE_BATCH]; /* the light buffer's texel at each end (light_texel_lane) */
  float fields[EYE_BATCH][SL_MAX_FIELDS];
  int q[EYE_BATCH]; /* pixel */
  int sun_row[EYE_BATCH];
  int angle_index[EYE_BATCH];
  int sky_first[EYE_BATCH]; /* the part looks the skylight up (else: as the part before) */
  int whole[EYE_BATCH];     /* the part is its segment whole, an optically thin one */
  int live; /* parts held */
} eye_batch;

/* Whether part s's sunlight is too dark for its light path's medium to matter: ln I below
 * EYE_DARK_LOG at both its ends at every wavelength. Along the part the light is log-linear between
 * the ends times the slab's own attenuation, which only lowers it (eye_batch_radiance), so the
 * part's sunlit radiance is below e^-40 of a lit part's with the same phase term whatever the path
 * integral gives: below float's rounding of any pixel the sun reaches, even through the tables'
 * forward peak. Seen from a storm's shadowed side or into a low sun, most parts near the surface
 * are that dark (the supercell at sunset: three quarters of the integrals). */
static inline int eye_dark(const eye_batch *b, const int nwl, const int s)
{
  double brightest = b->l0[0][s];
  for (int c = 0; c < nwl; ++c) brightest = sl__max(brightest, sl__max(b->l0[c][s], b->l1[c][s]));
  return brightest < EYE_DARK_LOG;
}

/* The batch's parts from the tile's samples si.. (cells, far ends' cells far_cells, pixels sq,
 * middles smid, lengths slen of cnt): per sample its fields and parts (scalar: a sample's parts
 * vary), until the batch has no room for another sample's parts; returns the next sample. */
static inline __attribute__((always_inline)) int eye_batch_parts(const slicer_frame *f, const int nf, const int nwl,
                                                                 eye_batch *b,
                                                                 const sl__field_cell *cells,
                                                                 const sl__field_cell *far_cells, const int *sq,
                                                                 const double *smid, const double *slen, int si,
                                                                 const int cnt)
{
  const sl_renderer *r = f->r;
  const double *ray = f->ray, *o = f->cam->position;
  const int back_to_front = f->back_to_front;
  int live = 0;
  for (; si < cnt && live <= EYE_BATCH - SL_PARTS_MAX; ++si) {
    float v[SL__FIELD_LANES];
    sl__field_fetch(r, nf, &cells[si], v);
    double beta_mid = 0.0;
    for (int j = 0; j < nf; ++j) beta_mid += v[j];
    /* Thick where the extinction at its middle or at its far end (sl__segment_far_end) makes it
     * so: a cloud's surface in the far half of a segment whose middle is clear air would otherwise
     * wait for the next slab's segment, drawing blocks wherever the surface crosses from one slab
     * to the next (the supercell's anvil base seen from below). The march looks at its next step
     * the same way (light_volume_march.c). */
    const double *rq = ray + (size_t)sq[si] * RAY_STRIDE;
    int thin = eye_deep(f, nwl, sq[si]);
    if (!thin && beta_mid * slen[si] < SL_PART_THIN) {
      double beta_far;
      if (nf > 1) {
        beta_far = far_cells[si].c ? sl__field_total(r, nf, &far_cells[si]) : 0.0;
      } else {
        double x_far[3];
        sl__segment_far_end(&r->lattice, o, rq, smid[si] + 0.5 * slen[si], x_far);
        beta_far = sl__total_extinction_n(r, nf, x_far);
      }
      thin = beta_far * slen[si] < SL_PART_THIN;
    }
    if (thin) {
      if (!(beta_mid > 0.0)) continue;
      for (int j = 0; j < nf; ++j) b->fields[live][j] = v[j];
      b->q[live] = sq[si], b->mid[live] = smid[si], b->len[live] = slen[si], b->beta[live] = beta_mid;
      b->sky_t[live] = smid[si], b->sky_first[live] = 1, b->whole[live] = 1;
      live++;
      continue;
    }
    const double t_near = smid[si] - 0.5 * slen[si], step = slen[si] / SL_PART_PROFILE;
    double step_beta[SL_PART_PROFILE], tau[SL_PART_PROFILE + 1];
    sl__segment_profile_fields kept;
    const double depth = sl__segment_profile(r, nf, o, rq, t_near, step, step_beta, tau, &kept);
    if (!(depth > 0.0)) continue;
    double t_at[SL_PARTS_MAX + 1], tau_at[SL_PARTS_MAX + 1];
    const int parts = sl_segment_parts(tau, t_near, step, t_near + slen[si], t_at, tau_at);
    /* A segment shorter than the skylight lattice's spacing, over which M barely changes, takes one
     * look-up for all its parts (a look-up per part was most of the skylight's cost), at the
     * optical depth tau_sky from the medium's start that the light it sends toward the eye has
     * on average, its weight e^-tau in [0, depth]: exact where M is linear in tau; depth / 2 for
     * a thin segment, 1 for a thick one. A longer one looks up at each part's middle. */
    const sl__sky_light *sky = &r->sky;
    const int sky_shared =
        sky->radiance && slen[si] < sl__min(sl__min(sky->spacing[0], sky->spacing[1]), sky->spacing[2]);
    double sky_t = 0.0;
    if (sky_shared) {
      const double tau_sky = depth < 1e-3 ? 0.5 * depth : 1.0 - depth / expm1(depth);
      int k_sky = 0;
      while (k_sky < SL_PART_PROFILE - 1 && tau[k_sky + 1] < tau_sky) k_sky++;
      const double span = tau[k_sky + 1] - tau[k_sky];
      sky_t = t_near + (k_sky + (span > 0.0 ? sl__min(sl__max((tau_sky - tau[k_sky]) / span, 0.0), 1.0) : 0.5)) * step;
    }
    int sky_first = 1;
    for (int p = 0; p < parts; ++p) {
      /* The parts in the order of compositing: nearest first, or farthest first back to front. */
      const int part = back_to_front ? parts - 1 - p : p;
      const double len = t_at[part + 1] - t_at[part], mid = 0.5 * (t_at[part] + t_at[part + 1]);
      if (!(len > 0.0 && tau_at[part + 1] > tau_at[part])) continue;
      const double beta = sl__segment_part_fields(r, nf, o, rq, t_near, step, step_beta, tau, &kept, tau_at[part],
                                                   tau_at[part + 1], len, b->fields[live]);
      if (!(beta > 0.0)) continue;
      b->q[live] = sq[si], b->mid[live] = mid, b->len[live] = len, b->beta[live] = beta;
      b->sky_t[live] = sky_shared ? sky_t : mid, b->sky_first[live] = sky_first || !sky_shared;
      b->whole[live] = 0;
      sky_first = 0;
      live++;
    }
  }
  b->live = live;
  return si;
}

/* Per part its geometry, light-buffer texels and sun-table row, in one loop over the batch without
 * branches, so that it vectorises (gathers from the rays); as a scalar loop this was the eye pass's
 * largest stage. The light buffer holds the light up to this slab's first plane s_start; from
 * there the light crosses this slab's own medium for a path that grows linearly along the eye
 * segment. The buffer's ln I is taken linear between the segment's two ends and the slab's own
 * attenuation exponential in the path, so the gather has a closed form
 * (sl_segment_scatter_moment_exp). Within the slab, the light keeps fraction(path) of itself
 * (eq. 24 or the plain transparency); its log, per metre of path, is the slab's effective
 * extinction. The fraction is probed at the segment's middle path; its table look-ups wait for
 * eye_batch_phases, its exponentials for eye_batch_radiance. */
static inline __attribute__((always_inline)) void eye_batch_geometry(const slicer_frame *f, const light_buffer *L,
                                                                     const sl__sun_lane *sun_lane, double s_start,
                                                                     eye_batch *b)
{
  const double *ray = f->ray, *o = f->cam->position, *h = f->h, *fwd = f->fwd;
  const double inv_hp = f->inv_hp;
  const sl__box_exit sun_exit = f->sun_exit;
  const sun_table *suntab = f->suntab;
  const int *angle_index = f->angle_index;
  const float *angle_weight = f->angle_weight;
  const int live = b->live;
#pragma GCC ivdep
  for (int s = 0; s < live; ++s) {
    const ptrdiff_t rq = (ptrdiff_t)b->q[s] * RAY_STRIDE;
    const double d[3] = {ray[rq], ray[rq + 1], ray[rq + 2]};
    const double mid = b->mid[s], len = b->len[s];
    const double t_near = mid - 0.5 * len, t_far = mid + 0.5 * len;
    const double x[3] = {o[0] + mid * d[0], o[1] + mid * d[1], o[2] + mid * d[2]};
    const double x_near[3] = {o[0] + t_near * d[0], o[1] + t_near * d[1], o[2] + t_near * d[2]};
    const double x_far[3] = {o[0] + t_far * d[0], o[1] + t_far * d[1], o[2] + t_far * d[2]};
    const double path_near = sl__max(
        sl__min((h[0] * x_near[0] + h[1] * x_near[1] + h[2] * x_near[2] - s_start) * inv_hp,
                sl__box_exit_distance(&sun_exit, x_near)),
        0.0);
    const double path_far = sl__max(
        sl__min((h[0] * x_far[0] + h[1] * x_far[1] + h[2] * x_far[2] - s_start) * inv_hp,
                sl__box_exit_distance(&sun_exit, x_far)),
        0.0);
    const double inv_beta = 1.0 / b->beta[s];
    light_texel_lane(L, x_near, &b->texel[0][s], &b->tu[0][s], &b->tv[0][s]);
    light_texel_lane(L, x_far, &b->texel[1][s], &b->tu[1][s], &b->tv[1][s]);
    sl__sun_row(suntab, sun_lane, x, &b->sun_row[s], &b->sun_frac[s]);
    const double path_mid = 0.5 * (path_near + path_far);
    b->path_mid[s] = path_mid;
    const double probe = sl__max(path_mid, 1e-3 * inv_beta);
    b->probe[s] = probe;
    b->angle_index[s] = angle_index[b->q[s]], b->angle_weight[s] = angle_weight[b->q[s]];
    b->inv_beta[s] = inv_beta, b->inv_len[s] = 1.0 / len;
    b->inv_probe[s] = 1.0 / probe, b->path_near[s] = path_near;
    b->light_rate[s] = (path_far - path_near) / len;
    b->depth[s] = mid * (d[0] * fwd[0] + d[1] * fwd[1] + d[2] * fwd[2]);
  }
}

/* Part s's light paths within its slab at its near and far ends, as lengths at its own extinction
 * (eye_batch_geometry's, replaced where the paths' own medium is integrated). */
static inline __attribute__((always_inline)) void eye_part_paths(eye_batch *b, const int s, const double near,
                                                                 const double far)
{
  b->path_near[s] = near, b->light_rate[s] = (far - near) * b->inv_len[s];
  b->path_mid[s] = 0.5 * (near + far);
  b->probe[s] = sl__max(b->path_mid[s], 1e-3 * b->inv_beta[s]);
  b->inv_probe[s] = 1.0 / b->probe[s];
}

/* The light at each part's two ends: the light buffer's channels (ln I per wavelength and n,
 * light_bilinear_texel); where an end's texels meet a cloud's surface at a grazing angle, its
 * light from its own entry (light_kink); n at the middle; the sunlight per extinction (the
 * sunlight's loop vectorises). */
static inline __attribute__((always_inline)) void eye_batch_light(const slicer_frame *f, const int nf, const int nwl,
                                                                  const light_buffer *L, ptrdiff_t light_di,
                                                                  ptrdiff_t light_dj, double s_start, eye_batch *b)
{
  const sl_renderer *r = f->r;
  const double *ray = f->ray, *o = f->cam->position, *h = f->h, *prop = f->prop;
  const double inv_hp = f->inv_hp, kink_step = 0.5 * f->entry_step; /* light_kink's light steps */
  const int kink = f->kink, live = b->live;
  for (int s = 0; s < live; ++s)
    for (int end = 0; end < 2; ++end) {
      double value[SL_MAX_WAVELENGTHS + 4];
      light_bilinear_texel(L->state, (int)light_di, (int)light_dj, b->texel[end][s], b->tu[end][s], b->tv[end][s],
                           nwl + 1, value);
      for (int c = 0; c < nwl; ++c) (end ? b->l1 : b->l0)[c][s] = value[c];
      (end ? b->n_far : b->n)[s] = value[nwl];
    }
  const double e_plane = s_start * inv_hp;
  for (int s = 0; s < (kink ? live : 0); ++s)
    for (int end = 0; end < 2; ++end) {
      const ptrdiff_t cell = b->texel[end][s] / (nwl + 1);
      const double gmin = L->cell_gmin[cell], gmax = L->cell_gmax[cell];
      if (!(gmin < e_plane && e_plane < 2.0 * gmax - gmin)) continue;
      const double *rq = ray + (size_t)b->q[s] * RAY_STRIDE;
      const double te = b->mid[s] + (end ? 0.5 : -0.5) * b->len[s];
      const double x[3] = {o[0] + te * rq[0], o[1] + te * rq[1], o[2] + te * rq[2]};
      const double back = (h[0] * x[0] + h[1] * x[1] + h[2] * x[2] - s_start) * inv_hp;
      const double p[3] = {x[0] - back * prop[0], x[1] - back * prop[1], x[2] - back * prop[2]};
      double value[SL_MAX_WAVELENGTHS + 1];
      if (!light_kink(r, nf, nwl, L, light_di, light_dj, b->texel[end][s], b->tu[end][s], b->tv[end][s], e_plane, p,
                      prop, kink_step, value))
        continue;
      for (int c = 0; c < nwl; ++c) (end ? b->l1 : b->l0)[c][s] = value[c];
      (end ? b->n_far : b->n)[s] = value[nwl];
    }
  /* The light's path from the slab's first plane to a part crosses the medium between them, not
   * the part's own: at a surface the part lies deep in the cloud while the plane is in clear air,
   * and the part's extinction along the whole path put its light (eq. 24) and its scattering
   * count (eq. 21) as far inside as the plane lay from it, darker and more isotropic the further
   * the plane, once per slab. Where that matters (an optical depth above EYE_PATH_DEPTH at the
   * part's own extinction), each end's path takes the length that has the optical depth of the
   * path's own medium (sl__segment_optical_depth) at the part's extinction, unless the part's
   * sunlight is too dark to matter (eye_dark). The parts of one segment lie next to each other in
   * the batch and share their ends, so each end is integrated once. An optically thin segment,
   * taken whole, integrates its middle's path alone and scales both ends' paths by what that
   * path holds against the part's own extinction: exact where the medium the ends' paths cross
   * differs from the part's by the same factor; one integral instead of two (against two: at most
   * 4e-6 of the frame, relative RMSE, on the storms' surfaces seen from above and below, the
   * eye pass 4-7 % faster; docs/PERFORMANCE.md). */
  int held_q = -1;
  double held_t[2] = {0.0, 0.0}, held_depth[2] = {0.0, 0.0};
  for (int s = 0; s < live; ++s) {
    const double path_near = b->path_near[s], path_far = path_near + b->light_rate[s] * b->len[s];
    if (!(b->beta[s] * sl__max(path_near, path_far) > EYE_PATH_DEPTH) || eye_deep(f, nwl, b->q[s]) ||
        eye_dark(b, nwl, s))
      continue;
    const double *rq = ray + (size_t)b->q[s] * RAY_STRIDE;
    if (b->whole[s]) {
      const double path_mid = 0.5 * (path_near + path_far), t = b->mid[s];
      const double x[3] = {o[0] + t * rq[0], o[1] + t * rq[1], o[2] + t * rq[2]};
      const double p[3] = {x[0] - path_mid * prop[0], x[1] - path_mid * prop[1], x[2] - path_mid * prop[2]};
      const double ratio =
          path_mid > 0.0 ? sl__segment_optical_depth(r, nf, p, x) * b->inv_beta[s] / path_mid : 0.0;
      eye_part_paths(b, s, ratio * path_near, ratio * path_far);
      continue;
    }
    double depth[2], te[2];
    for (int end = 0; end < 2; ++end) {
      te[end] = b->mid[s] + (end ? 0.5 : -0.5) * b->len[s];
      const double tol = 1e-9 * (fabs(te[end]) + 1.0), path = end ? path_far : path_near;
      if (b->q[s] == held_q && fabs(te[end] - held_t[1 - end]) <= tol) {
        depth[end] = held_depth[1 - end];
        continue;
      }
      const double x[3] = {o[0] + te[end] * rq[0], o[1] + te[end] * rq[1], o[2] + te[end] * rq[2]};
      const double p[3] = {x[0] - path * prop[0], x[1] - path * prop[1], x[2] - path * prop[2]};
      depth[end] = path > 0.0 ? sl__segment_optical_depth(r, nf, p, x) : 0.0;
    }
    held_q = b->q[s];
    for (int end = 0; end < 2; ++end) held_t[end] = te[end], held_depth[end] = depth[end];
    eye_part_paths(b, s, depth[0] * b->inv_beta[s], depth[1] * b->inv_beta[s]);
  }
#pragma omp simd
  for (int s = 0; s < live; ++s) b->n[s] = 0.5 * (b->n[s] + b->n_far[s]);
  for (int c = 0; c < nwl; ++c) {
    double *restrict out = b->sun[c];
    const double *restrict rgb = &f->suntab->rgb[0][0];
#pragma omp simd
    for (int s = 0; s < live; ++s) out[s] = sl__sun_lerp(rgb, b->sun_row[s], b->sun_frac[s], c) * b->inv_beta[s];
  }
  for (int s = 0; s < (r->sky.radiance ? live : 0); ++s) {
    if (!b->sky_first[s]) {
      memcpy(b->sky[s], b->sky[s - 1], sizeof b->sky[s]);
      continue;
    }
    const double *rq = ray + (size_t)b->q[s] * RAY_STRIDE, t = b->sky_t[s];
    const double x[3] = {o[0] + t * rq[0], o[1] + t * rq[1], o[2] + t * rq[2]};
    sl__sky_light_at(&r->sky, x, b->sky[s]);
  }
}

/* The batch's table look-ups (eye_batch_phases, with the model of the fields the batch holds) and
 * its exponentials (eye_batch_radiance). */
static inline __attribute__((always_inline)) void eye_batch_scatter(const slicer_frame *f, const int nf,
                                                                    const int nwl, eye_batch *b)
{
  const sl_light_model *m = &f->r->model, *held_model = m;
  const int live = b->live;
  const int held = sl__batch_fields(f->subsets, nf, live, b->fields, &held_model);
#define EYE_PHASES(model, mode, count) \
  eye_batch_phases(model, mode, count, nwl, live, b->fields, b->n, b->probe, b->path_mid, b->angle_index, \
                   b->angle_weight, b->sun, b->log_kept, b->source)
  SL_WITH_BATCH_MODEL(m, held_model, held, nf, EYE_PHASES);
#undef EYE_PHASES
  eye_batch_radiance(nwl, live, b->beta, b->inv_beta, b->len, b->inv_len, b->inv_probe, b->path_near, b->light_rate,
                     b->log_kept, b->l0, b->l1, b->source, b->opacity, b->radiance);
  if (f->r->sky.radiance)
    sl__sky_light_add(held_model, (int)held_model->mode, held, nwl, live, b->fields, b->inv_beta, b->opacity,
                      b->sky, b->radiance);
}

/* The batch's light into its pixels' accumulators, front to back (under the transparency in front)
 * or back to front (over what lies behind); a ray front to back whose transparency falls below the
 * scene's termination ends its span at slice k. */
static inline __attribute__((always_inline)) void eye_batch_composite(const slicer_frame *f, const int nwl, int k,
                                                                      const eye_batch *b)
{
  float *acc = f->acc;
  int *pk = f->pk;
  const int acc_stride = nwl + 2, back_to_front = f->back_to_front;
  const double termination = f->r->scene.termination_transparency;
  for (int s = 0; s < b->live; ++s) {
    const size_t q = (size_t)b->q[s];
    const double opacity = b->opacity[s];
    float *a = acc + q * acc_stride;
    const double w = back_to_front ? 1.0 : a[nwl];
    for (int c = 0; c < nwl; ++c) {
      const double radiance = b->radiance[c][s];
      if (back_to_front) a[c] = (float)(a[c] * (1.0 - opacity) + radiance);
      else a[c] += (float)(w * radiance);
    }
    if (back_to_front) a[nwl + 1] = (float)(a[nwl + 1] * (1.0 - opacity) + opacity * b->depth[s]);
    else a[nwl + 1] += (float)(w * opacity * b->depth[s]);
    a[nwl] *= (float)(1.0 - opacity); /* exp(-beta len), from expm1's exact small end */
    if (!back_to_front && a[nwl] < termination) pk[2 * q + 1] = k;
  }
}

#endif
