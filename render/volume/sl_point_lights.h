/* Emissive point lights (a town's street lamps) in the world frame, drawn into a rendered HDR
 * frame: projected through the scene's pinhole camera, attenuated by the volume renderer's own
 * transmittance between them and the eye, with their depth in the frame's Z channel so the glow
 * (render/apsf) convolves each in its depth layer. docs/SCENES.md, "Night and lights".
 *
 * Units. The renderer's radiance is relative to a top-of-atmosphere sun of irradiance 1 per
 * channel (sl_image.h). Photometric quantities map onto it through the solar illuminance
 * constant E_sc: a luminance L_v (cd/m^2) is L_v / E_sc per steradian, a luminous intensity
 * I_v (cd) is I_v / E_sc in m^2/sr (irradiance I / d^2 at distance d, in sun units). A colour
 * is given as relative linear-sRGB weights, scaled to unit luminance Y = 0.2126 R + 0.7152 G +
 * 0.0722 B, so that the white sun (1, 1, 1) has Y = 1 as well. */
#ifndef SL_POINT_LIGHTS_H
#define SL_POINT_LIGHTS_H

#include <stddef.h>

#include "sl_image.h"
#include "sl_renderer.h"
#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The solar illuminance constant (extraterrestrial illuminance at 1 AU normal to the beam),
 * 128 000 lx as used in daylighting (IES; e.g. the "Sunlight" calculation after the IES
 * Lighting Handbook). Darula, Kittler & Gueymard (2005) derive 133 334 lx from the ASTM E490
 * spectrum: the choice moves every light by 4 %. */
#define SL_SOLAR_ILLUMINANCE_LX 128000.0

/* Per-channel value in sun units of a photometric quantity (cd or cd/m^2) of colour rgb (relative
 * weights, >= 0, not all zero): value / E_sc * rgb / Y(rgb). */
void sl_photometric_to_render(double photometric, const double rgb[3], double out[3]);

typedef struct sl_point_light {
  double position[3];  /* world ENU metres */
  double intensity[3]; /* radiant intensity per channel, sun units x m^2 / sr (isotropic) */
} sl_point_light;

/* A rectangular town grid on the ground: count[0] x count[1] lamps `spacing` metres apart around
 * `center` (x, y), each `height` metres above the ground, every position moved by up to
 * +-jitter/2 of the spacing in x and y (a seeded hash of the lamp's index: reproducible). */
typedef struct sl_light_grid {
  double center[2];
  int count[2];
  double spacing, height, jitter;
  double intensity_cd; /* luminous intensity of one lamp, cd */
  double color[3];     /* relative linear-sRGB weights */
  unsigned seed;
} sl_light_grid;

/* Fills out (count[0] * count[1] lights) from the grid, at z = height: the caller adds the
 * ground under each (app/night_scene: the terrain's own triangles). Returns SL_OK or SL_ERR_ARG. */
int sl_light_grid_build(const sl_light_grid *g, sl_point_light *out, sl_error *err);

/* One light as the camera sees it. */
typedef struct sl_light_pixel {
  size_t pixel;        /* row-major index, row 0 at the top */
  double ray_distance; /* along the pixel's unit centre ray to the light's depth plane (opaque distance) */
  double depth;        /* along the view axis (the frame's Z) */
  double radiance[3];  /* unattenuated: (I / d^2) / the pixel's solid angle, sun units per sr */
} sl_light_pixel;

/* Projects the lights through the camera (the renderer's pinhole, sl_camera_ray's pixel
 * centres); lights behind the camera or outside the frame are left out. Each lands on the pixel
 * that holds it, whose solid angle (pixel side 1/f on the unit image plane, times cos^3 of its
 * centre's angle from the axis) spreads its irradiance: sum of radiance x solid angle = I / d^2
 * exactly. out needs n entries; *n_out gets how many are in the frame. */
int sl_point_lights_project(const sl_camera *cam, const sl_point_light *lights, int n, sl_light_pixel *out,
                            int *n_out, sl_error *err);

/* Eye rays of light pixels stop at the light (opaque_distance, width x height, +inf where
 * nothing is opaque; the nearer of the two is kept), so the volume renderer's transparency of
 * that pixel is the transmittance of the cloud between the eye and the light. */
void sl_point_lights_stop_rays(const sl_light_pixel *lp, int n, float *opaque_distance);

/* Adds each light, times the pixel's transparency from the volume render (`transparency`, the
 * renderer's exp(-tau) up to the opaque distance; NULL: 1), to img's RGB, sets the pixel's depth
 * to the light's (the nearest light's where several share a pixel) and marks it in source_mask
 * (width x height, may be NULL) for the glow. Alpha is left as it is. */
void sl_point_lights_draw(const sl_light_pixel *lp, int n, const float *transparency, sl_image *img,
                          unsigned char *source_mask);

/* Adds a constant night-sky radiance (sun units per sr) to the pixels of img whose centre ray
 * points above the horizontal (the sky; the ground below stays as it is). The analytic sky
 * (render/sky) models sunlight only and gives exactly 0 once the sun is down. */
int sl_night_sky_fill(const sl_camera *cam, const double radiance[3], sl_image *img, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
