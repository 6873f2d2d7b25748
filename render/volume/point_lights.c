/* Emissive point lights drawn into a rendered frame (sl_point_lights.h). */
#include "sl_point_lights.h"

#include <math.h>
#include <stdint.h>

#include "renderer_internal.h"

void sl_photometric_to_render(double photometric, const double rgb[3], double out[3])
{
  const double Y = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; /* Rec. 709 / sRGB luminance */
  for (int c = 0; c < 3; ++c) out[c] = Y > 0.0 ? photometric / SL_SOLAR_ILLUMINANCE_LX * rgb[c] / Y : 0.0;
}

/* A uniform number in [0, 1) from (seed, index): splitmix64's finaliser. */
static double hash_unit(unsigned seed, uint64_t index)
{
  uint64_t z = index * 0x9E3779B97F4A7C15ull + ((uint64_t)seed << 32) + 0x632BE59BD9B4E019ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

int sl_light_grid_build(const sl_light_grid *g, sl_point_light *out, sl_error *err)
{
  if (g->count[0] < 1 || g->count[1] < 1 || (double)g->count[0] * g->count[1] > 1e7)
    return sl_fail(err, SL_ERR_ARG, "lights: the grid needs 1..1e7 lamps (got %d x %d)", g->count[0], g->count[1]);
  if (!(g->spacing > 0.0) || !isfinite(g->spacing) || !(g->jitter >= 0.0 && g->jitter <= 1.0) || !isfinite(g->height))
    return sl_fail(err, SL_ERR_ARG, "lights: spacing must be > 0 m, jitter in [0, 1] and height finite");
  if (!(g->intensity_cd >= 0.0) || !isfinite(g->intensity_cd) || !(g->color[0] >= 0.0 && g->color[1] >= 0.0 &&
                                                                     g->color[2] >= 0.0) ||
      !(g->color[0] + g->color[1] + g->color[2] > 0.0))
    return sl_fail(err, SL_ERR_ARG, "lights: intensity must be >= 0 cd and the colour >= 0, not all zero");
  double I[3];
  sl_photometric_to_render(g->intensity_cd, g->color, I);
  for (int j = 0; j < g->count[1]; ++j)
    for (int i = 0; i < g->count[0]; ++i) {
      const uint64_t k = (uint64_t)j * g->count[0] + i;
      sl_point_light *l = &out[k];
      const double x = g->center[0] + (i - 0.5 * (g->count[0] - 1)) * g->spacing +
                       g->jitter * g->spacing * (hash_unit(g->seed, 2 * k) - 0.5);
      const double y = g->center[1] + (j - 0.5 * (g->count[1] - 1)) * g->spacing +
                       g->jitter * g->spacing * (hash_unit(g->seed, 2 * k + 1) - 0.5);
      l->position[0] = x, l->position[1] = y;
      l->position[2] = g->height;
      for (int c = 0; c < 3; ++c) l->intensity[c] = I[c];
    }
  return SL_OK;
}

int sl_point_lights_project(const sl_camera *cam, const sl_point_light *lights, int n, sl_light_pixel *out,
                            int *n_out, sl_error *err)
{
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up))
    return sl_fail(err, SL_ERR_ARG, "lights: camera position equals the target, or up is parallel to the view");
  const double tan_half = tan(0.5 * cam->fov_deg * M_PI / 180.0), aspect = (double)cam->width / cam->height;
  /* Pixels are square: side 2 tan_half / height = 1 / f on the image plane at distance 1. */
  const double inv_f = 2.0 * tan_half / cam->height;
  int m = 0;
  for (int k = 0; k < n; ++k) {
    const sl_point_light *l = &lights[k];
    const double v[3] = {l->position[0] - cam->position[0], l->position[1] - cam->position[1],
                         l->position[2] - cam->position[2]};
    const double z = sl_dot3(v, fwd);
    if (!(z > 0.0)) continue;
    const double sx = sl_dot3(v, right) / z, sy = sl_dot3(v, up) / z;
    /* The inverse of sl_camera_pixel_ray's pixel-centre map. */
    const double fx = 0.5 * (sx / (tan_half * aspect) + 1.0) * cam->width;
    const double fy = 0.5 * (1.0 - sy / tan_half) * cam->height;
    if (!(fx >= 0.0 && fx < cam->width && fy >= 0.0 && fy < cam->height)) continue;
    const int px = (int)fx, py = (int)fy;
    double d[3];
    sl_camera_pixel_ray(fwd, right, up, tan_half, aspect, cam->width, cam->height, px, py, d);
    const double cos_axis = sl_dot3(d, fwd);
    const double solid_angle = inv_f * inv_f * cos_axis * cos_axis * cos_axis;
    const double dist2 = sl_dot3(v, v);
    sl_light_pixel *o = &out[m++];
    o->pixel = (size_t)py * cam->width + px;
    o->ray_distance = z / cos_axis;
    o->depth = z;
    for (int c = 0; c < 3; ++c) o->radiance[c] = l->intensity[c] / dist2 / solid_angle;
  }
  *n_out = m;
  return SL_OK;
}

void sl_point_lights_stop_rays(const sl_light_pixel *lp, int n, float *opaque_distance)
{
  for (int k = 0; k < n; ++k)
    if (!(opaque_distance[lp[k].pixel] <= lp[k].ray_distance)) opaque_distance[lp[k].pixel] = (float)lp[k].ray_distance;
}

void sl_point_lights_draw(const sl_light_pixel *lp, int n, const float *transparency, sl_image *img,
                          unsigned char *source_mask)
{
  /* A light pixel takes the depth of its nearest light, not the volume's. */
  if (img->depth)
    for (int k = 0; k < n; ++k) img->depth[lp[k].pixel] = INFINITY;
  for (int k = 0; k < n; ++k) {
    const size_t q = lp[k].pixel;
    const double t = transparency ? transparency[q] : 1.0;
    for (int c = 0; c < 3; ++c) img->rgba[4 * q + c] += (float)(t * lp[k].radiance[c]);
    if (img->depth && lp[k].depth < img->depth[q]) img->depth[q] = (float)lp[k].depth;
    if (source_mask) source_mask[q] = 1;
  }
}

int sl_night_sky_fill(const sl_camera *cam, const double radiance[3], sl_image *img, sl_error *err)
{
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up))
    return sl_fail(err, SL_ERR_ARG, "night sky: camera position equals the target, or up is parallel to the view");
  const double tan_half = tan(0.5 * cam->fov_deg * M_PI / 180.0), aspect = (double)cam->width / cam->height;
  for (int y = 0; y < img->height; ++y)
    for (int x = 0; x < img->width; ++x) {
      double d[3];
      sl_camera_pixel_ray(fwd, right, up, tan_half, aspect, img->width, img->height, x, y, d);
      if (!(d[2] > 0.0)) continue;
      float *px = img->rgba + 4 * ((size_t)y * img->width + x);
      for (int c = 0; c < 3; ++c) px[c] += (float)radiance[c];
    }
  return SL_OK;
}
