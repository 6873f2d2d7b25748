#include "sl_camera.h"

#include <math.h>
#include <stddef.h>

#include "sl_vec3.h"

#define DEG (3.14159265358979323846 / 180.0)

void sl_sun_direction(double elevation_deg, double azimuth_deg, double out[3])
{
  const double ce = cos(elevation_deg * DEG);
  out[0] = ce * sin(azimuth_deg * DEG);
  out[1] = ce * cos(azimuth_deg * DEG);
  out[2] = sin(elevation_deg * DEG);
}

int sl_camera_basis(const sl_camera *cam, double fwd[3], double right[3], double up[3])
{
  for (int a = 0; a < 3; ++a) fwd[a] = cam->target[a] - cam->position[a];
  if (sl_normalize3(fwd)) return 1;
  sl_cross3(fwd, cam->up, right);
  if (sl_normalize3(right)) return 1;
  sl_cross3(right, fwd, up);
  return 0;
}

void sl_camera_frame(const double lo[3], const double hi[3], double azimuth_deg, double elevation_deg,
                     double fov_deg, int width, int height, sl_camera *cam)
{
  double dir[3];
  sl_sun_direction(elevation_deg, azimuth_deg, dir);
  double radius = 0.0;
  for (int a = 0; a < 3; ++a) {
    cam->target[a] = 0.5 * (lo[a] + hi[a]);
    radius += 0.25 * (hi[a] - lo[a]) * (hi[a] - lo[a]);
  }
  radius = sqrt(radius);
  const double aspect = (double)width / height;
  double half = 0.5 * fov_deg * M_PI / 180.0;
  if (aspect < 1.0) half = atan(tan(half) * aspect);
  const double distance = 1.05 * radius / sin(half);
  for (int a = 0; a < 3; ++a) cam->position[a] = cam->target[a] + distance * dir[a];
  cam->up[0] = 0.0, cam->up[1] = 0.0, cam->up[2] = 1.0;
  if (fabs(dir[2]) > 0.999) cam->up[1] = 1.0, cam->up[2] = 0.0;
  cam->fov_deg = fov_deg;
  cam->width = width;
  cam->height = height;
  cam->opaque_distance = NULL; /* nothing opaque in front of the volume unless the caller says so */
}

int sl_camera_chaser(const double lo[3], const double hi[3], double azimuth_deg, double eye_z, double fov_deg,
                     int width, int height, sl_camera *cam)
{
  double dir[3]; /* from the box toward the camera, horizontal */
  sl_sun_direction(0.0, azimuth_deg, dir);
  const double tan_v = tan(0.5 * fov_deg * M_PI / 180.0), tan_h = tan_v * width / height;
  const double pitch = atan(0.5 * tan_v), half_v = 0.5 * fov_deg * M_PI / 180.0;
  const double c[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  /* The box's extent along the view (depth, from its centre to its nearest face) and across it. */
  const double ex = 0.5 * (hi[0] - lo[0]), ey = 0.5 * (hi[1] - lo[1]);
  const double depth = fabs(dir[0]) * ex + fabs(dir[1]) * ey, across = fabs(dir[1]) * ex + fabs(dir[0]) * ey;
  /* Nearest-face distance that fits the top (at the near face) and the width (there too). */
  const double rise = hi[2] - eye_z;
  const double fit_top = rise > 0.0 ? rise / tan(pitch + 0.95 * half_v) : 0.0;
  const double fit_width = across / (0.95 * tan_h);
  if (fit_width > 3.0 * fit_top) return 0;
  double near = fit_top > fit_width ? fit_top : fit_width;
  if (near < 0.05 * across + 1.0) near = 0.05 * across + 1.0;
  const double distance = near + depth;
  cam->position[0] = c[0] + distance * dir[0];
  cam->position[1] = c[1] + distance * dir[1];
  cam->position[2] = eye_z;
  /* Look back along the azimuth, up by the pitch. */
  for (int a = 0; a < 2; ++a) cam->target[a] = cam->position[a] - distance * cos(pitch) * dir[a];
  cam->target[2] = eye_z + distance * sin(pitch);
  cam->up[0] = 0.0, cam->up[1] = 0.0, cam->up[2] = 1.0;
  cam->fov_deg = fov_deg;
  cam->width = width;
  cam->height = height;
  cam->opaque_distance = NULL;
  return 1;
}

int sl_camera_ray(const sl_camera *cam, int px, int py, double d[3])
{
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up)) return 1;
  sl_camera_pixel_ray(fwd, right, up, tan(0.5 * cam->fov_deg * M_PI / 180.0), (double)cam->width / cam->height,
                      cam->width, cam->height, px, py, d);
  return 0;
}

void sl_image_opaque_depth(const sl_camera *cam, const float *distance, sl_image *img)
{
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up)) return;
#pragma omp parallel for schedule(static)
  for (int py = 0; py < cam->height; ++py)
    for (int px = 0; px < cam->width; ++px) {
      const size_t q = (size_t)py * cam->width + px;
      double d[3];
      if (!isfinite(distance[q]) || sl_camera_ray(cam, px, py, d)) continue;
      const float z = (float)(distance[q] * sl_dot3(d, fwd));
      if (!(img->depth[q] <= z)) img->depth[q] = z;
    }
}
