/* Renders one frame of a storm file to EXR through libstormlight, as `stormlight render
 * STORM.nc --cpu-composite` draws it: settings (defaults, then flags), the scene built once
 * (plan once), then a frame of it (render many): the camera as render frames it, the volume over
 * the sky.
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
      sl_settings_check(&s, &err) || sl_scene_build(&s, NULL, &scene, &err)) {
    fprintf(stderr, "render_frame: %s\n", err.message);
    return 1;
  }
  sl_camera cam;
  sl_image frame;
  int rc = sl_scene_render_frame(&s, &scene, &cam, &frame, NULL, &err);
  if (!rc) {
    rc = sl_write_exr(argv[2], &frame, SL_EXR_FLOAT, &err);
    sl_image_free(&frame);
  }
  if (rc) fprintf(stderr, "render_frame: %s\n", err.message);
  sl_built_scene_free(&scene);
  return rc ? 1 : 0;
}
