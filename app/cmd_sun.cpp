// stormlight sun: the sun's apparent elevation and azimuth for a UTC date-time and a place.
#include <cjson/cJSON.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>

#include "cli.h"
#include "commands.h"
#include "sl_sky.h"

// Parses ISO 8601 "YYYY-MM-DDTHH:MM[:SS[.fff]][Z|+hh:mm|-hh:mm]" (a space may replace the T; no
// zone means UTC) into a UTC date-time. Shared with cmd_sky.cpp through the declaration there.
bool sl_parse_iso8601_utc(const std::string &text, sl_utc *out, std::string *why)
{
  sl_error err{};
  if (sl_utc_parse_iso8601(text.c_str(), out, &err) == SL_OK) return true;
  *why = err.message;
  return false;
}

int sl_cmd_sun(int argc, char **argv)
{
  sl::Options o("sun", "--date ISO8601 --lat DEG --lon DEG [--json]",
                "The sun's apparent (refracted) elevation and azimuth, clockwise from north, for a date-time\n"
                "and a place: Meeus (1998) ch. 25 solar coordinates with nutation, apparent sidereal time,\n"
                "parallax and the refraction of NREL's SPA; within 0.005 degrees of SPA (docs/ACCURACY.md).\n"
                "A date without a zone is UTC; +hh:mm / -hh:mm offsets are applied.");
  o.option("date", "ISO8601", "date-time, e.g. 2024-06-21T05:30:00Z or 2003-10-17T12:30:30-07:00");
  o.option("lat", "DEG", "latitude, north positive");
  o.option("lon", "DEG", "longitude, east positive");
  o.option("pressure", "HPA", "surface pressure for refraction", "1010");
  o.option("temperature", "C", "surface temperature for refraction", "10");
  o.option("delta-t", "S", "TT - UT in seconds", "69.2");
  o.flag("no-refraction", "report the geometric elevation");
  o.flag("json", "print one JSON object");
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (!o.has("date") || !o.has("lat") || !o.has("lon")) return sl::fail("sun", "--date, --lat and --lon are required", 2);
  sl_utc t;
  std::string why;
  if (!sl_parse_iso8601_utc(o.str("date"), &t, &why)) return sl::fail("sun", "--date: " + why, 2);
  double lat, lon;
  sl_solar_options opt;
  sl_solar_options_default(&opt);
  if (!o.number("lat", &lat) || !o.number("lon", &lon) || !o.number("pressure", &opt.pressure_hpa) ||
      !o.number("temperature", &opt.temperature_c) || !o.number("delta-t", &opt.delta_t_s))
    return sl::fail("sun", o.error(), 2);
  opt.refraction = !o.has("no-refraction");
  sl_solar_position p;
  sl_error err{};
  if (sl_solar_position_compute(&t, lat, lon, &opt, &p, &err)) return sl::fail("sun", err.message, 2);

  if (o.has("json")) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "elevation", p.elevation_deg);
    cJSON_AddNumberToObject(root, "azimuth", p.azimuth_deg);
    cJSON_AddNumberToObject(root, "zenith", p.zenith_deg);
    cJSON_AddNumberToObject(root, "elevation_geometric", p.elevation_true_deg);
    cJSON_AddBoolToObject(root, "night", p.night);
    cJSON *dir = cJSON_AddArrayToObject(root, "direction_enu");
    for (double c : p.direction) cJSON_AddItemToArray(dir, cJSON_CreateNumber(c));
    cJSON_AddNumberToObject(root, "declination", p.declination_deg);
    cJSON_AddNumberToObject(root, "julian_day", p.julian_day);
    char date[64];
    std::snprintf(date, sizeof date, "%04d-%02d-%02dT%02d:%02d:%06.3fZ", t.year, t.month, t.day, t.hour,
                  t.minute, t.second);
    cJSON_AddStringToObject(root, "date_utc", date);
    cJSON_AddStringToObject(root, "algorithm", "Meeus 1998 ch. 25 + nutation + SPA refraction");
    char *text = cJSON_PrintUnformatted(root);
    std::printf("%s\n", text);
    std::free(text);
    cJSON_Delete(root);
  } else {
    std::printf("%04d-%02d-%02dT%02d:%02d:%06.3fZ at %.6f, %.6f\n", t.year, t.month, t.day, t.hour, t.minute,
                t.second, lat, lon);
    std::printf("elevation %.4f deg%s, azimuth %.4f deg (clockwise from north)%s\n", p.elevation_deg,
                opt.refraction ? " (apparent)" : " (geometric)", p.azimuth_deg, p.night ? ", night" : "");
  }
  return 0;
}
