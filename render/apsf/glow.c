/* The depth-dependent FFT convolution (Narasimhan et al., section 7.3) and eqs. 30-31; the 2D
 * PSF itself is in kernel.c. */
#include "sl_glow.h"
#include "sl_guards.h"

#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "glow_internal.h"
#include "sl_legendre.h"

static double now_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

struct sl_glow_workspace {
  int width, height, rx, ry, nx, ny;
  double *re;                    /* ny x nx real plane */
  fftw_complex *ks, *cs;         /* ny x (nx/2+1): kernel and channel spectra */
  fftw_complex *sum[3];          /* per-channel sums over layers (allocated on first use) */
  fftw_plan fwd, inv;
};

/* Smallest n >= lo whose only prime factors are 2, 3, 5, 7 (FFTW's fast sizes). */
static int fft_size(int lo)
{
  for (int n = lo < 1 ? 1 : lo;; ++n) {
    int r = n;
    while (r % 2 == 0) r /= 2;
    while (r % 3 == 0) r /= 3;
    while (r % 5 == 0) r /= 5;
    while (r % 7 == 0) r /= 7;
    if (r == 1) return n;
  }
}

void sl_glow_workspace_free(sl_glow_workspace *ws)
{
  if (!ws) return;
  if (ws->fwd) fftw_destroy_plan(ws->fwd);
  if (ws->inv) fftw_destroy_plan(ws->inv);
  fftw_free(ws->re);
  fftw_free(ws->ks);
  fftw_free(ws->cs);
  for (int c = 0; c < 3; ++c) fftw_free(ws->sum[c]);
  free(ws);
}

sl_glow_workspace *sl_glow_workspace_create(int width, int height, int rx, int ry, sl_error *err)
{
  if (width < 1 || height < 1 || width > 65536 || height > 65536) {
    sl_fail(err, SL_ERR_ARG, "glow: frame size %d x %d is out of range", width, height);
    return NULL;
  }
  sl_glow_workspace *ws = calloc(1, sizeof *ws);
  if (!ws) {
    sl_fail(err, SL_ERR_NOMEM, "glow: out of memory");
    return NULL;
  }
  ws->width = width;
  ws->height = height;
  ws->rx = rx <= 0 || rx > width - 1 ? width - 1 : rx;
  ws->ry = ry <= 0 || ry > height - 1 ? height - 1 : ry;
  ws->nx = fft_size(width + ws->rx);
  ws->ny = fft_size(height + ws->ry);
  const size_t nreal = (size_t)ws->nx * ws->ny, ncplx = (size_t)ws->ny * (ws->nx / 2 + 1);
  ws->re = fftw_malloc(sizeof(double) * nreal);
  ws->ks = fftw_malloc(sizeof(fftw_complex) * ncplx);
  ws->cs = fftw_malloc(sizeof(fftw_complex) * ncplx);
  if (!ws->re || !ws->ks || !ws->cs) {
    sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for %d x %d transforms", ws->nx, ws->ny);
    sl_glow_workspace_free(ws);
    return NULL;
  }
  ws->fwd = fftw_plan_dft_r2c_2d(ws->ny, ws->nx, ws->re, ws->cs, FFTW_ESTIMATE);
  ws->inv = fftw_plan_dft_c2r_2d(ws->ny, ws->nx, ws->cs, ws->re, FFTW_ESTIMATE);
  if (!ws->fwd || !ws->inv) {
    sl_fail(err, SL_ERR_NOMEM, "glow: FFTW could not plan %d x %d transforms", ws->nx, ws->ny);
    sl_glow_workspace_free(ws);
    return NULL;
  }
  return ws;
}

void sl_glow_workspace_size(const sl_glow_workspace *ws, int *nx, int *ny)
{
  *nx = ws->nx;
  *ny = ws->ny;
}

/* The kernel wrapped around the origin (offset d at index d mod n) into ws->ks. The
 * workspace's size (>= frame + radius) keeps wrapped kernel values off the frame. Either from
 * a sampled kernel or straight from the model (no kernel-sized array in between). */
static void kernel_spectrum_any(sl_glow_workspace *ws, const sl_glow_kernel *k, const sl_glow_model *km)
{
  const int nx = ws->nx, ny = ws->ny, rx = k ? k->rx : ws->rx, ry = k ? k->ry : ws->ry, kw = 2 * rx + 1;
  memset(ws->re, 0, sizeof(double) * (size_t)nx * ny);
  for (int dy = -ry; dy <= ry; ++dy) {
    double *row = ws->re + (size_t)((dy + ny) % ny) * nx;
    if (k) {
      const double *kr = k->w + (size_t)(dy + ry) * kw + rx;
      for (int dx = -rx; dx <= rx; ++dx) row[(dx + nx) % nx] = kr[dx];
    } else {
      for (int dx = 0; dx <= rx; ++dx) row[dx] = sl_glow_model_value(km, dx, dy);
      for (int dx = 1; dx <= rx; ++dx) row[nx - dx] = row[dx];
    }
  }
  fftw_execute_dft_r2c(ws->fwd, ws->re, ws->ks);
}
static void kernel_spectrum(sl_glow_workspace *ws, const sl_glow_kernel *k) { kernel_spectrum_any(ws, k, NULL); }

/* The spectrum of one float plane, zero-padded, into ws->cs. Returns 0 for an all-zero plane. */
static int plane_spectrum(sl_glow_workspace *ws, const float *src)
{
  const int nx = ws->nx, W = ws->width, H = ws->height;
  int any = 0;
  for (size_t i = 0; i < (size_t)W * H && !any; ++i) any = src[i] != 0.0f;
  if (!any) return 0;
  memset(ws->re, 0, sizeof(double) * (size_t)nx * ws->ny);
  for (int y = 0; y < H; ++y) {
    const float *s = src + (size_t)y * W;
    double *row = ws->re + (size_t)y * nx;
    for (int x = 0; x < W; ++x) row[x] = s[x];
  }
  fftw_execute_dft_r2c(ws->fwd, ws->re, ws->cs);
  return 1;
}

/* dst (+)= cs * ks / (nx ny): FFTW's transforms are unnormalised. */
static void multiply_spectra(sl_glow_workspace *ws, fftw_complex *dst, int add)
{
  const size_t ncplx = (size_t)ws->ny * (ws->nx / 2 + 1);
  const double scale = 1.0 / ((double)ws->nx * ws->ny);
  for (size_t i = 0; i < ncplx; ++i) {
    const double a = ws->cs[i][0], b = ws->cs[i][1], kr = ws->ks[i][0], ki = ws->ks[i][1];
    const double re = (a * kr - b * ki) * scale, im = (a * ki + b * kr) * scale;
    if (add) {
      dst[i][0] += re;
      dst[i][1] += im;
    } else {
      dst[i][0] = re;
      dst[i][1] = im;
    }
  }
}

/* accum += the frame part of the inverse transform of spec (which it destroys). */
static void inverse_into(sl_glow_workspace *ws, fftw_complex *spec, float *accum)
{
  fftw_execute_dft_c2r(ws->inv, spec, ws->re);
  for (int y = 0; y < ws->height; ++y) {
    float *o = accum + (size_t)y * ws->width;
    const double *row = ws->re + (size_t)y * ws->nx;
    for (int x = 0; x < ws->width; ++x) o[x] += (float)row[x];
  }
}

int sl_glow_convolve(sl_glow_workspace *ws, const sl_glow_kernel *k, const float *const *src, float *const *accum,
                     int n_channels, sl_error *err)
{
  if (k->rx > ws->rx || k->ry > ws->ry)
    return sl_fail(err, SL_ERR_ARG, "glow: kernel radius %d x %d exceeds the workspace's %d x %d", k->rx, k->ry, ws->rx,
                   ws->ry);
  int kernel_ready = 0;
  for (int c = 0; c < n_channels; ++c) {
    if (!plane_spectrum(ws, src[c])) continue;
    if (!kernel_ready) {
      kernel_spectrum(ws, k); /* through re, into ks: the plane's spectrum in cs stays */
      kernel_ready = 1;
    }
    multiply_spectra(ws, ws->cs, 0);
    inverse_into(ws, ws->cs, accum[c]);
  }
  return SL_OK;
}

double sl_airlight_path(double scene_radiance, double horizon_brightness, double T)
{
  const double t = exp(-T);
  return scene_radiance * t + horizon_brightness * (1.0 - t); /* Narasimhan et al., eqs. 30-31 */
}

/* The part of the cone of directions s at angle acos(mu) around a sight line d at elevation e
 * that lies above the horizontal: s_z = mu sin e + sqrt(1 - mu^2) cos e cos(phi) > 0. */
static double cone_share_above(double mu, double sin_e, double cos_e)
{
  const double s = sl_safe_sqrt(1.0 - mu * mu), z = mu * sin_e;
  if (s * cos_e <= 0.0) return z > 0.0 ? 1.0 : z < 0.0 ? 0.0 : 0.5; /* the cone is one direction */
  const double c = -z / (s * cos_e);
  return acos(sl_clamp_cosine(c)) / SL_PI;
}

/* The cosine mu at which Henyey-Greenstein's cumulative distribution over mu reaches u:
 * C(mu) = (1 - q^2) / (2 q) (1 / sqrt(1 + q^2 - 2 q mu) - 1 / (1 + q)). */
static double hg_inverse_cdf(double q, double u)
{
  if (fabs(q) < 1e-9) return 2.0 * u - 1.0;
  const double t = (1.0 - q * q) / (1.0 - q + 2.0 * q * u);
  const double mu = (1.0 + q * q - t * t) / (2.0 * q);
  return sl_clamp_cosine(mu);
}
static double hg_cdf(double q, double mu)
{
  if (fabs(q) < 1e-9) return 0.5 * (mu + 1.0);
  return (1.0 - q * q) / (2.0 * q) * (1.0 / sqrt(1.0 + q * q - 2.0 * q * mu) - 1.0 / (1.0 + q));
}

double sl_airlight_upper_share(double q, double elevation_rad)
{
  /* In u = C(mu) the phase function's weight is uniform (its sharp forward peak is gone), so F is
   * the mean of a(mu(u), e) over u in [0, 1]: Gauss-Legendre on the pieces between the kinks of
   * a at mu = -cos e and cos e. */
  enum { N = 96 };
  double x[N], w[N];
  sl_gauss_legendre(N, x, w);
  const double sin_e = sin(elevation_rad), cos_e = cos(elevation_rad), k = fabs(cos_e);
  const double edges[4] = {0.0, hg_cdf(q, -k), hg_cdf(q, k), 1.0};
  double share = 0.0;
  for (int p = 0; p < 3; ++p) {
    const double h = 0.5 * (edges[p + 1] - edges[p]);
    if (!(h > 0.0)) continue;
    for (int i = 0; i < N; ++i)
      share += h * w[i] * cone_share_above(hg_inverse_cdf(q, edges[p] + h * (x[i] + 1.0)), sin_e, cos_e);
  }
  return share;
}

double sl_airlight_source(double albedo, double q, double elevation_rad, double radiance_up, double radiance_down)
{
  const double F = sl_airlight_upper_share(q, elevation_rad);
  return albedo * (radiance_up * F + radiance_down * (1.0 - F));
}

/* A source: inside the medium (T > 0) and bright enough, or marked by the caller. */
static int is_source(const sl_glow_params *p, const float *px, double T, size_t i)
{
  if (!(T > 0.0)) return 0;
  return (p->source_mask && p->source_mask[i]) || fmax(px[0], fmax(px[1], px[2])) >= p->threshold;
}

static double airlight_at(const sl_glow_params *p, size_t i, int c)
{
  return p->airlight_map ? p->airlight_map[3 * i + c] : p->airlight[c];
}

static double channel_scale(const sl_glow_params *p, int c)
{
  return p->channel_sigma_scale[c] > 0.0 ? p->channel_sigma_scale[c] : 1.0;
}

void sl_glow_params_defaults(sl_glow_params *p)
{
  memset(p, 0, sizeof *p);
  p->medium.albedo = 1.0;
  p->medium.q = 0.9;
  p->fov_y_deg = 40.0;
  p->threshold = 1.0;
  p->n_layers = 8;
  p->norm = SL_GLOW_FLUENCE;
  p->attenuate = 1;
  p->tolerance = 1e-4;
}

/* The arguments sl_glow_apply can work with, or a one-line error. */
static int glow_check(const sl_glow_workspace *ws, const sl_glow_params *p, const sl_image *in, const sl_image *out,
                      sl_error *err)
{
  const int W = in->width, H = in->height;
  if (W != ws->width || H != ws->height)
    return sl_fail(err, SL_ERR_ARG, "glow: workspace is for %d x %d, the image is %d x %d", ws->width, ws->height, W, H);
  if (out->width != W || out->height != H || !out->rgba)
    return sl_fail(err, SL_ERR_ARG, "glow: output image must be allocated at %d x %d", W, H);
  if (p->n_layers < 1 || p->n_layers > SL_GLOW_MAX_LAYERS)
    return sl_fail(err, SL_ERR_ARG, "glow: layers must be 1..%d (got %d)", SL_GLOW_MAX_LAYERS, p->n_layers);
  if (!(p->fov_y_deg > 0.0 && p->fov_y_deg < 170.0))
    return sl_fail(err, SL_ERR_ARG, "glow: field of view must be in (0, 170) degrees (got %g)", p->fov_y_deg);
  if (!(p->fixed_T > 0.0) && !(p->sigma > 0.0 && isfinite(p->sigma)))
    return sl_fail(err, SL_ERR_ARG, "glow: give an extinction coefficient > 0 or a fixed optical thickness");
  if (!(p->fixed_T > 0.0) && !in->depth)
    return sl_fail(err, SL_ERR_ARG, "glow: the image has no depth and no fixed optical thickness was given");
  if (!(p->threshold > 0.0)) return sl_fail(err, SL_ERR_ARG, "glow: threshold must be > 0 (got %g)", p->threshold);
  return SL_OK;
}

/* Optical distance per pixel into Tpx: the view-axis depth times the secant of the pixel's angle
 * from the axis is the distance to the camera (f: the focal length in pixels). NAN marks pixels
 * outside the medium. The sources' count and their least and largest T into st. */
static int glow_optical_distances(const sl_glow_params *p, const sl_image *in, double f, double *Tpx,
                                  sl_glow_stats *st, sl_error *err)
{
  const int W = in->width, H = in->height;
  int sources = 0;
  double Tmin = INFINITY, Tmax = 0.0;
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const size_t i = (size_t)y * W + x;
      const float *px = in->rgba + 4 * i;
      if (!isfinite(px[0]) || !isfinite(px[1]) || !isfinite(px[2]))
        return sl_fail(err, SL_ERR_DATA, "glow: pixel (%d, %d) has a non-finite colour", x, y);
      double T;
      if (p->fixed_T > 0.0) {
        T = p->fixed_T;
      } else {
        const double z = in->depth[i];
        if (isnan(z) || z < 0.0)
          return sl_fail(err, SL_ERR_DATA, "glow: pixel (%d, %d) has depth %g (must be >= 0 or +inf)", x, y, z);
        const double u = (x + 0.5 - 0.5 * W) / f, v = (y + 0.5 - 0.5 * H) / f;
        double distance = isinf(z) ? (p->sky_distance > 0.0 ? p->sky_distance : NAN) : z * sqrt(1.0 + u * u + v * v);
        if (p->bank_depth > 0.0 && distance > p->bank_depth) distance = p->bank_depth;
        T = p->sigma * distance;
      }
      Tpx[i] = T;
      if (is_source(p, px, T, i)) {
        ++sources;
        if (T < Tmin) Tmin = T;
        if (T > Tmax) Tmax = T;
      }
    }
  }
  st->sources = sources;
  st->T_min = sources ? Tmin : 0.0;
  st->T_max = Tmax;
  return SL_OK;
}

/* The sources' glow, layer by layer: layers evenly spaced in log T, at most n_layers and none
 * closer than 2 % in T (the PSF hardly changes within that); a source between two layers feeds
 * both with linear weights in log T, so its glow changes continuously with its depth. The
 * convolution is linear: the layers' products are summed in the frequency domain (ws->sum) and
 * each channel goes back once into glow[c], so a layer costs one kernel and three forward
 * transforms. src: three planes of scratch. */
static int glow_layers(sl_glow_workspace *ws, const sl_glow_params *p, const sl_image *in, const double *Tpx, double f,
                       float *src[3], float *glow[3], sl_glow_model *km, sl_glow_stats *st, sl_error *err)
{
  const size_t npx = (size_t)in->width * in->height;
  const double Tmin = st->T_min, Tmax = st->T_max;
  int L = st->sources ? 1 + (int)ceil(log(Tmax / Tmin) / log(1.02) - 1e-9) : 0;
  if (L > p->n_layers) L = p->n_layers;
  const double lmin = st->sources ? log(Tmin) : 0.0, lstep = L > 1 ? (log(Tmax) - lmin) / (L - 1) : 1.0;
  int used[3] = {0, 0, 0};
  for (int c = 0; c < 3 && L > 0; ++c) {
    if (!ws->sum[c]) ws->sum[c] = fftw_malloc(sizeof(fftw_complex) * (size_t)ws->ny * (ws->nx / 2 + 1));
    if (!ws->sum[c]) return sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for %d x %d spectra", ws->nx, ws->ny);
  }
  for (int l = 0; l < L; ++l) {
    int any = 0;
    for (size_t i = 0; i < npx; ++i) {
      const float *px = in->rgba + 4 * i;
      double w = 0.0;
      if (is_source(p, px, Tpx[i], i)) {
        const double d = L > 1 ? fabs((log(Tpx[i]) - lmin) / lstep - l) : 0.0;
        w = d < 1.0 ? 1.0 - d : 0.0;
      }
      for (int c = 0; c < 3; ++c) src[c][i] = (float)(w * px[c]);
      any |= w > 0.0;
    }
    if (!any) continue; /* no sources at this depth: no work */
    const double Tl = exp(lmin + l * lstep);
    double t_kernel = 0.0, t_fft = 0.0;
    const sl_apsf_medium *built = NULL;
    double built_scale = 0.0;
    for (int c = 0; c < 3; ++c) {
      const sl_apsf_medium *mc = p->channel_medium[c] ? p->channel_medium[c] : &p->medium;
      const double scale = channel_scale(p, c);
      double t0 = now_s();
      if (!plane_spectrum(ws, src[c])) continue;
      double t1 = now_s();
      t_fft += t1 - t0;
      if (mc != built || scale != built_scale) {
        const int rc = sl_glow_model_build(km, mc, Tl * scale, f, ws->rx, ws->ry, p->norm, p->tolerance, err);
        if (rc) return rc;
        t0 = now_s();
        t_kernel += t0 - t1;
        kernel_spectrum_any(ws, NULL, km);
        t_fft += now_s() - t0;
        built = mc, built_scale = scale;
      }
      t0 = now_s();
      multiply_spectra(ws, ws->sum[c], used[c]);
      t_fft += now_s() - t0;
      used[c] = 1;
    }
    st->kernel_seconds += t_kernel;
    st->convolve_seconds += t_fft;
    st->layer_T[st->layers_used] = Tl;
    st->layer_terms[st->layers_used] = km->terms;
    ++st->layers_used;
    if (p->progress) p->progress(p->progress_user, (l + 1.0) / (L + 1.0));
  }
  const double t0 = now_s();
  for (int c = 0; c < 3; ++c)
    if (used[c]) inverse_into(ws, ws->sum[c], glow[c]);
  st->convolve_seconds += now_s() - t0;
  return SL_OK;
}

/* The frame: each pixel's own light attenuated by the medium in front of it, with that medium's
 * airlight, plus the glow; a source's light is all in the glow (the kernel's Dirac included),
 * and the medium in front of it still adds its airlight. */
static void glow_compose(const sl_glow_params *p, const sl_image *in, const double *Tpx, float *glow[3], sl_image *out)
{
  const size_t npx = (size_t)in->width * in->height;
  for (size_t i = 0; i < npx; ++i) {
    const float *px = in->rgba + 4 * i;
    float *o = out->rgba + 4 * i;
    const double T = Tpx[i];
    const int source = is_source(p, px, T, i);
    const float a = px[3];
    for (int c = 0; c < 3; ++c) {
      double base = px[c];
      if (source) base = p->attenuate ? sl_airlight_path(0.0, airlight_at(p, i, c), T * channel_scale(p, c)) : 0.0;
      else if (T > 0.0 && p->attenuate) base = sl_airlight_path(px[c], airlight_at(p, i, c), T * channel_scale(p, c));
      o[c] = (float)(base + glow[c][i]);
    }
    o[3] = a;
  }
  if (out != in) {
    if (out->depth && in->depth) memcpy(out->depth, in->depth, sizeof(float) * npx);
    if (out->transparency && in->transparency) memcpy(out->transparency, in->transparency, sizeof(float) * npx);
  }
}

int sl_glow_apply(sl_glow_workspace *ws, const sl_glow_params *p, const sl_image *in, sl_image *out,
                  sl_glow_stats *stats, sl_error *err)
{
  int rc = glow_check(ws, p, in, out, err);
  if (rc) return rc;
  const size_t npx = (size_t)in->width * in->height;
  const double f = sl_glow_focal_px(in->height, p->fov_y_deg * SL_PI / 180.0);
  double *Tpx = malloc(sizeof(double) * npx);
  float *planes = calloc(npx * 6, sizeof(float));
  sl_glow_model *km = malloc(sizeof *km);
  if (!Tpx || !planes || !km) {
    free(Tpx);
    free(planes);
    free(km);
    return sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for a %d x %d frame", in->width, in->height);
  }
  sl_glow_stats st;
  memset(&st, 0, sizeof st);
  float *src[3] = {planes, planes + npx, planes + 2 * npx};
  float *glow[3] = {planes + 3 * npx, planes + 4 * npx, planes + 5 * npx};
  rc = glow_optical_distances(p, in, f, Tpx, &st, err);
  if (!rc) rc = glow_layers(ws, p, in, Tpx, f, src, glow, km, &st, err);
  if (!rc) {
    glow_compose(p, in, Tpx, glow, out);
    if (p->progress) p->progress(p->progress_user, 1.0);
  }
  if (stats) *stats = st;
  free(Tpx);
  free(planes);
  free(km);
  return rc;
}
