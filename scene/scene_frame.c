/* One frame of a built scene on the CPU (sl_scene_frame.h): the order of cmd_render's CPU path. */
#include "sl_scene_frame.h"

#ifdef SL_WITH_REFERENCE
#include "sl_reference.h"
#endif

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

/* What both frames share: the camera as render frames it, the distances to the round ground its
 * eye rays stop at, the volume layer and the sky it goes over. */
typedef struct frame_parts {
  float *opaque;
  sl_image volume, sky;
} frame_parts;

static int frame_begin(const sl_settings *s, const sl_built_scene *b, sl_camera *cam, sl_image *frame,
                       frame_parts *p, sl_error *err)
{
  *frame = (sl_image){0};
  *p = (frame_parts){0};
  const char *layer = sl_scene_frame_unsupported(s);
  if (layer)
    return sl_fail(err, SL_ERR_ARG, "--%s is drawn by the stormlight command only (its VTK and night passes)", layer);
  if (!b->renderer) return sl_fail(err, SL_ERR_ARG, "the scene was built without a renderer");
  double lo[3], hi[3];
  sl_renderer_content_bounds(b->renderer, lo, hi);
  sl_scene_camera(s, &b->frame.volume, lo, hi, b->scene.sun_direction, cam);
  const size_t n = (size_t)cam->width * cam->height;
  p->opaque = malloc(n * sizeof *p->opaque);
  if (!p->opaque) return sl_fail(err, SL_ERR_NOMEM, "render: out of memory");
  for (size_t i = 0; i < n; ++i) p->opaque[i] = INFINITY;
  if (sl_scene_ground_opaque(b->scene.atmosphere, cam, p->opaque)) cam->opaque_distance = p->opaque;
  if (sl_image_alloc(&p->volume, cam->width, cam->height, err) || sl_image_alloc(&p->sky, cam->width, cam->height, err) ||
      sl_image_alloc(frame, cam->width, cam->height, err))
    return err->code;
  return SL_OK;
}

/* The volume over the sky into frame (rc 0), its Z the volume's opacity-weighted depth and the
 * ground behind what it lets through; then frees the parts (and the frame on failure). */
static int frame_end(int rc, sl_camera *cam, sl_image *frame, frame_parts *p, sl_error *err)
{
  if (!rc) {
    sl_image_over(&p->volume, &p->sky, frame);
    sl_image_opaque_depth(cam, p->opaque, &p->sky);
    sl_image_depth_over(&p->volume, &p->sky, frame);
  }
  cam->opaque_distance = NULL;
  free(p->opaque);
  sl_image_free(&p->volume);
  sl_image_free(&p->sky);
  if (rc) sl_image_free(frame);
  return rc ? (err->code ? err->code : rc) : SL_OK;
}

int sl_scene_render_frame(const sl_settings *s, sl_built_scene *b, sl_camera *cam, sl_image *frame,
                          sl_render_stats *stats, sl_error *err)
{
  frame_parts p;
  int rc = frame_begin(s, b, cam, frame, &p, err);
  if (!rc) rc = sl_renderer_render(b->renderer, cam, &p.volume, stats, err);
  if (!rc) rc = sl_renderer_background(b->renderer, cam, &p.sky, err);
  return frame_end(rc, cam, frame, &p, err);
}

#ifdef SL_WITH_REFERENCE
int sl_scene_reference_frame(const sl_settings *s, const sl_built_scene *b, long spp, unsigned long long seed,
                             int skylight, sl_camera *cam, sl_image *frame, float *stderr_rgb, sl_error *err)
{
  *frame = (sl_image){0};
  if (!b->optics) return sl_fail(err, SL_ERR_ARG, "the reference needs the scene's particle tables (not the low-albedo model)");
  if (spp < 1) return sl_fail(err, SL_ERR_ARG, "the reference needs at least one sample per pixel");
  sl_ref_medium *medium = sl_ref_medium_from_volume(&b->frame.volume, b->optics, err);
  if (!medium) return err->code;
  frame_parts p;
  sl_ref_accum acc = {0};
  int rc = frame_begin(s, b, cam, frame, &p, err);
  if (!rc) rc = sl_ref_accum_init(&acc, cam->width, cam->height, sl_ref_medium_wavelength_count(medium), err);
  if (!rc) {
    sl_ref_scene sc;
    sl_ref_scene_defaults(&sc);
    sc.medium = medium;
    for (int a = 0; a < 3; ++a) sc.sun_direction[a] = b->scene.sun_direction[a];
    sc.atmosphere = b->scene.atmosphere;
    for (int c = 0; c < 3; ++c) sc.sky_radiance[c] = s->sky[c];
    sc.skylight = skylight;
    sc.seed = seed;
    const sl_ref_budget budget = {spp, 0.0, NULL, NULL};
    rc = sl_ref_render(&sc, cam, &budget, &acc, err) || sl_ref_accum_image(&acc, medium, &p.volume, stderr_rgb, err) ||
         sl_ref_background(&sc, cam, &p.sky, err);
  }
  sl_ref_accum_free(&acc);
  sl_ref_medium_destroy(medium);
  return frame_end(rc, cam, frame, &p, err);
}
#else
int sl_scene_reference_frame(const sl_settings *s, const sl_built_scene *b, long spp, unsigned long long seed,
                             int skylight, sl_camera *cam, sl_image *frame, float *stderr_rgb, sl_error *err)
{
  (void)s, (void)b, (void)spp, (void)seed, (void)skylight, (void)cam, (void)stderr_rgb;
  *frame = (sl_image){0};
  return sl_fail(err, SL_ERR_ARG, "this build left the Monte Carlo reference out (SL_RENDER_PARTS)");
}
#endif
