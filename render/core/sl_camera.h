/* The pinhole camera every renderer of the project uses (the fast slicer, the light-volume march,
 * the GPU pass's inputs, the Monte Carlo reference, the lamps' projection), and directions from
 * compass angles. World frame: local east-north-up metres (sl_volume.h). */
#ifndef SL_CAMERA_H
#define SL_CAMERA_H

#include "sl_image.h"
#include "sl_vec3.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sl_camera {
  double position[3], target[3], up[3]; /* world ENU metres; up need not be orthogonal */
  double fov_deg;                       /* vertical field of view, (0, 170) */
  int width, height;
  /* Opaque surfaces (terrain): per pixel, rows from the top, the distance along the pixel's unit
   * ray (sl_camera_ray) to the first opaque surface, +inf where none; eye rays stop there. NULL:
   * nothing opaque. Not owned. */
  const float *opaque_distance;
} sl_camera;

/* Unit vector (x east, y north, z up) at elevation and compass azimuth (clockwise from north),
 * degrees: toward the sun, or from a target toward its camera. */
void sl_sun_direction(double elevation_deg, double azimuth_deg, double out[3]);

/* A camera looking at the box's centre from compass azimuth `azimuth_deg` (clockwise from
 * north, the direction from the target to the camera) and elevation `elevation_deg`, far
 * enough that the box's bounding sphere fills the view. */
void sl_camera_frame(const double lo[3], const double hi[3], double azimuth_deg, double elevation_deg,
                     double fov_deg, int width, int height, sl_camera *cam);
/* A storm chaser's camera: at height `eye_z` on the side of the box (horizontal compass direction
 * `azimuth_deg` from its centre to the camera), looking along that azimuth back at the box and up
 * by a pitch that puts a flat horizon a quarter of the image above its bottom edge
 * (atan(tan(fov / 2) / 2), 10.3 degrees at 40), and as near as lets the whole box fit the frame: its
 * top edge below the image's top and its width within the image's, each with a 5 % margin, seen
 * from the box's nearest face. Returns 0 (cam untouched) for a box too wide for a ground view: one
 * that the width puts more than three times as far as the top does (a deck, a hurricane), whose
 * storm would sit as a line on the horizon or beyond it. */
int sl_camera_chaser(const double lo[3], const double hi[3], double azimuth_deg, double eye_z, double fov_deg,
                      int width, int height, sl_camera *cam);
/* The camera's orthonormal basis: forward (toward the target), right (forward x up) and up
 * (made orthogonal); returns 1 when the position equals the target or up is parallel to the view. */
int sl_camera_basis(const sl_camera *cam, double fwd[3], double right[3], double up[3]);
/* The pinhole: the unit ray through pixel (px, py)'s centre, on an image plane at distance 1 along
 * fwd, for a basis from sl_camera_basis and tan_half = tan(fov / 2), aspect = width / height.
 * Inline: the eye passes call it per pixel. */
static inline void sl_camera_pixel_ray(const double fwd[3], const double right[3], const double up[3],
                                       double tan_half, double aspect, int width, int height, int px, int py,
                                       double d[3])
{
  const double sx = (2.0 * (px + 0.5) / width - 1.0) * tan_half * aspect;
  const double sy = (1.0 - 2.0 * (py + 0.5) / height) * tan_half;
  for (int a = 0; a < 3; ++a) d[a] = fwd[a] + sx * right[a] + sy * up[a];
  sl_normalize3(d);
}
/* The ray through pixel (px, py) of the camera (unit direction, world frame). Returns 1 for a
 * degenerate camera. */
int sl_camera_ray(const sl_camera *cam, int px, int py, double d[3]);

/* The view-axis depth (sl_image.depth) of opaque surfaces at a distance along each pixel's unit
 * ray: img->depth becomes the nearer of its own and t * (ray . forward), per pixel. */
void sl_image_opaque_depth(const sl_camera *cam, const float *distance, sl_image *img);

#ifdef __cplusplus
}
#endif
#endif
