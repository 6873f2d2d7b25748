// A `stormlight render` scene (docs/SCENES.md) resolved into what any renderer of it needs: the
// storm at its time, the sun as render places it, the air and the camera's parameters. One reading
// for the reference (cmd_reference.cpp) and the validation report (cmd_validate.cpp), so that both
// renderers see the scene exactly as `stormlight render` does.
#pragma once

#include <string>
#include <vector>

#include "cli.h"
#include "sl_renderer.h"
#include "sl_sky.h"
#include "sl_storm.h"

namespace sl {

struct RenderScene {
  Options options{"render", "", ""};  // render's options with the scene's values and render's defaults
  std::string data;                   // the storm file
  long time_index = 0;
  sl_storm_frame frame{};
  bool have_frame = false;
  double sun_elevation_deg = 0, sun_azimuth_deg = 0;
  bool with_air = true, flat_earth = false, spectral = false;
  double sky[3] = {0, 0, 0};  // without air: the constant background
  RenderScene() = default;
  RenderScene(const RenderScene &) = delete;
  RenderScene &operator=(const RenderScene &) = delete;
  ~RenderScene();
};

// Reads the scene file, applies `overrides` (render arguments such as {"--width", "64"}, placed
// after the scene's so they win), loads the storm and places the sun (given angles, `date`, or the
// file's own time over the grid's centre). Returns false with one line naming the file and the
// problem.
bool load_render_scene(const std::string &path, const std::vector<std::string> &overrides, RenderScene *s,
                       std::string *why);

// The sun over a loaded frame as render places it: the solar position at `date` (when not null) or
// else at the file's own time of time_index, over the frame's centre. Compass azimuth and
// elevation, degrees, and the time used (when_used may be null). False with one line naming the file and the problem; *no_times is set when
// the file has no times to fall back on (a usage error: give a date or the sun's angles).
bool frame_solar_position(const std::string &file, long time_index, const sl_storm_frame &frame, const sl_utc *date,
                          double *elevation, double *azimuth, sl_utc *when_used, bool *no_times, std::string *why);

// The scene's camera for content bounds lo..hi (sl_renderer_content_bounds): render's framing from
// view-azimuth and view-elevation, or camera-position and camera-target where the scene gives them.
bool render_scene_camera(RenderScene *s, const double lo[3], const double hi[3], sl_camera *cam, std::string *why);

}  // namespace sl
