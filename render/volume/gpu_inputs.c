/* The renderer's prepared state for a GPU pass (sl_renderer_gpu.h). */
#include "sl_renderer_gpu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "renderer_internal.h"
#include "resolve.h"
#include "sl_sample_physics.h"

void sl_renderer_gpu_inputs_get(const sl_renderer *r, sl_renderer_gpu_inputs *out)
{
  memset(out, 0, sizeof *out);
  out->model = &r->model;
  out->n[0] = r->shape.nx, out->n[1] = r->shape.ny, out->n[2] = r->shape.nz;
  memcpy(out->origin, r->shape.origin, sizeof out->origin);
  memcpy(out->spacing, r->shape.spacing, sizeof out->spacing);
  out->fields = r->fields;
  memcpy(out->content_lo, r->clo, sizeof r->clo);
  memcpy(out->content_hi, r->chi, sizeof r->chi);
  memcpy(out->content_center, r->content_center, sizeof r->content_center);
  memcpy(out->sun_direction, r->scene.sun_direction, sizeof out->sun_direction);
  sl_sweep_geometry_init(out->n, out->spacing, out->sun_direction, &out->sweep);
  out->termination_transparency = r->scene.termination_transparency;
  out->march_samples = sl__march_samples(&r->scene);
  out->any_extinction = r->any_extinction;
  out->skylight = sl__diffuse_lattice(&r->scene) && r->any_extinction;
  out->sky_ready = r->sky_built;
  out->sky = r->sky.radiance;
  for (int a = 0; a < 3; ++a)
    out->sky_n[a] = r->sky.n[a], out->sky_origin[a] = r->sky.origin[a], out->sky_spacing[a] = r->sky.spacing[a];
}

int sl_renderer_sunlight_table(const sl_renderer *r, const sl_camera *cam, double *rows, double *z0, double *dz,
                               double *ground_radius, int *night, sl_error *err)
{
  const sl_scene *sc = &r->scene;
  sl_sky_view view = {0};
  if (sc->atmosphere && sl_sky_view_init(&view, sc->atmosphere, cam->position, sc->sun_direction, err)) return err->code;
  sun_table *t = malloc(sizeof *t);
  if (!t) return sl_fail(err, SL_ERR_NOMEM, "render: out of memory");
  sl__sun_table_init(t, sc, &view, r->clo, r->chi);
  for (int i = 0; i < SUN_TABLE_SIZE; ++i)
    for (int c = 0; c < t->nwl; ++c) rows[i * t->nwl + c] = t->rgb[i][c];
  *z0 = t->z0;
  *dz = t->dz;
  *ground_radius = sc->atmosphere ? sc->atmosphere->ground_radius : 0.0;
  *night = view.night;
  free(t);
  return SL_OK;
}

int sl_renderer_resolve_accumulator(const sl_renderer *r, const sl_camera *cam, const float *acc, int stride,
                                    sl_image *img, sl_error *err)
{
  if (!cam || cam->width != img->width || cam->height != img->height)
    return sl_fail(err, SL_ERR_ARG, "resolve: the image is not the camera's size");
  if (stride != r->model.nwl + 2) return sl_fail(err, SL_ERR_ARG, "resolve: %d values per pixel, expected %d", stride,
                                                 r->model.nwl + 2);
  const sl_scene *sc = &r->scene;
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up))
    return sl_fail(err, SL_ERR_ARG, "resolve: camera position equals the target, or up is parallel to the view");
  sl_sky_view view = {0};
  if (sc->atmosphere && sl_sky_view_init(&view, sc->atmosphere, cam->position, sc->sun_direction, err)) return err->code;
  const double tan_half = tan(0.5 * cam->fov_deg * M_PI / 180.0);
  const double aspect = (double)img->width / img->height;
  const double *o = cam->position;
  const double h_center = sl_dot3(fwd, r->content_center), f_o = sl_dot3(fwd, o);
  const size_t np = (size_t)img->width * img->height;
#pragma omp parallel for schedule(static)
  for (size_t q = 0; q < np; ++q) {
    double d[3];
    sl_camera_pixel_ray(fwd, right, up, tan_half, aspect, img->width, img->height, (int)(q % img->width),
                  (int)(q / img->width), d);
    double t0 = 0.0, t1 = 0.0;
    if (!(sl_ray_box(r->clo, r->chi, o, d, &t0, &t1) && t1 > 0.0)) t0 = t1 = 0.0;
    if (t0 < 0.0) t0 = 0.0;
    /* The light-volume pass's midplane: across the view axis through the content's centre. */
    const double t_mid = sl_resolve_split(sl_dot3(fwd, d), h_center - f_o, t0, t1);
    sl__resolve_pixel(r, r->model.nwl, sc->atmosphere ? &view : NULL, d, t_mid, acc + q * (size_t)stride, img, q);
  }
  return SL_OK;
}

int sl_renderer_gpu_sky_get(const sl_renderer *r, const sl_camera *cam, sl_renderer_gpu_sky *out, sl_error *err)
{
  memset(out, 0, sizeof *out);
  const sl_scene *sc = &r->scene;
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up))
    return sl_fail(err, SL_ERR_ARG, "resolve: camera position equals the target, or up is parallel to the view");
  out->nwl = r->model.nwl;
  memcpy(out->to_rgb, r->to_rgb, sizeof out->to_rgb);
  memcpy(out->sky_radiance, sc->sky_radiance, sizeof out->sky_radiance);
  out->mid_distance = sl_dot3(fwd, r->content_center) - sl_dot3(fwd, cam->position);
  if (!sc->atmosphere) return SL_OK;
  const sl_atmosphere *atm = sc->atmosphere;
  sl_sky_view view;
  if (sl_sky_view_init(&view, atm, cam->position, sc->sun_direction, err)) return err->code;
  out->has_atmosphere = 1;
  out->altitude = view.altitude;
  out->airmass = view.airmass;
  memcpy(out->up, view.up, sizeof out->up);
  memcpy(out->sun, view.sun, sizeof out->sun);
  for (int c = 0; c < r->model.nwl; ++c) {
    out->beta_sea_level[c] = atm->beta_sea_level[c];
    out->sun_irradiance[c] = atm->sun_irradiance[c];
  }
  out->inv_scale_height = 1.0 / atm->scale_height;
  out->ground_radius = atm->ground_radius;
  const sl__ground *g = &r->ground;
  out->ground_on = g->on;
  if (g->on) {
    for (int c = 0; c < r->model.nwl; ++c) out->ground_sun[c] = g->sun[c], out->ground_sky[c] = g->sky[c];
    out->shadow = g->shadow;
    for (int a = 0; a < 2; ++a)
      out->shadow_n[a] = g->n[a], out->shadow_origin[a] = g->origin[a], out->shadow_spacing[a] = g->spacing[a];
  }
  return SL_OK;
}
