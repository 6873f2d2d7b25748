#include "scene.h"

#include <cjson/cJSON.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace sl {

namespace {

const char *const kKeys[] = {"data", "time", "width", "height", "slices", "light-resolution", "sun-azimuth",
                             "sun-elevation", "date", "earth", "camera-position", "camera-target", "view-azimuth",
                             "view-elevation", "fov", "exposure", "xi", "lighting", "wavelengths", "light-volume",
                             "no-atmosphere", "sky", "dz", "float", "threads", "out", "fog-visibility-km", "fog-depth-km"};

bool known(const char *key)
{
  for (const char *k : kKeys)
    if (std::string(k) == key) return true;
  return false;
}

std::string number_text(double v)
{
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

bool scene_to_arguments(const std::string &path, std::vector<std::string> *args, std::string *error)
{
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open the scene file";
    return false;
  }
  std::stringstream text;
  text << in.rdbuf();
  cJSON *root = cJSON_Parse(text.str().c_str());
  if (!root || !cJSON_IsObject(root)) {
    *error = path + ": not a JSON object";
    cJSON_Delete(root);
    return false;
  }
  const std::string dir = path.find('/') == std::string::npos ? "." : path.substr(0, path.rfind('/'));
  bool ok = true;
  for (cJSON *item = root->child; item && ok; item = item->next) {
    const std::string key = item->string ? item->string : "";
    if (key == "comment") continue;
    if (!known(key.c_str())) {
      *error = path + ": unknown scene key '" + key + "'";
      ok = false;
      break;
    }
    if (key == "data" || key == "out") {
      if (!cJSON_IsString(item)) {
        *error = path + ": '" + key + "' must be a string";
        ok = false;
        break;
      }
      std::string value = item->valuestring;
      if (!value.empty() && value[0] != '/') value = dir + "/" + value;
      if (key == "data") args->insert(args->begin(), value);
      else args->push_back("--out"), args->push_back(value);
    } else if (cJSON_IsBool(item)) {
      if (cJSON_IsTrue(item)) args->push_back("--" + key);
    } else if (cJSON_IsNumber(item)) {
      if (!std::isfinite(item->valuedouble)) {
        *error = path + ": '" + key + "' is not a finite number";
        ok = false;
        break;
      }
      args->push_back("--" + key);
      args->push_back(number_text(item->valuedouble));
    } else if (cJSON_IsString(item)) {
      args->push_back("--" + key);
      args->push_back(item->valuestring);
    } else if (cJSON_IsArray(item)) {
      std::string list;
      for (cJSON *e = item->child; e; e = e->next) {
        if (!cJSON_IsNumber(e)) {
          *error = path + ": '" + key + "' must hold numbers";
          ok = false;
          break;
        }
        list += (list.empty() ? "" : ",") + number_text(e->valuedouble);
      }
      args->push_back("--" + key);
      args->push_back(list);
    } else {
      *error = path + ": '" + key + "' has an unsupported type";
      ok = false;
    }
  }
  cJSON_Delete(root);
  return ok;
}

}  // namespace sl
