#include "render_scene.h"

#include "scene.h"
#include "sl_georef.h"

namespace sl {

RenderScene::~RenderScene() { sl_built_scene_free(&built); }

bool load_render_scene(const std::string &path, const std::vector<std::string> &overrides, RenderScene *s,
                       std::string *why)
{
  std::vector<std::string> args;
  if (!scene_to_arguments(path, &args, why)) return false;
  const auto failed = [&](const std::string &message) {
    *why = path + ": " + message;
    return false;
  };
  declare_render_options(s->options);  // the same options and defaults render reads the scene with
  std::vector<std::string> all = {"render"};
  all.insert(all.end(), args.begin(), args.end());
  all.insert(all.end(), overrides.begin(), overrides.end());
  std::vector<char *> cargv;
  for (std::string &a : all) cargv.push_back(&a[0]);
  Options &o = s->options;
  if (!o.parse((int)cargv.size(), cargv.data())) return failed(o.error());
  if (o.positional().size() != 1) return failed("the scene names no \"data\" file");
  sl_error err{};
  if (!settings_from_options(o, o.positional()[0], &s->settings, why)) return failed(*why);
  if (sl_settings_check(&s->settings, &err) || sl_scene_load(&s->settings, 0, &s->built, &err)) return failed(err.message);
  s->sun_elevation_deg = s->built.sun_elevation_deg;
  // Compass azimuth into the volume's axes, which are the grid's (docs/GEOREFERENCING.md).
  s->sun_azimuth_deg = sl_georef_grid_azimuth(&s->frame.georef, s->built.sun_azimuth_deg);
  s->spectral = s->settings.spectral;
  s->with_air = !s->settings.no_atmosphere;
  for (int c = 0; c < 3; ++c) s->sky[c] = s->settings.sky[c];
  return true;
}

}  // namespace sl
