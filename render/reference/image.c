/* Progressive images of the volume layer. Each sample of a pixel at one
 * wavelength is an independent path: its transparency by ratio tracking, its scattered light by
 * delta tracking with next-event estimation of the sun at every collision (and, with skylight,
 * the sky collected where a scattered path leaves the box). The air is treated as render/volume
 * treats it: the volume layer is V' = T_front V + (1 - T_vol) L_front with the split at the plane
 * through the content's centre perpendicular to the slicing half-vector, and the sunlight at a
 * point is eq. 12 with the view's air mass. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "reference_internal.h"
#include "sl_cie.h"

#define ROULETTE_WEIGHT 0.1
#define DEFAULT_ROULETTE_DEPTH 16
/* Past the roulette depth a path survives each scattering with this probability (its weight
 * grows by the inverse): unbiased, and it bounds the cost of albedo-1 media. */
#define DEEP_SURVIVAL 0.98

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static int normalize3(double v[3])
{
  const double n = sqrt(dot3(v, v));
  if (!(n > 0.0) || !isfinite(n)) return 1;
  v[0] /= n, v[1] /= n, v[2] /= n;
  return 0;
}

void sl_ref_scene_defaults(sl_ref_scene *s)
{
  memset(s, 0, sizeof *s);
  s->sun_direction[2] = 1.0;
  for (int w = 0; w < SL_REF_MAX_WAVELENGTHS; ++w) s->sun_irradiance[w] = 1.0;
  s->seed = 1;
}

int sl_ref_accum_init(sl_ref_accum *a, int width, int height, int n_wavelengths, sl_error *err)
{
  memset(a, 0, sizeof *a);
  if (width < 1 || height < 1 || n_wavelengths < 1 || n_wavelengths > SL_REF_MAX_WAVELENGTHS)
    return sl_fail(err, SL_ERR_ARG, "reference: image %dx%d with %d wavelengths", width, height, n_wavelengths);
  const size_t np = (size_t)width * height, n = np * n_wavelengths;
  a->width = width, a->height = height, a->n_wavelengths = n_wavelengths;
  a->sum = calloc(n, sizeof(double));
  a->sum2 = calloc(n, sizeof(double));
  a->transparency_sum = calloc(n, sizeof(double));
  a->depth_sum = calloc(np, sizeof(double));
  a->depth_weight = calloc(np, sizeof(double));
  if (!a->sum || !a->sum2 || !a->transparency_sum || !a->depth_sum || !a->depth_weight) {
    sl_ref_accum_free(a);
    return sl_fail(err, SL_ERR_NOMEM, "reference: out of memory for a %dx%d accumulator", width, height);
  }
  return SL_OK;
}

void sl_ref_accum_free(sl_ref_accum *a)
{
  free(a->sum), free(a->sum2), free(a->transparency_sum), free(a->depth_sum), free(a->depth_weight);
  memset(a, 0, sizeof *a);
}

/* Everything about one frame that every path reads. */
typedef struct frame {
  const sl_ref_scene *sc;
  const sl_ref_medium *m;
  sl_sky_view view;
  double sun[3];
  int sun_up;
  int sun_mis; /* the sun-directed second strategy is on */
} frame;

static double sunlight_at(const frame *fr, int w, double z)
{
  const sl_atmosphere *atm = fr->sc->atmosphere;
  if (!atm) return fr->sc->sun_irradiance[w];
  if (fr->view.night) return 0.0;
  /* Riley et al. 2004, eq. 12, with the view's air mass as render/volume's sun table. */
  return atm->sun_irradiance[w] *
         exp(-sl_sky_sun_optical_depth(atm->beta_sea_level[w], 1.0 / atm->scale_height, z, fr->view.airmass));
}

static double sky_from(const frame *fr, int w, const double x[3], const double d[3])
{
  const sl_atmosphere *atm = fr->sc->atmosphere;
  if (!atm) return fr->sc->sky_radiance[w];
  /* The sky seen from x: the frame's view moved to x. Its air mass is the eye's, which docs/SKY.md
   * measures below 0.2% for heights within 20 km of the eye. */
  sl_sky_view v = fr->view;
  v.eye[0] = x[0], v.eye[1] = x[1], v.eye[2] = x[2];
  double rad[SL_SKY_MAX_WAVELENGTHS];
  sl_sky_view_segment(&v, d, 0.0, INFINITY, rad, NULL);
  return rad[w];
}

/* The second strategy for light that reaches a path through one more scattering (docs/REFERENCE.md,
 * "Forward peaks and fireflies"). Next-event estimation at a vertex weighs the sun by the phase
 * function there, P(d . sun), which for cloud droplets reaches 400/sr within a degree of the sun:
 * a path that happens to head for the sun lights up one sample. So from every vertex x (component
 * c, throughput beta after its albedo) a direction is also proposed from c's phase function
 * centred on the sun, tracked to its next collision, and the sun estimated there; the two
 * strategies for that next vertex are combined with the balance heuristic (Veach 1997), which
 * is unbiased and bounds the proposal's contribution by about P_c(d . d_sun) instead of
 * P(d_sun . sun). */
static double sun_directed_estimate(const frame *fr, int w, const double x[3], const double d[3], int c, double beta,
                                    sl_ref_rng *rng)
{
  const sl_ref_medium *m = fr->m;
  double ds[3];
  sl_ref_phase_sample(m, c, w, fr->sun, rng, ds);
  const double pdf_path = ref_phase_pdf(m, c, w, dot3(d, ds)), pdf_sun = ref_phase_pdf(m, c, w, dot3(fr->sun, ds));
  const double f = sl_ref_phase_eval(m, c, w, dot3(d, ds));
  if (!(f > 0.0) || !(pdf_path + pdf_sun > 0.0)) return 0.0;
  double y[3] = {x[0], x[1], x[2]};
  if (ref_track(m, w, y, ds, rng, NULL) != TRACK_COLLISION) return 0.0;
  const int c2 = ref_choose_component(m, w, y, rng);
  const double p = sl_ref_phase_eval(m, c2, w, dot3(ds, fr->sun));
  const double e = sunlight_at(fr, w, y[2]);
  if (!(p > 0.0) || !(e > 0.0)) return 0.0;
  /* beta f / pdf_sun times the MIS weight pdf_sun / (pdf_path + pdf_sun). */
  const double throughput = beta * f / (pdf_path + pdf_sun) * m->albedo_eff[c2][w];
  return throughput * p * e * ref_transmittance(m, w, y, fr->sun, INFINITY, rng);
}

/* Light scattered toward the eye by the volume along the ray x0 + t d (x0 on or in the box),
 * before any air. *first gets the distance to the first collision (-1 when none). */
static double path_radiance(const frame *fr, int w, const double x0[3], const double d0[3], sl_ref_rng *rng,
                            double *first)
{
  const sl_ref_medium *m = fr->m;
  const sl_ref_scene *sc = fr->sc;
  const int rr_depth = sc->roulette_depth > 0 ? sc->roulette_depth : DEFAULT_ROULETTE_DEPTH;
  double x[3] = {x0[0], x0[1], x0[2]}, d[3] = {d0[0], d0[1], d0[2]};
  double beta = 1.0, radiance = 0.0;
  int depth = 0;
  /* Densities with which the current direction d was proposed at the previous vertex by the two
   * strategies (around the path, around the sun); 0 when d did not come from a scattering. */
  double pdf_path = 0.0, pdf_sun = 0.0;
  *first = -1.0;
  for (;;) {
    double travelled;
    const track_event ev = ref_track(m, w, x, d, rng, &travelled);
    if (ev != TRACK_COLLISION) {
      const int on_surface = ev == TRACK_BOTTOM && m->desc.black_surface;
      if (depth > 0 && sc->skylight && !on_surface) radiance += beta * sky_from(fr, w, x, d);
      break;
    }
    if (depth == 0) *first = travelled;
    const int c = ref_choose_component(m, w, x, rng);
    beta *= m->albedo_eff[c][w];
    ++depth;
    if (fr->sun_up && beta > 0.0) {
      /* Next-event estimation of the collimated sun: the phase function toward it times the
       * sunlight at this height times the volume's transparency toward it. */
      const double p = sl_ref_phase_eval(m, c, w, dot3(d, fr->sun));
      const double e = sunlight_at(fr, w, x[2]);
      /* Balance heuristic against the sun-directed strategy below (1 for the first vertex). */
      const double mis = pdf_path + pdf_sun > 0.0 ? pdf_path / (pdf_path + pdf_sun) : 1.0;
      if (p > 0.0 && e > 0.0) radiance += mis * beta * p * e * ref_transmittance(m, w, x, fr->sun, INFINITY, rng);
    }
    if (sc->max_scatter > 0 && depth >= sc->max_scatter) break;
    double q = 1.0;
    if (beta < ROULETTE_WEIGHT) q = beta / ROULETTE_WEIGHT;
    else if (depth > rr_depth) q = DEEP_SURVIVAL;
    if (q < 1.0) {
      if (sl_ref_rng_uniform(rng) >= q) break;
      beta /= q;
    }
    if (fr->sun_mis && (sc->max_scatter == 0 || depth < sc->max_scatter))
      radiance += sun_directed_estimate(fr, w, x, d, c, beta, rng);
    double nd[3];
    beta *= sl_ref_phase_sample(m, c, w, d, rng, nd);
    if (fr->sun_mis) {
      pdf_path = ref_phase_pdf(m, c, w, dot3(d, nd));
      pdf_sun = ref_phase_pdf(m, c, w, dot3(fr->sun, nd));
    }
    d[0] = nd[0], d[1] = nd[1], d[2] = nd[2];
  }
  return radiance;
}

int sl_ref_render(const sl_ref_scene *sc, const sl_camera *cam, const sl_ref_budget *budget, sl_ref_accum *acc,
                  sl_error *err)
{
  if (!sc || !sc->medium) return sl_fail(err, SL_ERR_ARG, "reference: no medium");
  const sl_ref_medium *m = sc->medium;
  if (!cam || cam->width != acc->width || cam->height != acc->height || acc->n_wavelengths != m->nw)
    return sl_fail(err, SL_ERR_ARG, "reference: the accumulator is not the camera's size or the medium's wavelengths");
  if (!(cam->fov_deg > 0.0 && cam->fov_deg < 170.0))
    return sl_fail(err, SL_ERR_ARG, "reference: field of view %g degrees is out of range (0, 170)", cam->fov_deg);
  if (!budget || budget->samples < 1) return sl_fail(err, SL_ERR_ARG, "reference: the budget has no samples");
  if (sc->atmosphere) {
    if (sc->atmosphere->count != m->nw)
      return sl_fail(err, SL_ERR_ARG, "reference: the atmosphere has %d wavelengths, the medium %d",
                     sc->atmosphere->count, m->nw);
    for (int w = 0; w < m->nw; ++w)
      if (fabs(sc->atmosphere->wavelength_nm[w] - m->desc.wavelength_nm[w]) > 1e-9)
        return sl_fail(err, SL_ERR_ARG, "reference: atmosphere wavelength %d is %g nm, the medium's %g nm", w,
                       sc->atmosphere->wavelength_nm[w], m->desc.wavelength_nm[w]);
  }
  double probe[3];
  if (sl_camera_ray(cam, 0, 0, probe))
    return sl_fail(err, SL_ERR_ARG, "reference: camera position equals the target, or up is parallel to the view");
  frame fr = {.sc = sc, .m = m};
  memcpy(fr.sun, sc->sun_direction, sizeof fr.sun);
  if (normalize3(fr.sun)) return sl_fail(err, SL_ERR_ARG, "reference: the sun direction is not a finite non-zero vector");
  fr.sun_up = 1;
  if (sc->atmosphere) {
    if (sl_sky_view_init(&fr.view, sc->atmosphere, cam->position, fr.sun, err)) return err->code;
    fr.sun_up = !fr.view.night;
  }
  fr.sun_mis = fr.sun_up && !sc->next_event_only;
  /* The midplane the fast renderer splits the air at: perpendicular to its slicing axis. */
  double fwd[3] = {cam->target[0] - cam->position[0], cam->target[1] - cam->position[1], cam->target[2] - cam->position[2]};
  normalize3(fwd);
  sl_slicing slicing;
  sl_choose_slicing(fwd, fr.sun, &slicing);
  const double *h = slicing.half_vector;
  const double h_center = dot3(h, m->content_center), h_o = dot3(h, cam->position);
  const int nw = m->nw;
  const size_t np = (size_t)cam->width * cam->height;
  const double *o = cam->position;
  const double t_start = omp_get_wtime();

  /* Passes are grouped into batches of at least ~64k paths, so that a small image does not pay a
   * thread start per sample; within a batch each pixel adds its samples in order. */
  long done = 0;
  while (done < budget->samples) {
    long batch = (long)(65536 / np) + 1;
    if (batch > budget->samples - done) batch = budget->samples - done;
    const long first_sample = acc->samples;
#pragma omp parallel for schedule(dynamic, 16)
    for (size_t q = 0; q < np; ++q) {
      double d[3];
      sl_camera_ray(cam, (int)(q % cam->width), (int)(q / cam->width), d);
      double t0, t1;
      const int hit = sl_ray_box(m->lo, m->hi, o, d, &t0, &t1) && t1 > 0.0;
      if (t0 < 0.0) t0 = 0.0;
      double front[SL_SKY_MAX_WAVELENGTHS] = {0}, front_t[SL_SKY_MAX_WAVELENGTHS];
      for (int w = 0; w < nw; ++w) front_t[w] = 1.0;
      if (hit && sc->atmosphere) {
        /* render/volume's split (sec. 5): the plane through the content's centre along h. */
        const double hd = dot3(h, d);
        double t_mid = fabs(hd) > 1e-12 ? (h_center - h_o) / hd : 0.5 * (t0 + t1);
        t_mid = t_mid < t0 ? t0 : t_mid > t1 ? t1 : t_mid;
        sl_sky_view_segment(&fr.view, d, 0.0, t_mid, front, front_t);
      }
      const double x0[3] = {o[0] + t0 * d[0], o[1] + t0 * d[1], o[2] + t0 * d[2]};
      for (long sample = first_sample; sample < first_sample + batch; ++sample)
        for (int w = 0; w < nw; ++w) {
          double value = 0.0, transparency = 1.0;
          if (hit) {
            sl_ref_rng rng = sl_ref_rng_make(sc->seed, q, (unsigned long long)sample, (unsigned long long)w);
            transparency = ref_transmittance(m, w, x0, d, INFINITY, &rng);
            double first;
            const double v = path_radiance(&fr, w, x0, d, &rng, &first);
            value = front_t[w] * v + (1.0 - transparency) * front[w];
            if (w == 0 && first >= 0.0) {
              acc->depth_sum[q] += (t0 + first) * dot3(d, fwd);
              acc->depth_weight[q] += 1.0;
            }
          }
          acc->sum[q * nw + w] += value;
          acc->sum2[q * nw + w] += value * value;
          acc->transparency_sum[q * nw + w] += transparency;
        }
    }
    acc->samples += batch;
    done += batch;
    if (budget->progress) budget->progress(budget->progress_user, (double)done / budget->samples);
    if (budget->max_seconds > 0.0 && omp_get_wtime() - t_start > budget->max_seconds) break;
  }
  acc->seconds += omp_get_wtime() - t_start;
  return SL_OK;
}

/* Weights from the medium's wavelengths to R, G, B: the paper's three channels as they are, one
 * wavelength as grey, otherwise CIE 1931 through sl_cie (white balanced, DESIGN.md). */
static int channel_weights(const sl_ref_medium *m, double *wt, sl_error *err)
{
  const int nw = m->nw;
  memset(wt, 0, 3 * (size_t)nw * sizeof(double));
  if (nw == 1) {
    wt[0] = wt[1] = wt[2] = 1.0;
    return SL_OK;
  }
  if (nw == 3) {
    for (int c = 0; c < 3; ++c) wt[c * nw + c] = 1.0;
    return SL_OK;
  }
  return sl_cie_srgb_weights(m->desc.wavelength_nm, nw, 1, wt, err);
}

int sl_ref_accum_image(const sl_ref_accum *acc, const sl_ref_medium *m, sl_image *layer, float *stderr_rgb,
                       sl_error *err)
{
  if (layer->width != acc->width || layer->height != acc->height || acc->n_wavelengths != m->nw)
    return sl_fail(err, SL_ERR_ARG, "reference: the image is not the accumulator's size");
  if (acc->samples < 1) return sl_fail(err, SL_ERR_ARG, "reference: no samples yet");
  const int nw = m->nw;
  double wt[3 * SL_REF_MAX_WAVELENGTHS];
  if (channel_weights(m, wt, err)) return err->code;
  const size_t np = (size_t)acc->width * acc->height;
  const double n = (double)acc->samples;
  for (size_t q = 0; q < np; ++q) {
    double rgb[3] = {0}, var[3] = {0}, transparency = 0.0;
    for (int w = 0; w < nw; ++w) {
      const double mean = acc->sum[q * nw + w] / n;
      const double v = n > 1.0 ? fmax(0.0, acc->sum2[q * nw + w] / n - mean * mean) / (n - 1.0) : 0.0;
      for (int c = 0; c < 3; ++c) {
        rgb[c] += wt[c * nw + w] * mean;
        var[c] += wt[c * nw + w] * wt[c * nw + w] * v;
      }
      /* One transparency for the layer: the channels' mean (hydrometeor extinction hardly
       * depends on wavelength, DESIGN.md). */
      transparency += acc->transparency_sum[q * nw + w] / n / nw;
    }
    for (int c = 0; c < 3; ++c) {
      layer->rgba[4 * q + c] = (float)rgb[c];
      if (stderr_rgb) stderr_rgb[3 * q + c] = (float)sqrt(var[c]);
    }
    layer->rgba[4 * q + 3] = (float)(1.0 - transparency);
    layer->transparency[q] = (float)transparency;
    layer->depth[q] = acc->depth_weight[q] > 0.0 ? (float)(acc->depth_sum[q] / acc->depth_weight[q]) : INFINITY;
  }
  return SL_OK;
}

int sl_ref_background(const sl_ref_scene *sc, const sl_camera *cam, sl_image *img, sl_error *err)
{
  if (!sc || !sc->medium || !cam || cam->width != img->width || cam->height != img->height)
    return sl_fail(err, SL_ERR_ARG, "reference background: the image is not the camera's size");
  const sl_ref_medium *m = sc->medium;
  const int nw = m->nw;
  double wt[3 * SL_REF_MAX_WAVELENGTHS];
  if (channel_weights(m, wt, err)) return err->code;
  double probe[3];
  if (sl_camera_ray(cam, 0, 0, probe))
    return sl_fail(err, SL_ERR_ARG, "reference background: camera position equals the target, or up is parallel");
  double sun[3] = {sc->sun_direction[0], sc->sun_direction[1], sc->sun_direction[2]};
  if (normalize3(sun)) return sl_fail(err, SL_ERR_ARG, "reference background: the sun direction is zero");
  sl_sky_view view;
  if (sc->atmosphere && sl_sky_view_init(&view, sc->atmosphere, cam->position, sun, err)) return err->code;
  const size_t np = (size_t)img->width * img->height;
#pragma omp parallel for schedule(static)
  for (size_t q = 0; q < np; ++q) {
    double L[SL_SKY_MAX_WAVELENGTHS] = {0};
    if (sc->atmosphere) {
      double d[3], disk[SL_SKY_MAX_WAVELENGTHS];
      sl_camera_ray(cam, (int)(q % img->width), (int)(q / img->width), d);
      sl_sky_view_segment(&view, d, 0.0, INFINITY, L, NULL);
      if (sl_sky_sun_disk_radiance(sc->atmosphere, cam->position, d, sun, disk))
        for (int w = 0; w < nw; ++w) L[w] += disk[w];
    } else {
      for (int w = 0; w < nw; ++w) L[w] = sc->sky_radiance[w];
    }
    for (int c = 0; c < 3; ++c) {
      double v = 0.0;
      for (int w = 0; w < nw; ++w) v += wt[c * nw + w] * L[w];
      img->rgba[4 * q + c] = (float)v;
    }
    img->rgba[4 * q + 3] = 1.0f;
    img->depth[q] = INFINITY;
    img->transparency[q] = 0.0f;
  }
  return SL_OK;
}
