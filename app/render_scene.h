// A `stormlight render` scene (docs/SCENES.md) for the reference (cmd_reference.cpp) and the
// validation report (cmd_validate.cpp): its settings and its storm and sun, loaded by the same
// sl_scene_load that render's sl_scene_build calls, so that both renderers see the scene exactly
// as `stormlight render` does.
#pragma once

#include <string>
#include <vector>

#include "cli.h"
#include "sl_renderer.h"
#include "sl_scene_build.h"
#include "sl_sky.h"
#include "sl_storm.h"

namespace sl {

struct RenderScene {
  Options options{"render", "", ""};  // render's options with the scene's values and render's defaults
  sl_settings settings{};             // the same as typed settings (scene/sl_settings.h)
  sl_built_scene built{};             // the storm and its sun (sl_scene_load): no air, tables or renderer
  sl_storm_frame &frame = built.frame;
  int &have_frame = built.have_frame;
  double sun_elevation_deg = 0, sun_azimuth_deg = 0;  // the sun's azimuth in the grid's axes
  bool with_air = true, spectral = false;
  double sky[3] = {0, 0, 0};  // without air: the constant background
  RenderScene() = default;
  RenderScene(const RenderScene &) = delete;
  RenderScene &operator=(const RenderScene &) = delete;
  ~RenderScene();
};

// Reads the scene file, applies `overrides` (render arguments such as {"--width", "64"}, placed
// after the scene's so they win), loads the storm and places the sun as render does
// (sl_scene_load: given angles, `date`, or the file's own time over the grid's centre). Returns
// false with one line naming the scene file and the problem.
bool load_render_scene(const std::string &path, const std::vector<std::string> &overrides, RenderScene *s,
                       std::string *why);

}  // namespace sl
