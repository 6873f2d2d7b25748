/* The flat ground's albedo without --terrain (sl_scene_ground_albedo): ground-albedo where given;
 * else the domain's mean of the file's ALBEDO (out-of-range fill values left out); else land and
 * water from its land mask, at Briegleb et al. (1986)'s 0.15 and 0.06 (a quarter land: 0.0825);
 * else land's 0.15. */
#include <string.h>

#include "sl_scene_build.h"
#include "sl_testing.h"

int main(void)
{
  sl_settings s;
  sl_settings_defaults(&s);
  sl_storm_frame f;
  memset(&f, 0, sizeof f);
  f.volume.nx = 4, f.volume.ny = 2;
  CHECK_CLOSE(sl_scene_ground_albedo(&s, &f), 0.15, 0, 1e-12); /* nothing in the file: land */

  float land[8] = {1, 1, 0, 0, 0, 0, 0, 0};
  f.land_mask = land;
  CHECK_CLOSE(sl_scene_ground_albedo(&s, &f), 0.0825, 0, 1e-7);

  float albedo[8] = {0.2f, 0.2f, 0.2f, 0.2f, 0.2f, 0.2f, 0.2f, -999.0f};
  f.surface_albedo = albedo; /* the file's own albedo wins over the land mask */
  CHECK_CLOSE(sl_scene_ground_albedo(&s, &f), 0.2, 0, 1e-7);

  sl_error err = {0};
  CHECK(sl_settings_set(&s, "ground-albedo", "0.3", &err) == SL_OK);
  CHECK_CLOSE(sl_scene_ground_albedo(&s, &f), 0.3, 0, 1e-12); /* given: the setting's */
  CHECK(sl_settings_set(&s, "ground-albedo", "0", &err) == SL_OK);
  CHECK_CLOSE(sl_scene_ground_albedo(&s, &f), 0.0, 0, 0);
  return sl_test_finish("test_ground_albedo");
}
