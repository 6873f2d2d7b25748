/* Renders one frame of a storm file to EXR through libstormlight, as `stormlight render
 * STORM.nc --cpu-composite` draws it: settings (defaults, then flags), the scene built once,
 * the camera as render frames it, the volume over the sky.
 *   cc render_frame.c $(pkg-config --cflags --libs stormlight) -o render_frame
 *   ./render_frame datasets/cumulus.nc frame.exr --width 320 --height 240 */
#include <stdio.h>

#include <stormlight.h>

int main(int argc, char **argv)
{
  if (argc < 3) {
    fprintf(stderr, "usage: render_frame STORM.nc OUT.exr [--option value ...]\n");
    return 2;
  }
  sl_error err = {0};
  sl_settings s;
  sl_settings_defaults(&s);
  sl_built_scene scene;
  if (sl_settings_parse_args(&s, 1, argv + 1, &err) || sl_settings_parse_args(&s, argc - 3, argv + 3, &err) ||
      sl_scene_build(&s, NULL, &scene, &err)) {
    fprintf(stderr, "render_frame: %s\n", err.message);
    return 1;
  }
  double lo[3], hi[3];
  sl_camera cam;
  sl_renderer_content_bounds(scene.renderer, lo, hi);
  sl_scene_camera(&s, lo, hi, &cam);
  sl_image volume = {0}, sky = {0}, frame = {0};
  int rc = sl_image_alloc(&volume, cam.width, cam.height, &err) || sl_image_alloc(&sky, cam.width, cam.height, &err) ||
           sl_image_alloc(&frame, cam.width, cam.height, &err) ||
           sl_renderer_render(scene.renderer, &cam, &volume, NULL, &err) ||
           sl_renderer_background(scene.renderer, &cam, &sky, &err);
  if (!rc) {
    sl_image_over(&volume, &sky, &frame);
    rc = sl_write_exr(argv[2], &frame, SL_EXR_FLOAT, &err);
  }
  if (rc) fprintf(stderr, "render_frame: %s\n", err.message);
  sl_image_free(&frame), sl_image_free(&sky), sl_image_free(&volume);
  sl_built_scene_free(&scene);
  return rc ? 1 : 0;
}
