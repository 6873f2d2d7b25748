#include "render_scene.h"

#include <cmath>
#include <ctime>
#include <memory>

#include "scene.h"
#include "sl_sky.h"

bool sl_parse_iso8601_utc(const std::string &text, sl_utc *out, std::string *why);  // cmd_sun.cpp

namespace sl {

RenderScene::~RenderScene()
{
  if (have_frame) sl_storm_frame_free(&frame);
}

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
  s->data = o.positional()[0];
  double dz;
  if (!o.integer("time", &s->time_index, 0, SL_MAX_TIMES - 1) || !o.number("dz", &dz)) return failed(o.error());
  sl_error err{};
  LoadOptions load;  // --field, --region, --levels, --stride, --max-memory as render reads them
  std::string load_error;
  if (!parse_load_options(o, &load, &load_error)) return failed(load_error);
  load.load.time_index = (int)s->time_index;
  load.load.dz = dz;
  if (sl_storm_load(s->data.c_str(), &load.load, &s->frame, &err)) return failed(err.message);
  s->have_frame = true;
  if (o.has("sun-azimuth") || o.has("sun-elevation")) {
    if (!o.number("sun-azimuth", &s->sun_azimuth_deg) || !o.number("sun-elevation", &s->sun_elevation_deg))
      return failed(o.error());
  } else {
    sl_utc date{};
    if (o.has("date") && !sl_parse_iso8601_utc(o.str("date"), &date, why)) return failed("date: " + *why);
    bool no_times = false;
    if (!frame_solar_position(s->data, s->time_index, s->frame, o.has("date") ? &date : nullptr,
                              &s->sun_elevation_deg, &s->sun_azimuth_deg, nullptr, &no_times, why))
      return failed(*why);
  }
  // Compass azimuth into the volume's axes, which are the grid's (docs/GEOREFERENCING.md).
  s->sun_azimuth_deg = sl_georef_grid_azimuth(&s->frame.georef, s->sun_azimuth_deg);
  const std::string wl = o.str("wavelengths"), earth = o.str("earth");
  if (wl != "rgb" && wl != "spectral") return failed("wavelengths must be rgb or spectral");
  if (earth != "flat" && earth != "round") return failed("earth must be flat or round");
  s->spectral = wl == "spectral";
  s->flat_earth = earth == "flat";
  s->with_air = !o.has("no-atmosphere");
  if (!s->with_air) {
    if (s->spectral) return failed("no-atmosphere needs wavelengths rgb");
    std::vector<double> sky;
    if (!o.list("sky", &sky) || sky.size() != 3) return failed("sky must be R,G,B");
    for (int c = 0; c < 3; ++c) s->sky[c] = sky[c];
  }
  return true;
}

bool frame_solar_position(const std::string &file, long time_index, const sl_storm_frame &frame, const sl_utc *date,
                          double *elevation, double *azimuth, sl_utc *when_used, bool *no_times, std::string *why)
{
  sl_utc when{};
  *no_times = false;
  if (date) {
    when = *date;
    // A run that counts seconds from its start (CM1) starts at --date: each time adds its seconds.
    std::unique_ptr<sl_storm_info> info(new sl_storm_info);
    sl_error err{};
    if (sl_storm_read_info(file.c_str(), info.get(), &err) == SL_OK && !info->has_times && info->has_elapsed &&
        time_index >= 0 && time_index < info->ntimes && info->elapsed_s[time_index] != 0.0) {
      struct tm tm{};
      tm.tm_year = when.year - 1900, tm.tm_mon = when.month - 1, tm.tm_mday = when.day;
      tm.tm_hour = when.hour, tm.tm_min = when.minute;
      const double seconds = when.second + info->elapsed_s[time_index];
      const double whole = std::floor(seconds);
      time_t t = timegm(&tm) + (time_t)whole;
      gmtime_r(&t, &tm);
      when = {tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec + (seconds - whole)};
    }
  } else {
    std::unique_ptr<sl_storm_info> info(new sl_storm_info);
    sl_error err{};
    if (sl_storm_read_info(file.c_str(), info.get(), &err) != SL_OK || !info->has_times) {
      *no_times = true;
      const std::string cal = info->calendar;
      *why = file + (cal.empty() || cal == "standard"
                         ? ": the file has no times"
                         : ": the file has no times in a calendar this reader knows (calendar '" + cal + "')") +
             ": give a date or the sun's azimuth and elevation";
      return false;
    }
    std::string t = info->sun_times[time_index], reason;
    for (char &ch : t)
      if (ch == '_') ch = 'T';
    if (!sl_parse_iso8601_utc(t + "Z", &when, &reason)) {
      *why = file + ": time '" + info->times[time_index] + "' is not a date-time: " + reason;
      return false;
    }
  }
  sl_solar_position pos;
  sl_error err{};
  if (!std::isfinite(frame.center_lat) || !std::isfinite(frame.center_lon)) {
    *why = file + ": the grid has no latitude and longitude (CM1, a WRF idealized run with MAP_PROJ 0 and no --origin, "
                  "or a projected CF grid without 2-D lat/lon or a projection origin): give the sun's azimuth and "
                  "elevation";
    return false;
  }
  if (sl_solar_position_compute(&when, frame.center_lat, frame.center_lon, nullptr, &pos, &err)) {
    *why = err.message;
    return false;
  }
  *elevation = pos.elevation_deg, *azimuth = pos.azimuth_deg;
  if (when_used) *when_used = when;
  return true;
}

bool render_scene_camera(RenderScene *s, const double lo[3], const double hi[3], sl_camera *cam, std::string *why)
{
  Options &o = s->options;
  long width, height;
  double view_az, view_el, fov;
  if (!o.integer("width", &width, 1, 16384) || !o.integer("height", &height, 1, 16384) ||
      !o.number("view-azimuth", &view_az) || !o.number("view-elevation", &view_el) || !o.number("fov", &fov)) {
    *why = o.error();
    return false;
  }
  if (!(fov > 0 && fov < 170)) {
    *why = "fov must be in (0, 170) degrees";
    return false;
  }
  sl_camera_frame(lo, hi, view_az, view_el, fov, (int)width, (int)height, cam);
  if ((o.has("camera-target") && !o.vec3("camera-target", cam->target)) ||
      (o.has("camera-position") && !o.vec3("camera-position", cam->position))) {
    *why = o.error();
    return false;
  }
  return true;
}

}  // namespace sl
