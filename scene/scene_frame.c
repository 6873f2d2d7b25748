/* One frame of a built scene on the CPU (sl_scene_frame.h): the order of cmd_render's CPU path. */
#include "sl_scene_frame.h"

#include <math.h>
#include <stdlib.h>

const char *sl_scene_frame_unsupported(const sl_settings *s)
{
  static const char *const layers[] = {"terrain",         "coastlines",  "borders",   "graticule",
                                       "domain-outline",  "scale-bar",   "lights-count",
                                       "night-sky-luminance"};
  for (size_t i = 0; i < sizeof layers / sizeof layers[0]; ++i)
    if (sl_settings_given(s, layers[i])) return layers[i];
  if (s->fog_visibility_km > 0.0) return "fog-visibility-km";
  return NULL;
}

int sl_scene_render_frame(const sl_settings *s, sl_built_scene *b, sl_camera *cam, sl_image *frame,
                          sl_render_stats *stats, sl_error *err)
{
  const char *layer = sl_scene_frame_unsupported(s);
  if (layer)
    return sl_fail(err, SL_ERR_ARG, "--%s is drawn by the stormlight command only (its VTK and night passes)", layer);
  if (!b->renderer) return sl_fail(err, SL_ERR_ARG, "the scene was built without a renderer");
  double lo[3], hi[3];
  sl_renderer_content_bounds(b->renderer, lo, hi);
  sl_scene_camera(s, lo, hi, cam);
  const size_t n = (size_t)cam->width * cam->height;
  float *opaque = malloc(n * sizeof *opaque);
  sl_image volume = {0}, sky = {0};
  *frame = (sl_image){0};
  int rc = opaque ? SL_OK : sl_fail(err, SL_ERR_NOMEM, "render: out of memory");
  if (!rc) {
    for (size_t i = 0; i < n; ++i) opaque[i] = INFINITY;
    if (sl_scene_ground_opaque(&b->scene, cam, opaque)) cam->opaque_distance = opaque;
    rc = sl_image_alloc(&volume, cam->width, cam->height, err) || sl_image_alloc(&sky, cam->width, cam->height, err) ||
         sl_image_alloc(frame, cam->width, cam->height, err);
  }
  if (!rc) rc = sl_renderer_render(b->renderer, cam, &volume, stats, err);
  if (!rc) rc = sl_renderer_background(b->renderer, cam, &sky, err);
  if (!rc) {
    sl_image_over(&volume, &sky, frame);
    /* Z: the volume's opacity-weighted depth, then the ground behind what it lets through. */
    sl_image_opaque_depth(cam, opaque, &sky);
    sl_image_depth_over(&volume, &sky, frame);
  }
  cam->opaque_distance = NULL;
  free(opaque);
  sl_image_free(&volume);
  sl_image_free(&sky);
  if (rc) sl_image_free(frame);
  return rc ? (err->code ? err->code : rc) : SL_OK;
}
