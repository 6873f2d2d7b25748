/* Glows around light sources: the 2D point spread function of a pinhole camera and the
 * depth-dependent convolution of Narasimhan et al., sections 7.2-7.3, with the attenuation and
 * airlight of eqs. 30-31. Plan once per frame size (sl_glow_workspace: FFTW plans and buffers),
 * then convolve as many frames as needed. FFTW's planner is not thread-safe: create workspaces
 * outside parallel regions; one workspace serves one thread at a time. */
#ifndef SL_GLOW_H
#define SL_GLOW_H

#include "sl_apsf.h"
#include "sl_image.h"
#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sl_glow_norm {
  /* Kernel = fluence weight (sl_apsf.h) times each pixel's solid angle: a source's image energy
   * E becomes E times the model's fluence fraction inside the frame (e^{-3(1-W0)T} over the
   * whole sphere; less in a pinhole's view). Resolution independent. */
  SL_GLOW_FLUENCE = 0,
  /* Kernel divided by its centre value (the paper's section 2.2.3 practical choice): the
   * source pixel keeps its value; the glow's energy then depends on the pixel size. */
  SL_GLOW_PEAK = 1
} sl_glow_norm;

/* A 2D PSF sampled on pixel offsets -rx..rx, -ry..ry (row-major, offset (dx, dy) at
 * w[(dy + ry) * (2 rx + 1) + dx + rx]). Pinhole camera at the source's distance inside the
 * medium: a pixel at r pixels from the source sees mu = cos(atan(r / focal_px)) (Fig. 10),
 * the same at every position in the frame (exact at the principal point; see docs/APSF.md). */
typedef struct sl_glow_kernel {
  int rx, ry;
  double *w;
  double sum;      /* sum of w */
  double T, blend, direct, series_scale; /* as in sl_apsf_profile */
  int terms;
} sl_glow_kernel;

int sl_glow_kernel_build(sl_glow_kernel *k, const sl_apsf_medium *m, double T, double focal_px, int rx, int ry,
                         sl_glow_norm norm, double tolerance, sl_error *err);
void sl_glow_kernel_free(sl_glow_kernel *k);

/* The same for a camera outside a spherical medium with the source at its centre (eq. 28, the
 * paper's milk bowl): radius R with optical radius T_radius = sigma R >= SL_APSF_BLEND_HI, camera
 * at distance D = distance_ratio * R (> 1) from the centre, looking at it. A pixel at r pixels
 * from the centre sees the field leaving the sphere at mu = sl_apsf_mu_outside(D, R, atan(r/f))
 * (0 where its ray misses the sphere); the radiance is carried unchanged through the clear air
 * outside, and the weight is relative to the bare source's vacuum fluence I0 / D^2, so the
 * fluence weight becomes (D/R)^2 T_radius^2 S / (4 pi), with the Dirac e^{-T_radius}. */
int sl_glow_kernel_build_sphere(sl_glow_kernel *k, const sl_apsf_medium *m, double T_radius, double distance_ratio,
                                double focal_px, int rx, int ry, double tolerance, sl_error *err);

/* Focal length in pixels of a pinhole with vertical field of view fov_y (radians). */
double sl_glow_focal_px(int height, double fov_y_rad);

typedef struct sl_glow_workspace sl_glow_workspace;
/* Plans real-to-complex and complex-to-real FFTs (FFTW_ESTIMATE: deterministic) for frames of
 * width x height and kernels up to rx, ry (<= 0: the whole frame, width - 1 and height - 1,
 * so the glow is never cut). The transform size is the smallest 2^a 3^b 5^c 7^d at least
 * width + rx by height + ry: linear, not circular, convolution. */
sl_glow_workspace *sl_glow_workspace_create(int width, int height, int rx, int ry, sl_error *err);
void sl_glow_workspace_free(sl_glow_workspace *ws);
void sl_glow_workspace_size(const sl_glow_workspace *ws, int *nx, int *ny);

/* accum[c][i] += (kernel * src[c])[i] for n_channels float planes of width x height (linear
 * convolution, cropped to the frame). Planes that are all zero cost nothing. */
int sl_glow_convolve(sl_glow_workspace *ws, const sl_glow_kernel *k, const float *const *src, float *const *accum,
                     int n_channels, sl_error *err);

typedef struct sl_glow_params {
  sl_apsf_medium medium;
  /* Optional per-channel media (R, G, B), e.g. a particle table at 650, 515 and 440 nm; NULL
   * entries use `medium`. Distinct media cost one kernel transform each per layer. */
  const sl_apsf_medium *channel_medium[3];
  double sigma;         /* extinction coefficient of the medium (1/m), T = sigma * distance */
  /* Optional extinction of channel c relative to sigma (0 means 1): T_c = scale_c T. Haze is
   * not grey (render/optics' aerosol: more extinction in blue); layers stay placed in T. */
  double channel_sigma_scale[3];
  double fixed_T;       /* > 0: every pixel at this T and depth is not read */
  double sky_distance;  /* distance (m) given to pixels of infinite depth; <= 0: such pixels are
                           neither sources nor attenuated (the sky is outside the medium) */
  double bank_depth;    /* > 0: the medium is a bank of this depth (m) in front of the camera: a
                           pixel's distance inside it is clipped to this (farther things, lights
                           beyond the bank included, are seen through all of it) */
  double fov_y_deg;     /* vertical field of view of the pinhole that made the image */
  double threshold;     /* a pixel is a source when its largest RGB value reaches this */
  /* Optional, width x height: pixels marked non-zero are sources whatever their value (emissive
   * lights drawn into the frame, sl_point_lights.h, fainter than any useful threshold). */
  const unsigned char *source_mask;
  int n_layers;         /* at most this many depth layers (1..64), evenly spaced in log T over the
                           sources and no closer than 2 % in T */
  sl_glow_norm norm;
  int attenuate;        /* eq. 30: e^{-T} on pixels that are not sources */
  double airlight[3];   /* eq. 31: L_sky (1 - e^{-T}) added to every pixel: the medium's source
                           function J (sl_airlight_source) */
  const float *airlight_map; /* optional, 3 floats per pixel: J per pixel instead of airlight[] */
  double tolerance;     /* series tolerance (sl_apsf_terms_needed) */
  void (*progress)(void *user, double fraction);
  void *progress_user;
} sl_glow_params;

void sl_glow_params_defaults(sl_glow_params *p);

/* Haze (render/optics' sl_aerosol_rural) at three wavelengths: per channel a Henyey-Greenstein
 * medium with q = the aerosol's asymmetry g and W0 its albedo, and the extinction relative to
 * 550 nm, where Koschmieder's visibility defines sigma (for channel_sigma_scale). */
int sl_glow_haze_media(const double wavelengths_nm[3], sl_apsf_medium media[3], double sigma_scale[3], sl_error *err);

/* Narasimhan et al., eqs. 30-31 without the glow: a scene radiance L0 seen through optical
 * thickness T of a medium whose source function J (the horizon brightness L_sky: what an
 * infinitely deep path of the medium shows) is the same all along the path,
 *   L = L0 e^{-T} + J (1 - e^{-T}),
 * the solution of dL/dtau = -L + J (docs/APSF.md, "Airlight", checks it by quadrature). */
double sl_airlight_path(double scene_radiance, double horizon_brightness, double T);

/* The share of a normalised Henyey-Greenstein phase function (asymmetry q) that points into the
 * upper hemisphere for a sight line d at elevation e (radians): light arriving from direction s
 * is scattered toward the eye through the angle whose cosine is mu = s.d (forward scattering
 * brings the light from beyond the point along the sight line), so
 *   F(e) = 2 pi int_{-1}^{1} p_HG(mu) a(mu, e) dmu,
 * a(mu, e) = acos(clamp(-mu tan e / sqrt(1 - mu^2))) / pi the part of the cone of half-angle
 * acos(mu) around d that lies above the horizontal. F(0) = 1/2 for every q: mirroring
 * z -> -z keeps the scattering angle of a horizontal ray. Integrated in HG's cumulative
 * distribution (where the phase weight is uniform) by Gauss-Legendre on the three pieces
 * between the cone's tangencies mu = +-cos e. */
double sl_airlight_upper_share(double q, double elevation_rad);

/* J of a medium of single-scattering albedo W0 and asymmetry q lit by diffuse light that is
 * uniform over the upper hemisphere (radiance L_up: the sky) and over the lower one (L_down: the
 * ground), along a sight line at elevation e: single scattering of that light,
 *   J = W0 (L_up F(e) + L_down (1 - F(e))),
 * the eq. 31 L_sky of that sight line (docs/APSF.md, "Airlight"). */
double sl_airlight_source(double albedo, double q, double elevation_rad, double radiance_up, double radiance_down);

#define SL_GLOW_MAX_LAYERS 64
typedef struct sl_glow_stats {
  int sources;                          /* source pixels */
  int layers_used;                      /* layers that held sources (only these are convolved) */
  double T_min, T_max;                  /* over the sources */
  double layer_T[SL_GLOW_MAX_LAYERS];   /* of the layers used */
  int layer_terms[SL_GLOW_MAX_LAYERS];
  double kernel_seconds, convolve_seconds;
} sl_glow_stats;

/* out = glows of the sources plus the rest of the image attenuated (eqs. 30-31). in's depth is
 * the distance along the view axis (sl_image.h); it is turned into the distance to the camera.
 * out must be allocated at in's size; it may alias in. Alpha, depth and transparency are
 * copied. ws must have been created for in's size. stats may be NULL. */
int sl_glow_apply(sl_glow_workspace *ws, const sl_glow_params *p, const sl_image *in, sl_image *out,
                  sl_glow_stats *stats, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
