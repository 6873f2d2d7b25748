// Scene files: a JSON object whose keys are stormlight render's options (docs/SCENES.md). A scene
// becomes command-line arguments placed before the user's own, so flags override the file.
#pragma once

#include <string>
#include <vector>

#include "cli.h"

namespace sl {

// Declares the options a scene may set (everything of `stormlight render` except its command-line
// conveniences): one list for render, for the reference's reading of render scenes, and for the
// check of scene keys.
void declare_render_options(Options &o);
// The terrain and map-layer options (read by read_map_options, app/terrain_scene.h).
void declare_map_options(Options &o);
// Night-sky luminance and the emissive town lights (read by app/night_scene.h).
void declare_night_options(Options &o);

// Reads a scene file into render arguments: "data" becomes the positional FILE (relative paths
// are taken relative to the scene file's folder), every other key "--key value" (booleans
// become flags when true, arrays become comma-separated lists). Returns false and fills error
// with one line naming the file and the problem.
bool scene_to_arguments(const std::string &path, std::vector<std::string> *args, std::string *error);
// The same from the file's text (`path` names it in messages and anchors relative paths).
bool scene_text_to_arguments(const std::string &text, const std::string &path, std::vector<std::string> *args,
                             std::string *error);

}  // namespace sl
