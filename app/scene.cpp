#include "scene.h"

#include <cjson/cJSON.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace sl {

namespace {

std::string number_text(double v)
{
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

// The scene around the storm (app/terrain_scene.*): declared here with the scene's other options
// so that the option list (and the scene-key check) needs no VTK or GMT.
void declare_map_options(Options &o)
{
  o.flag("terrain", "draw the terrain (HGT) as a lit surface: eye rays stop at it, the storm shadows it");
  o.option("terrain-albedo", "A", "terrain albedo (default: the file's ALBEDO, else land 0.15, water 0.06)");
  o.flag("coastlines", "draw GSHHG coastlines (GMT) draped on the terrain");
  o.flag("borders", "draw national borders (DCW through GMT) draped on the terrain");
  o.flag("graticule", "draw a latitude/longitude graticule");
  o.option("graticule-step", "DEG", "graticule spacing in degrees (0 = 3 to 8 lines across the domain)", "0");
  o.flag("domain-outline", "draw the outline of the model domain");
  o.flag("scale-bar", "draw a scale bar in the domain's south-west corner");
}

// Night and emissive lights (app/night_scene.*, docs/SCENES.md "Night and lights"): declared here
// for the same reason as the map options.
void declare_night_options(Options &o)
{
  o.option("night-sky-luminance", "CD_M2", "luminance of the sky above the horizon, cd/m^2, added to the analytic sky (which\n"
           "is 0 once the sun is down): e.g. 2e-4 for a moonless natural night sky", "0");
  o.option("lights-count", "NX,NY", "a town of NX x NY emissive street lamps on the ground (default: none)");
  o.option("lights-center", "X,Y", "the town's centre, metres east, north in the world frame", "0,0");
  o.option("lights-spacing", "M", "distance between neighbouring lamps", "150");
  o.option("lights-height", "M", "lamp height above the ground (the file's HGT)", "10");
  o.option("lights-jitter", "F", "each lamp moved by up to +-F/2 of the spacing (seeded, reproducible)", "0.6");
  o.option("lights-intensity-cd", "CD", "luminous intensity of one lamp toward the camera, cd (isotropic)", "1000");
  o.option("lights-color", "R,G,B", "lamp colour as relative linear-sRGB weights (scaled to unit luminance; default: high-pressure\n"
           "sodium, chromaticity x 0.52, y 0.42)", "1,0.29,0.01");
}

void declare_render_options(Options &o)
{
  o.option("out", "FILES", "output image(s), comma-separated: .exr (linear HDR) and/or .png (tone-mapped)");
  o.option("time", "N", "time index in the file", "0");
  o.option("width", "PX", "image width", "512");
  o.option("height", "PX", "image height", "512");
  o.option("slices", "N", "slicing planes across the volume (0 = enough to resolve the grid)", "0");
  o.option("light-resolution", "N", "square light-buffer texels along its longer side (0 = automatic: per axis, about a pixel at the cloud, at most a grid cell)", "0");
  o.option("sun-azimuth", "DEG", "sun azimuth, clockwise from north (with --sun-elevation; default: from the date)");
  o.option("sun-elevation", "DEG", "sun elevation above the horizon (with --sun-azimuth)");
  o.option("date", "ISO8601", "UTC date-time that places the sun over the grid's centre (default: the file's time)");
  o.option("earth", "flat|round", "air mass of the sunlight: the paper's flat earth or a spherical one", "round");
  o.option("curvature", "flat|drop", "storm columns on the tangent plane (flat) or sunk by the sphere's depth below it\n"
           "(drop: r^2/2R, 19.6 km at 500 km; docs/GEOREFERENCING.md)", "flat");
  o.option("origin", "LAT,LON", "tangent point of the world frame (default: the grid's centre at this time)");
  o.option("lighting", "MODEL", "multiple (Riley eqs. 16-26 with eq. 24), eq25 (the paper's eq. 25), low-albedo (Fig. 13)",
           "multiple");
  o.option("xi", "XI", "eq. 26's back-scattering term added to Ams, 1/sr: light that higher orders return and the\n"
           "forward-only light buffer discards (0 for thin media)", "0.05");
  o.option("wavelengths", "SET", "rgb (650, 515, 440 nm as red, green, blue) or spectral (16 from 380 to 720 nm via CIE)",
           "rgb");
  o.option("fog-visibility-km", "V", "glows (Narasimhan et al.) of bright sources seen through fog of small droplets "
           "(cloud tables) with this visibility; 0 = none", "0");
  o.option("fog-type", "fog|haze", "with --fog-visibility-km: fog (small droplets, cloud tables) or haze (Shettle & Fenn's "
           "rural aerosol through Mie, not grey)", "fog");
  o.option("fog-depth-km", "D", "with fog: how deep the fog bank in front of the camera is (what lies farther is seen "
           "through all of it)", "2");
  o.flag("light-volume", "light a cached view-independent light volume once, then ray-march (fast camera moves)");
  o.option("march-samples", "N", "with --light-volume or --gpu: eye samples per grid cell along a ray, 1..8 (fewer is\n"
           "faster and coarser on thick cloud surfaces; docs/ACCURACY.md)", "2");
  o.flag("no-atmosphere", "no air: unattenuated white sunlight and the constant --sky behind the volume");
  o.option("camera-position", "X,Y,Z", "camera position, metres east, north, up (default frames the cloud)");
  o.option("camera-target", "X,Y,Z", "point the camera looks at (default: the cloud's centre)");
  o.option("view-azimuth", "DEG", "default camera: compass direction from the cloud to the camera", "200");
  o.option("view-elevation", "DEG", "default camera: elevation of the camera seen from the cloud", "12");
  o.option("fov", "DEG", "vertical field of view", "40");
  o.option("threads", "N", "OpenMP threads (0 = all cores)", "0");
  o.option("exposure", "E", "PNG tone mapping: 1 - exp(-E L)", "12");
  o.option("sky", "R,G,B", "with --no-atmosphere: the constant sky radiance", "0.035,0.055,0.10");
  o.option("dz", "M", "vertical spacing of the uniform grid (0 = half the mean model layer)", "0");
  o.flag("float", "write 32-bit float EXR channels instead of half");
  declare_load_options(o);
  declare_map_options(o);  // the scene around the storm: terrain and map layers
  declare_night_options(o);
}

bool scene_to_arguments(const std::string &path, std::vector<std::string> *args, std::string *error)
{
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open the scene file";
    return false;
  }
  std::stringstream text;
  text << in.rdbuf();
  return scene_text_to_arguments(text.str(), path, args, error);
}

bool scene_text_to_arguments(const std::string &text, const std::string &path, std::vector<std::string> *args,
                             std::string *error)
{
  Options declared("render", "", "");
  declare_render_options(declared);
  cJSON *root = cJSON_Parse(text.c_str());
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
    if (key == "camera_keys") continue;  // a series' camera path (app/camera_path.cpp reads it)
    if (key != "data" && (!declared.declared(key) || key == "help")) {
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
