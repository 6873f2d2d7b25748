/* What the air adds around the volume: the frame behind the volume (sky, sun disk, ground
 * distance) and the ground's distance along the camera's rays. A pixel's resolve through the air
 * in front of it is resolve.h's. */
#include "renderer_internal.h"
#include "sl_cie.h"
#include "sl_sample_physics.h"

#include <math.h>

int sl_renderer_background(const sl_renderer *r, const sl_camera *cam, sl_image *img, sl_error *err)
{
  if (!cam || cam->width != img->width || cam->height != img->height)
    return sl_fail(err, SL_ERR_ARG, "background: the image is not the camera's size");
  const sl_scene *sc = &r->scene;
  sl_sky_view view;
  if (sc->atmosphere && sl_sky_view_init(&view, sc->atmosphere, cam->position, sc->sun_direction, err))
    return err->code;
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up))
    return sl_fail(err, SL_ERR_ARG, "background: camera position equals the target, or up is parallel to the view");
  const double tan_half = tan(0.5 * cam->fov_deg * M_PI / 180.0);
  const double aspect = (double)img->width / img->height;
  const size_t n = (size_t)img->width * img->height;
  const int nwl = r->model.nwl;
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < n; ++i) {
    double L[SL_MAX_WAVELENGTHS], rgb[3], ground_depth = INFINITY;
    if (sc->atmosphere) {
      double d[3], sun_disk[SL_MAX_WAVELENGTHS];
      sl_camera_pixel_ray(fwd, right, up, tan_half, aspect, img->width, img->height, (int)(i % img->width),
                (int)(i / img->width), d);
      double T[SL_MAX_WAVELENGTHS];
      sl_sky_view_segment(&view, d, 0.0, INFINITY, L, T);
      if (sl_sky_sun_disk_radiance(sc->atmosphere, cam->position, d, sc->sun_direction, sun_disk))
        for (int c = 0; c < nwl; ++c) L[c] += sun_disk[c];
      /* Where the ray meets the ground (plane or sphere), as distance along the view axis. */
      double up_eye[3];
      const double h = sl_sky_altitude(sc->atmosphere, cam->position, up_eye);
      const double t = sl_sky_ground_distance(h, sl_dot3(d, up_eye), sc->atmosphere->ground_radius);
      ground_depth = t * sl_dot3(d, fwd);
      /* The lit ground behind the air in front of it: sun times the storm's shadow, plus sky. */
      if (r->ground.on && isfinite(t)) {
        const double S = sl__ground_shadow_at(&r->ground, cam->position[0] + t * d[0], cam->position[1] + t * d[1]);
        for (int c = 0; c < nwl; ++c) L[c] += T[c] * (r->ground.sun[c] * S + r->ground.sky[c]);
      }
      sl_cie_apply(r->to_rgb, nwl, L, rgb);
    } else {
      for (int c = 0; c < SL_CHANNELS; ++c) rgb[c] = sc->sky_radiance[c];
    }
    for (int c = 0; c < SL_CHANNELS; ++c) img->rgba[4 * i + c] = (float)rgb[c];
    img->rgba[4 * i + 3] = 1.0f;
    img->depth[i] = (float)ground_depth;
    img->transparency[i] = 0.0f;
  }
  return SL_OK;
}

void sl_camera_ground_distance(const sl_camera *cam, const sl_atmosphere *atm, float *distance)
{
  double up[3];
  const double h = sl_sky_altitude(atm, cam->position, up);
#pragma omp parallel for schedule(static)
  for (int py = 0; py < cam->height; ++py)
    for (int px = 0; px < cam->width; ++px) {
      double d[3];
      if (sl_camera_ray(cam, px, py, d)) continue;
      const double t = sl_sky_ground_distance(h, sl_dot3(d, up), atm->ground_radius);
      float *q = distance + (size_t)py * cam->width + px;
      if (t < *q) *q = (float)t;
    }
}
