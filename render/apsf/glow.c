/* The 2D PSF and the depth-dependent FFT convolution (Narasimhan et al., sections 7.2-7.3). */
#include "sl_glow.h"

#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sl_legendre.h"

static double now_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

double sl_glow_focal_px(int height, double fov_y_rad) { return 0.5 * height / tan(0.5 * fov_y_rad); }

void sl_glow_kernel_free(sl_glow_kernel *k)
{
  free(k->w);
  k->w = NULL;
}

/* Solid angle of a unit pixel at r pixels from the principal point: dA cos / d^2 = f / d^3. */
static double pixel_solid_angle(double f, double r2) { return f / ((f * f + r2) * sqrt(f * f + r2)); }

/* The 2D PSF as a function of the pixel offset: 8 x 8 sub-samples within 6 pixels of the
 * source (where the profile changes within a pixel), a radial table uniform in sqrt(r) beyond
 * (the kernel of an HD frame has 8 M taps per layer: no atan per tap). */
enum { NEAR = 6, SUB = 8, NR = 16384 };
typedef struct kernel_model {
  double near[NEAR][NEAR]; /* |dx|, |dy| < 6, Dirac included */
  double radial[NR];
  double inv_r_table, scale;
  double T, blend, direct, series_scale;
  int terms;
} kernel_model;

static int model_build(kernel_model *km, const sl_apsf_medium *m, double T, double focal_px, int rx, int ry,
                       sl_glow_norm norm, double tolerance, sl_error *err)
{
  if (rx < 0 || ry < 0 || (double)(2 * rx + 1) * (2 * ry + 1) > 1e9)
    return sl_fail(err, SL_ERR_ARG, "glow: kernel size %d x %d is out of range", 2 * rx + 1, 2 * ry + 1);
  if (!(focal_px > 0.0) || !isfinite(focal_px))
    return sl_fail(err, SL_ERR_ARG, "glow: focal length must be > 0 pixels (got %g)", focal_px);
  const double r_max = sqrt((double)rx * rx + (double)ry * ry) + 2.0 * NEAR;
  sl_apsf_profile prof;
  if (sl_apsf_profile_build(&prof, m, T, tolerance, atan(r_max / focal_px), 4096, err)) return err->code;
  km->T = T;
  km->blend = prof.blend;
  km->direct = prof.direct;
  km->series_scale = prof.series_scale;
  km->terms = prof.terms;
  km->inv_r_table = 1.0 / r_max;
  for (int i = 0; i < NR; ++i) {
    const double u = (double)i / (NR - 1), r = r_max * u * u;
    km->radial[i] = sl_apsf_profile_eval(&prof, atan(r / focal_px)) * pixel_solid_angle(focal_px, r * r);
  }
  for (int dy = 0; dy < NEAR; ++dy)
    for (int dx = 0; dx < NEAR; ++dx) {
      double v = 0.0;
      for (int j = 0; j < SUB; ++j)
        for (int i = 0; i < SUB; ++i) {
          const double x = dx + (i + 0.5) / SUB - 0.5, y = dy + (j + 0.5) / SUB - 0.5, s2 = x * x + y * y;
          v += sl_apsf_profile_eval(&prof, atan(sqrt(s2) / focal_px)) * pixel_solid_angle(focal_px, s2);
        }
      km->near[dy][dx] = v / (SUB * SUB);
    }
  km->near[0][0] += prof.direct; /* eq. 30's Dirac: the unscattered beam */
  sl_apsf_profile_free(&prof);
  km->scale = 1.0;
  if (norm == SL_GLOW_PEAK) {
    if (!(km->near[0][0] > 0.0))
      return sl_fail(err, SL_ERR_DATA, "glow: the PSF at T = %g has no positive centre value", T);
    km->scale = 1.0 / km->near[0][0];
  }
  return SL_OK;
}

static inline double model_value(const kernel_model *km, int dx, int dy)
{
  dx = dx < 0 ? -dx : dx;
  dy = dy < 0 ? -dy : dy;
  if (dx < NEAR && dy < NEAR && dx * dx + dy * dy < NEAR * NEAR) return km->scale * km->near[dy][dx];
  const double t = sqrt(sqrt((double)dx * dx + (double)dy * dy) * km->inv_r_table) * (NR - 1);
  int i = (int)t;
  if (i > NR - 2) i = NR - 2;
  return km->scale * (km->radial[i] + (t - i) * (km->radial[i + 1] - km->radial[i]));
}

int sl_glow_kernel_build(sl_glow_kernel *k, const sl_apsf_medium *m, double T, double focal_px, int rx, int ry,
                         sl_glow_norm norm, double tolerance, sl_error *err)
{
  k->w = NULL;
  kernel_model *km = malloc(sizeof *km);
  if (!km) return sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for a kernel");
  int rc = model_build(km, m, T, focal_px, rx, ry, norm, tolerance, err);
  const int nx = 2 * rx + 1, ny = 2 * ry + 1;
  if (rc == SL_OK && !(k->w = malloc(sizeof(double) * (size_t)nx * (size_t)ny)))
    rc = sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for a %d x %d kernel", nx, ny);
  if (rc) {
    free(km);
    return rc;
  }
  k->rx = rx;
  k->ry = ry;
  k->T = T;
  k->blend = km->blend;
  k->direct = km->direct;
  k->series_scale = km->series_scale;
  k->terms = km->terms;
  double sum = 0.0;
  for (int dy = -ry; dy <= ry; ++dy)
    for (int dx = -rx; dx <= rx; ++dx) sum += k->w[(size_t)(dy + ry) * nx + dx + rx] = model_value(km, dx, dy);
  k->sum = sum;
  free(km);
  return SL_OK;
}

int sl_glow_kernel_build_sphere(sl_glow_kernel *k, const sl_apsf_medium *m, double T_radius, double distance_ratio,
                                double focal_px, int rx, int ry, double tolerance, sl_error *err)
{
  k->w = NULL;
  if (!(T_radius >= SL_APSF_BLEND_HI) || !isfinite(T_radius))
    return sl_fail(err, SL_ERR_ARG, "glow: a sphere seen from outside needs its optical radius >= %g (got %g)",
                   SL_APSF_BLEND_HI, T_radius);
  if (!(distance_ratio > 1.0) || !isfinite(distance_ratio))
    return sl_fail(err, SL_ERR_ARG, "glow: the camera must be outside the sphere (distance ratio %g)", distance_ratio);
  if (rx < 0 || ry < 0 || (double)(2 * rx + 1) * (2 * ry + 1) > 1e9 || !(focal_px > 0.0))
    return sl_fail(err, SL_ERR_ARG, "glow: kernel %d x %d or focal length %g out of range", 2 * rx + 1, 2 * ry + 1,
                   focal_px);
  sl_apsf_series s;
  if (sl_apsf_series_init(&s, m, T_radius, tolerance, 0, err)) return err->code;
  const int nx = 2 * rx + 1, ny = 2 * ry + 1;
  k->w = malloc(sizeof(double) * (size_t)nx * (size_t)ny);
  if (!k->w) {
    sl_apsf_series_free(&s);
    return sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for a %d x %d kernel", nx, ny);
  }
  /* The unscattered share as in sl_apsf_profile: a Dirac e^{-T}, the series scaled by s. */
  const double direct = exp(-T_radius), s_frac = fmax(0.0, 1.0 - exp((3.0 * (1.0 - m->albedo) - 1.0) * T_radius));
  const double scale = s_frac * distance_ratio * distance_ratio * T_radius * T_radius / (4.0 * SL_PI);
  double sum = 0.0;
  for (int dy = -ry; dy <= ry; ++dy)
    for (int dx = -rx; dx <= rx; ++dx) {
      const int near = dx * dx + dy * dy < NEAR * NEAR;
      const int sub = near ? SUB : 1;
      double v = 0.0;
      for (int j = 0; j < sub; ++j)
        for (int i = 0; i < sub; ++i) {
          const double x = dx + (near ? (i + 0.5) / sub - 0.5 : 0.0), y = dy + (near ? (j + 0.5) / sub - 0.5 : 0.0);
          const double r2 = x * x + y * y;
          const double mu = sl_apsf_mu_outside(distance_ratio, 1.0, atan(sqrt(r2) / focal_px)); /* eq. 28 */
          if (mu > -1.5) v += scale * sl_apsf_series_eval(&s, mu) * pixel_solid_angle(focal_px, r2);
        }
      v /= sub * sub;
      if (dx == 0 && dy == 0) v += direct;
      k->w[(size_t)(dy + ry) * nx + dx + rx] = v;
      sum += v;
    }
  k->rx = rx;
  k->ry = ry;
  k->T = T_radius;
  k->blend = 1.0;
  k->direct = direct;
  k->series_scale = s_frac;
  k->terms = s.terms;
  k->sum = sum;
  sl_apsf_series_free(&s);
  return SL_OK;
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
    sl_glow_workspace_free(ws);
    sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for %d x %d transforms", ws->nx, ws->ny);
    return NULL;
  }
  ws->fwd = fftw_plan_dft_r2c_2d(ws->ny, ws->nx, ws->re, ws->cs, FFTW_ESTIMATE);
  ws->inv = fftw_plan_dft_c2r_2d(ws->ny, ws->nx, ws->cs, ws->re, FFTW_ESTIMATE);
  if (!ws->fwd || !ws->inv) {
    sl_glow_workspace_free(ws);
    sl_fail(err, SL_ERR_NOMEM, "glow: FFTW could not plan %d x %d transforms", ws->nx, ws->ny);
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
static void kernel_spectrum_any(sl_glow_workspace *ws, const sl_glow_kernel *k, const kernel_model *km)
{
  const int nx = ws->nx, ny = ws->ny, rx = k ? k->rx : ws->rx, ry = k ? k->ry : ws->ry, kw = 2 * rx + 1;
  memset(ws->re, 0, sizeof(double) * (size_t)nx * ny);
  for (int dy = -ry; dy <= ry; ++dy) {
    double *row = ws->re + (size_t)((dy + ny) % ny) * nx;
    if (k) {
      const double *kr = k->w + (size_t)(dy + ry) * kw + rx;
      for (int dx = -rx; dx <= rx; ++dx) row[(dx + nx) % nx] = kr[dx];
    } else {
      for (int dx = 0; dx <= rx; ++dx) row[dx] = model_value(km, dx, dy);
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

int sl_glow_apply(sl_glow_workspace *ws, const sl_glow_params *p, const sl_image *in, sl_image *out,
                  sl_glow_stats *stats, sl_error *err)
{
  const int W = in->width, H = in->height;
  const size_t npx = (size_t)W * H;
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
  const double f = sl_glow_focal_px(H, p->fov_y_deg * SL_PI / 180.0);

  /* Optical distance per pixel: the view-axis depth times the secant of the pixel's angle
   * from the axis is the distance to the camera. NAN marks pixels outside the medium. */
  double *Tpx = malloc(sizeof(double) * npx);
  float *planes = calloc(npx * 6, sizeof(float));
  kernel_model *km = malloc(sizeof *km);
  if (!Tpx || !planes || !km) {
    free(Tpx);
    free(planes);
    free(km);
    return sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for a %d x %d frame", W, H);
  }
  int rc = SL_OK, sources = 0;
  double Tmin = INFINITY, Tmax = 0.0;
  for (int y = 0; y < H && rc == SL_OK; ++y) {
    for (int x = 0; x < W; ++x) {
      const size_t i = (size_t)y * W + x;
      const float *px = in->rgba + 4 * i;
      if (!isfinite(px[0]) || !isfinite(px[1]) || !isfinite(px[2])) {
        rc = sl_fail(err, SL_ERR_DATA, "glow: pixel (%d, %d) has a non-finite colour", x, y);
        break;
      }
      double T;
      if (p->fixed_T > 0.0) {
        T = p->fixed_T;
      } else {
        const double z = in->depth[i];
        if (isnan(z) || z < 0.0) {
          rc = sl_fail(err, SL_ERR_DATA, "glow: pixel (%d, %d) has depth %g (must be >= 0 or +inf)", x, y, z);
          break;
        }
        const double u = (x + 0.5 - 0.5 * W) / f, v = (y + 0.5 - 0.5 * H) / f;
        if (isinf(z)) T = p->sky_distance > 0.0 ? p->sigma * p->sky_distance : NAN;
        else T = p->sigma * z * sqrt(1.0 + u * u + v * v);
      }
      Tpx[i] = T;
      const double peak = fmax(px[0], fmax(px[1], px[2]));
      if (T > 0.0 && peak >= p->threshold) {
        ++sources;
        if (T < Tmin) Tmin = T;
        if (T > Tmax) Tmax = T;
      }
    }
  }
  sl_glow_stats st;
  memset(&st, 0, sizeof st);
  st.sources = sources;
  st.T_min = sources ? Tmin : 0.0;
  st.T_max = Tmax;
  float *src[3] = {planes, planes + npx, planes + 2 * npx};
  float *glow[3] = {planes + 3 * npx, planes + 4 * npx, planes + 5 * npx};
  /* Layers evenly spaced in log T; a source between two layers feeds both with linear weights
   * in log T, so its glow changes continuously with its depth. */
  /* At most n_layers, and none closer than 2 % in T: the PSF hardly changes within that. */
  int L = sources ? 1 + (int)ceil(log(Tmax / Tmin) / log(1.02) - 1e-9) : 0;
  if (L > p->n_layers) L = p->n_layers;
  const double lmin = sources ? log(Tmin) : 0.0, lstep = L > 1 ? (log(Tmax) - lmin) / (L - 1) : 1.0;
  /* The convolution is linear: the layers' products are summed in the frequency domain and
   * each channel goes back once, so a layer costs one kernel and three forward transforms. */
  int used[3] = {0, 0, 0};
  for (int c = 0; c < 3 && L > 0 && rc == SL_OK; ++c) {
    if (!ws->sum[c]) ws->sum[c] = fftw_malloc(sizeof(fftw_complex) * (size_t)ws->ny * (ws->nx / 2 + 1));
    if (!ws->sum[c]) rc = sl_fail(err, SL_ERR_NOMEM, "glow: out of memory for %d x %d spectra", ws->nx, ws->ny);
  }
  for (int l = 0; l < L && rc == SL_OK; ++l) {
    int any = 0;
    for (size_t i = 0; i < npx; ++i) {
      const float *px = in->rgba + 4 * i;
      double w = 0.0;
      if (Tpx[i] > 0.0 && fmax(px[0], fmax(px[1], px[2])) >= p->threshold) {
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
    for (int c = 0; c < 3 && rc == SL_OK; ++c) {
      const sl_apsf_medium *mc = p->channel_medium[c] ? p->channel_medium[c] : &p->medium;
      double t0 = now_s();
      if (!plane_spectrum(ws, src[c])) continue;
      double t1 = now_s();
      t_fft += t1 - t0;
      if (mc != built) {
        rc = model_build(km, mc, Tl, f, ws->rx, ws->ry, p->norm, p->tolerance, err);
        if (rc) break;
        t0 = now_s();
        t_kernel += t0 - t1;
        kernel_spectrum_any(ws, NULL, km);
        t_fft += now_s() - t0;
        built = mc;
      }
      t0 = now_s();
      multiply_spectra(ws, ws->sum[c], used[c]);
      t_fft += now_s() - t0;
      used[c] = 1;
    }
    if (rc) break;
    st.kernel_seconds += t_kernel;
    st.convolve_seconds += t_fft;
    st.layer_T[st.layers_used] = Tl;
    st.layer_terms[st.layers_used] = km->terms;
    ++st.layers_used;
    if (p->progress) p->progress(p->progress_user, (l + 1.0) / (L + 1.0));
  }
  if (rc == SL_OK) {
    const double t0 = now_s();
    for (int c = 0; c < 3; ++c)
      if (used[c]) inverse_into(ws, ws->sum[c], glow[c]);
    st.convolve_seconds += now_s() - t0;
  }
  if (rc == SL_OK) {
    for (size_t i = 0; i < npx; ++i) {
      const float *px = in->rgba + 4 * i;
      float *o = out->rgba + 4 * i;
      const double T = Tpx[i];
      const int is_source = T > 0.0 && fmax(px[0], fmax(px[1], px[2])) >= p->threshold;
      const float a = px[3];
      for (int c = 0; c < 3; ++c) {
        double base = px[c];
        if (is_source) {
          base = 0.0; /* all of it is in the glow, the unscattered beam included (the kernel's Dirac) */
        } else if (T > 0.0 && p->attenuate) {
          const double t = exp(-T);
          base = px[c] * t + p->airlight[c] * (1.0 - t); /* Narasimhan et al., eqs. 30-31 */
        }
        o[c] = (float)(base + glow[c][i]);
      }
      o[3] = a;
    }
    if (out != in) {
      if (out->depth && in->depth) memcpy(out->depth, in->depth, sizeof(float) * npx);
      if (out->transparency && in->transparency) memcpy(out->transparency, in->transparency, sizeof(float) * npx);
    }
    if (p->progress) p->progress(p->progress_user, 1.0);
  }
  if (stats) *stats = st;
  free(Tpx);
  free(planes);
  free(km);
  return rc;
}
