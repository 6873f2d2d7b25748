/* Optical depth by direct quadrature of the total extinction (sl__optical_depth), and where a pixel
 * sees the volume and how much sunlight reaches there (sl_renderer.h): the point of its view ray at
 * optical depth 1 (the first mean free path, where most of what the eye receives from a thick
 * cloud is scattered) and the transparency from there toward the sun. The latter classes pixels
 * for validation (a face in the cloud's own shadow is lit by the sky alone); the passes never
 * read it. The ground's shadow map (ground_shadow.c) takes the former toward the sun. */
#include <math.h>
#include <stdlib.h>

#include "renderer_internal.h"
#include "vector_math.h"

double sl__optical_depth(const sl_renderer *r, const double o[3], const double d[3], double t0, double t1,
                         double step, double stop, double *t_stop)
{
  double tau = 0.0;
  *t_stop = INFINITY;
  for (double t = t0; t < t1; t += step) {
    const double len = fmin(step, t1 - t), tm = t + 0.5 * len;
    const double x[3] = {o[0] + tm * d[0], o[1] + tm * d[1], o[2] + tm * d[2]};
    const double dtau = len * sl__total_extinction(r, x);
    if (tau + dtau >= stop) {
      *t_stop = t + (dtau > 0.0 ? (stop - tau) / dtau * len : 0.0);
      return stop;
    }
    tau += dtau;
  }
  return tau;
}

int sl_renderer_surface_sunlight(const sl_renderer *r, const sl_camera *cam, float *out, sl_error *err)
{
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up))
    return sl_fail(err, SL_ERR_ARG, "render: camera position equals the target, or up is parallel to the view");
  const double tan_half = tan(0.5 * cam->fov_deg * M_PI / 180.0), aspect = (double)cam->width / cam->height;
  const double *sun = r->scene.sun_direction, *o = cam->position;
  double step = r->shape.spacing[0];
  for (int a = 1; a < 3; ++a) step = fmin(step, r->shape.spacing[a]);
  step *= 0.25;
  const long np = (long)cam->width * cam->height;
#pragma omp parallel for schedule(dynamic, 16)
  for (long q = 0; q < np; ++q) {
    double d[3], t0, t1, t_surface;
    sl_camera_pixel_ray(fwd, right, up, tan_half, aspect, cam->width, cam->height, (int)(q % cam->width),
                        (int)(q / cam->width), d);
    out[q] = NAN;
    if (!r->any_extinction || !sl_ray_box(r->clo, r->chi, o, d, &t0, &t1) || t1 <= 0.0) continue;
    if (t0 < 0.0) t0 = 0.0;
    if (cam->opaque_distance && cam->opaque_distance[q] < t1) t1 = cam->opaque_distance[q];
    sl__optical_depth(r, o, d, t0, t1, step, 1.0, &t_surface);
    if (!isfinite(t_surface)) continue;
    const double x[3] = {o[0] + t_surface * d[0], o[1] + t_surface * d[1], o[2] + t_surface * d[2]};
    double s0, s1, unused;
    if (!sl_ray_box(r->clo, r->chi, x, sun, &s0, &s1)) s1 = 0.0;
    out[q] = (float)exp(-sl__optical_depth(r, x, sun, 0.0, fmax(s1, 0.0), step, INFINITY, &unused));
  }
  return SL_OK;
}
