// Scene files: a JSON object whose keys are stormlight render's options (docs/SCENES.md). A scene
// becomes command-line arguments placed before the user's own, so flags override the file.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cli.h"
#include "sl_scene_build.h"
#include "sl_settings.h"

namespace sl {

// Declares the options a scene may set (everything of `stormlight render` except its command-line
// conveniences), from the one option table (sl_settings_options, scene/sl_settings.h): names,
// defaults and help come from it.
void declare_render_options(Options &o);
// The settings the parsed options give: the table's defaults, each option given set through
// sl_settings_set (one line naming the option when a value is bad), and `data` as the storm file.
bool settings_from_options(Options &o, const std::string &data, sl_settings *s, std::string *why);

// A built scene (sl_scene_build, or its stages) freed with what it holds.
struct BuiltSceneFree {
  void operator()(sl_built_scene *b) const
  {
    sl_built_scene_free(b);
    delete b;
  }
};
using BuiltScenePtr = std::unique_ptr<sl_built_scene, BuiltSceneFree>;

// Reads a scene file into render arguments (sl_scene_json_args): "data" becomes the positional
// FILE (relative paths are taken relative to the scene file's folder), every other key
// "--key value" (booleans become flags when true, arrays become comma-separated lists). Returns
// false and fills error with one line naming the file and the problem.
bool scene_to_arguments(const std::string &path, std::vector<std::string> *args, std::string *error);
// The same from the file's text (`path` names it in messages and anchors relative paths).
bool scene_text_to_arguments(const std::string &text, const std::string &path, std::vector<std::string> *args,
                             std::string *error);

}  // namespace sl
