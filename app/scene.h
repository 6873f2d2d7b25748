// Scene files: a JSON object whose keys are stormlight render's options (docs/SCENES.md). A scene
// becomes command-line arguments placed before the user's own, so flags override the file.
#pragma once

#include <string>
#include <vector>

namespace sl {

// Reads a scene file into render arguments: "data" becomes the positional FILE (relative paths
// are taken relative to the scene file's folder), every other key "--key value" (booleans
// become flags when true, arrays become comma-separated lists). Returns false and fills error
// with one line naming the file and the problem.
bool scene_to_arguments(const std::string &path, std::vector<std::string> *args, std::string *error);

}  // namespace sl
