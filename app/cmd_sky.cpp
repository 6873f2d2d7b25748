// stormlight sky: single-scattered sky radiance and transparency along one view ray (Riley et
// al. 2004 eqs. 11-15, corrected), or an image of the sky alone.
#include <cjson/cJSON.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cli.h"
#include "commands.h"
#include "sl_image_io.h"
#include "sl_sky.h"

bool sl_parse_iso8601_utc(const std::string &text, sl_utc *out, std::string *why);  // cmd_sun.cpp

namespace {

const double kPi = 3.14159265358979323846;

bool ends_with(const std::string &s, const std::string &tail)
{
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// Fills rgba (width x height) with the sky seen from eye: fisheye (equidistant, zenith at the
// centre, north up, east left as on a sky chart) or panorama (equirectangular, azimuth 0..360
// from the left edge, elevation +90..-90 from the top). Plans one sl_sky_view per image, as the
// renderer should.
void render_sky(const sl_atmosphere &atm, const double eye[3], const double sun[3], bool fisheye, int width,
                int height, float *rgba)
{
  sl_sky_view view;
  sl_sky_view_init(&view, &atm, eye, sun, nullptr);
  std::vector<double> disk(atm.count);
  sl::Progress progress("sky", true);
  for (int y = 0; y < height; ++y) {
    progress.update((double)y / height);
    for (int x = 0; x < width; ++x) {
      float *px = rgba + 4 * ((size_t)y * width + x);
      double dir[3];
      if (fisheye) {
        const double u = (2.0 * (x + 0.5) / width - 1.0), v = (1.0 - 2.0 * (y + 0.5) / height);
        const double r = std::sqrt(u * u + v * v);
        if (r > 1.0) {
          px[0] = px[1] = px[2] = px[3] = 0.0f;
          continue;
        }
        const double zenith = r * 0.5 * kPi, az = std::atan2(-u, v);
        dir[0] = std::sin(zenith) * std::sin(az);
        dir[1] = std::sin(zenith) * std::cos(az);
        dir[2] = std::cos(zenith);
      } else {
        const double az = 2.0 * kPi * (x + 0.5) / width, el = 0.5 * kPi - kPi * (y + 0.5) / height;
        dir[0] = std::cos(el) * std::sin(az);
        dir[1] = std::cos(el) * std::cos(az);
        dir[2] = std::sin(el);
      }
      double sky[3];
      sl_sky_view_segment(&view, dir, 0.0, INFINITY, sky, nullptr);
      sl_sky_sun_disk_radiance(&atm, eye, dir, sun, disk.data());
      for (int c = 0; c < 3; ++c) px[c] = (float)(sky[c] + disk[c]);
      px[3] = 1.0f;
    }
  }
  progress.done();
}

}  // namespace

int sl_cmd_sky(int argc, char **argv)
{
  sl::Options o("sky",
                "--eye-height M --view-elevation DEG --view-azimuth DEG --sun-elevation DEG --sun-azimuth DEG\n"
                "       [--distance M] [--earth flat|round] --json\n"
                "   or: stormlight sky --image --out sky.png|sky.exr [--projection fisheye|panorama] ...",
                "Single-scattered sky radiance gathered along the view ray from the eye (Riley et al. 2004\n"
                "eqs. 14-15, corrected; docs/SKY.md) to --distance or to the top of the atmosphere, and the\n"
                "ray's transparency (eq. 11), per wavelength, for a top-of-atmosphere sun of irradiance 1.\n"
                "--earth flat is the paper's model exactly; round gives the sunlight a spherical-earth\n"
                "(Chapman) air mass. The sun comes from --sun-elevation/--sun-azimuth or --date/--lat/--lon.\n"
                "A sun below the horizon is night: radiance 0 and \"night\": true.");
  o.option("eye-height", "M", "eye height above sea level in metres", "0");
  o.option("view-elevation", "DEG", "view direction above the horizon", "30");
  o.option("view-azimuth", "DEG", "view direction, clockwise from north", "180");
  o.option("sun-elevation", "DEG", "sun above the horizon", "30");
  o.option("sun-azimuth", "DEG", "sun, clockwise from north", "180");
  o.option("date", "ISO8601", "place the sun by date-time instead (needs --lat and --lon)");
  o.option("lat", "DEG", "latitude for --date");
  o.option("lon", "DEG", "longitude for --date");
  o.option("distance", "M", "segment length in metres (default: to the top of the atmosphere or the ground)");
  o.option("earth", "flat|round", "air mass of the sunlight", "round");
  o.option("wavelengths", "rgb|spectral|NM,NM,..", "rgb = 650,515,440 (Riley Table 2); spectral = 16 from 380 to 720",
           "rgb");
  o.option("rayleigh", "bodhaine|riley", "sea-level coefficients: standard air (Bodhaine 1999) or Riley Table 3",
           "bodhaine");
  o.flag("json", "print one JSON object");
  o.flag("image", "render the sky alone to --out instead");
  o.option("out", "FILE", "image file, .png (tone-mapped sRGB) or .exr (linear half float)");
  o.option("projection", "fisheye|panorama", "image projection", "fisheye");
  o.option("size", "N", "image height in pixels (panorama: width 2N)", "512");
  o.option("exposure", "E", "PNG tone mapping: 1 - exp(-E L)", "8");
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;

  const std::string earth_name = o.str("earth");
  if (earth_name != "flat" && earth_name != "round") return sl::fail("sky", "--earth must be flat or round", 2);
  const std::string rayleigh_name = o.str("rayleigh");
  if (rayleigh_name != "bodhaine" && rayleigh_name != "riley")
    return sl::fail("sky", "--rayleigh must be bodhaine or riley", 2);
  std::vector<double> wavelengths;
  const std::string wl = o.str("wavelengths");
  if (wl == "rgb") {
    wavelengths.assign(sl_sky_rgb_wavelengths_nm, sl_sky_rgb_wavelengths_nm + SL_SKY_RGB_COUNT);
  } else if (wl == "spectral") {
    wavelengths.resize(SL_SKY_SPECTRAL_COUNT);
    sl_sky_spectral_wavelengths(wavelengths.data());
  } else if (!o.list("wavelengths", &wavelengths)) {
    return sl::fail("sky", o.error(), 2);
  }

  sl_atmosphere atm;
  sl_error err{};
  if (sl_atmosphere_init(&atm, wavelengths.data(), (int)wavelengths.size(),
                         earth_name == "flat" ? SL_EARTH_FLAT : SL_EARTH_ROUND,
                         rayleigh_name == "riley" ? SL_RAYLEIGH_RILEY2004 : SL_RAYLEIGH_BODHAINE1999, &err))
    return sl::fail("sky", err.message, 2);

  double eye_height, view_el, view_az, sun_el, sun_az;
  if (!o.number("eye-height", &eye_height) || !o.number("view-elevation", &view_el) ||
      !o.number("view-azimuth", &view_az) || !o.number("sun-elevation", &sun_el) || !o.number("sun-azimuth", &sun_az))
    return sl::fail("sky", o.error(), 2);
  if (view_el < -90 || view_el > 90 || sun_el < -90 || sun_el > 90)
    return sl::fail("sky", "elevations must lie in [-90, 90] degrees", 2);
  if (eye_height < -500.0 || eye_height > 1e6) return sl::fail("sky", "--eye-height must lie in [-500, 1e6] m", 2);
  if (o.has("date")) {
    if (!o.has("lat") || !o.has("lon")) return sl::fail("sky", "--date needs --lat and --lon", 2);
    if (o.has("sun-elevation") || o.has("sun-azimuth"))
      return sl::fail("sky", "give either --date or --sun-elevation/--sun-azimuth", 2);
    sl_utc t;
    std::string why;
    if (!sl_parse_iso8601_utc(o.str("date"), &t, &why)) return sl::fail("sky", "--date: " + why, 2);
    double lat, lon;
    if (!o.number("lat", &lat) || !o.number("lon", &lon)) return sl::fail("sky", o.error(), 2);
    sl_solar_position p;
    if (sl_solar_position_compute(&t, lat, lon, nullptr, &p, &err)) return sl::fail("sky", err.message, 2);
    sun_el = p.elevation_deg;
    sun_az = p.azimuth_deg;
  }
  double sun[3], dir[3];
  sl_sun_direction(sun_el, sun_az, sun);
  sl_sun_direction(view_el, view_az, dir);
  const double eye[3] = {0.0, 0.0, eye_height};

  if (o.has("image")) {
    if (!o.has("out")) return sl::fail("sky", "--image needs --out FILE.png|FILE.exr", 2);
    const std::string out = o.str("out"), projection = o.str("projection");
    if (projection != "fisheye" && projection != "panorama")
      return sl::fail("sky", "--projection must be fisheye or panorama", 2);
    if (wl != "rgb") return sl::fail("sky", "--image needs --wavelengths rgb (650,515,440 as R,G,B)", 2);
    long size;
    double exposure;
    if (!o.integer("size", &size, 8, 8192) || !o.number("exposure", &exposure)) return sl::fail("sky", o.error(), 2);
    const bool fisheye = projection == "fisheye";
    const int width = fisheye ? (int)size : 2 * (int)size, height = (int)size;
    sl_image img{};
    if (sl_image_alloc(&img, width, height, &err)) return sl::fail("sky", err.message);
    render_sky(atm, eye, sun, fisheye, width, height, img.rgba);
    int status;
    if (ends_with(out, ".png")) status = sl_write_png(out.c_str(), &img, (float)exposure, &err);
    else if (ends_with(out, ".exr")) status = sl_write_exr(out.c_str(), &img, SL_EXR_HALF, &err);
    else status = sl_fail(&err, SL_ERR_ARG, "%s: the file name must end in .png or .exr", out.c_str());
    sl_image_free(&img);
    if (status) return sl::fail("sky", err.message);
    return 0;
  }

  double distance = INFINITY;
  if (o.has("distance") && (!o.number("distance", &distance) || distance < 0.0))
    return sl::fail("sky", "--distance must be a length >= 0 in metres", 2);
  std::vector<double> radiance(atm.count), transparency(atm.count), sunlight(atm.count);
  int night = 0;
  if (sl_sky_segment(&atm, eye, dir, distance, sun, radiance.data(), transparency.data(), &night, &err) ||
      sl_sky_sunlight(&atm, eye, sun, sunlight.data(), nullptr, &err))
    return sl::fail("sky", err.message);

  if (o.has("json")) {
    cJSON *root = cJSON_CreateObject();
    auto array = [&](const char *name, const double *v, int n) {
      cJSON *a = cJSON_AddArrayToObject(root, name);
      for (int i = 0; i < n; ++i) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[i]));
    };
    array("wavelengths_nm", atm.wavelength_nm, atm.count);
    array("beta_sea_level", atm.beta_sea_level, atm.count);
    cJSON_AddNumberToObject(root, "scale_height_m", atm.scale_height);
    array("radiance", radiance.data(), atm.count);
    array("transparency", transparency.data(), atm.count);
    array("sunlight_at_eye", sunlight.data(), atm.count);
    cJSON_AddBoolToObject(root, "night", night);
    cJSON_AddStringToObject(root, "earth", earth_name.c_str());
    cJSON_AddNumberToObject(root, "sun_elevation_deg", sun_el);
    cJSON_AddNumberToObject(root, "sun_azimuth_deg", sun_az);
    if (std::isfinite(distance)) cJSON_AddNumberToObject(root, "distance_m", distance);
    else cJSON_AddNullToObject(root, "distance_m");
    char *text = cJSON_PrintUnformatted(root);
    std::printf("%s\n", text);
    std::free(text);
    cJSON_Delete(root);
  } else {
    std::printf("eye %.1f m, view elevation %.3f azimuth %.3f, sun elevation %.3f azimuth %.3f, %s earth%s\n",
                eye_height, view_el, view_az, sun_el, sun_az, earth_name.c_str(), night ? " (night)" : "");
    std::printf("%10s %14s %14s %14s\n", "nm", "beta_sl 1/m", "radiance", "transparency");
    for (int i = 0; i < atm.count; ++i)
      std::printf("%10.1f %14.6e %14.6e %14.6e\n", atm.wavelength_nm[i], atm.beta_sea_level[i], radiance[i],
                  transparency[i]);
  }
  return 0;
}
