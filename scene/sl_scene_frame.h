/* One frame of a built scene, drawn on the CPU as `stormlight render --cpu-composite` draws it
 * where the scene holds nothing of the command line's own layers: the front ends without VTK
 * (the Python module, programs linking libstormlight) call this. */
#ifndef SL_SCENE_FRAME_H
#define SL_SCENE_FRAME_H

#include "sl_scene_build.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The option of settings s that sl_scene_render_frame does not draw, or NULL: terrain and map
 * lines (VTK draws them), lamps and the night sky, fog (the CLI's passes). */
const char *sl_scene_frame_unsupported(const sl_settings *s);

/* Frames the camera as render does (sl_scene_camera over the renderer's content bounds) into *cam,
 * stops its eye rays at the round ground, and draws the volume over the sky into frame (allocated
 * here at the camera's size; the caller frees it with sl_image_free): premultiplied linear RGBA,
 * the volume's transparency, and the depth of the volume over the ground's. cam's
 * opaque_distance is NULL on return. SL_ERR_ARG where sl_scene_frame_unsupported names an
 * option. */
int sl_scene_render_frame(const sl_settings *s, sl_built_scene *b, sl_camera *cam, sl_image *frame,
                          sl_render_stats *stats, sl_error *err);

/* The same frame by the Monte Carlo reference (render/reference, docs/REFERENCE.md): the built
 * storm as a reference medium at the tables' wavelengths, the same sun, air, camera and round
 * ground, spp samples per pixel and wavelength from seed (skylight: scattered paths that leave
 * the box collect the sky). stderr_rgb (3 floats per pixel, may be NULL) receives each channel's
 * standard error. The scene needs its particle tables (not the low-albedo model's). */
int sl_scene_reference_frame(const sl_settings *s, const sl_built_scene *b, long spp, unsigned long long seed,
                             int skylight, sl_camera *cam, sl_image *frame, float *stderr_rgb, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
