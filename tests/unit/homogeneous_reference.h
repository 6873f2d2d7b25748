/* An independent reference for the renderer's tests: the low-albedo single-scattering radiance
 * of a homogeneous box, by direct numerical quadrature along one ray (no slicing, no buffers). */
#ifndef HOMOGENEOUS_REFERENCE_H
#define HOMOGENEOUS_REFERENCE_H

typedef struct box_medium {
  double lo[3], hi[3];
  double beta;     /* extinction, m^-1 */
  double phase;    /* constant phase function, 1/sr */
  double albedo;
} box_medium;

/* Radiance toward the eye along o + t d (d unit) from a collimated sun of irradiance 1 coming
 * from direction `sun` (unit, toward the sun), plus `background` times the transparency. */
double reference_radiance(const box_medium *m, const double o[3], const double d[3], const double sun[3],
                          double background, int steps);
/* Transparency exp(-beta * chord) of the box along the ray. */
double reference_transparency(const box_medium *m, const double o[3], const double d[3]);

#endif

#include "sl_renderer.h"
#include "sl_volume.h"

/* A volume of nx x ny x nz cells exactly covering [lo, hi] whose cloud field gives extinction beta. */
int make_box_volume(sl_volume *v, int nx, int ny, int nz, const double lo[3], const double hi[3], double beta);
/* The renderer's output for one camera, composited over its background: radiance of channel 0. */
int render_frame(const sl_scene *scene, const sl_camera *cam, sl_image *out);
