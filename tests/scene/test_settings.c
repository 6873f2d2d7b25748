/* The scene's settings (scene/settings.c, scene_json.c) and UTC date-times (render/sky/utc.c):
 *   - every default of the option table parses and means what its help text says;
 *   - the table and the keys docs/SCENES.md documents are the same set;
 *   - command-line text and a scene file give the same settings; bad values are one-line errors
 *     naming the option;
 *   - ISO 8601 dates against the calendar (offsets across midnight and a leap day) and a CM1 run's
 *     elapsed seconds across a month's end. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sl_renderer.h"
#include "sl_settings.h"
#include "sl_testing.h"

static void test_defaults(void)
{
  sl_settings s;
  sl_settings_defaults(&s);
  /* The values render's --help has always stated, as numbers. */
  CHECK(s.width == 512 && s.height == 512 && s.time_index == 0 && s.slices == 0);
  CHECK_CLOSE(s.xi, 0, 0, 0);
  CHECK(s.skylight == 1 && s.diffuse_sunlight == 1);
  CHECK_CLOSE(s.fov_deg, 40, 0, 0);
  CHECK_CLOSE(s.view_azimuth_deg, 200, 0, 0);
  CHECK_CLOSE(s.sky[1], 0.055, 0, 0);
  CHECK_CLOSE(s.lights_color[1], 0.29, 0, 0);
  CHECK(s.lighting == SL_LIGHTING_MULTIPLE && !s.spectral && !s.flat_earth && !s.curvature_drop);
  CHECK(s.max_fields == SL_VOLUME_MAX_FIELDS && s.march_samples == 1 && s.stride == 1);
  /* Defaults are not "given": a scene that sets nothing places the sun from the file's time. */
  int given = 0;
  for (int i = 0; i < sl_settings_option_count; ++i) given += s.given[i];
  CHECK(given == 0);
  /* Every fallback parses by itself (the table cannot carry a default its parser refuses). */
  for (int i = 0; i < sl_settings_option_count; ++i) {
    const sl_option *o = &sl_settings_options[i];
    sl_error err = {0};
    if (o->fallback) CHECK_MSG(sl_settings_set(&s, o->name, o->fallback, &err) == SL_OK, o->name);
    CHECK_MSG((o->type == SL_OPTION_FLAG) == (o->metavar == NULL), o->name);
  }
}

/* The keys docs/SCENES.md documents: the first cell of its tables headed "| key | type | meaning |"
 * (the camera path's "key field" table documents a key's fields, not scene keys). */
static void test_documented_keys(const char *scenes_md)
{
  FILE *f = fopen(scenes_md, "r");
  CHECK_MSG(f != NULL, scenes_md);
  if (!f) return;
  char line[2048], documented[128][64];
  int n = 0;
  int in_table = 0;
  while (fgets(line, sizeof line, f)) {
    if (line[0] != '|') in_table = 0;
    if (!strncmp(line, "| key | type | meaning |", 24)) in_table = 1;
    if (!in_table || strncmp(line, "| `", 3) != 0) continue;
    /* The first cell: one or more `key` separated by commas. */
    char *end = strchr(line + 1, '|');
    if (!end) continue;
    *end = '\0';
    for (char *p = strchr(line, '`'); p && n < 128; p = strchr(p + 1, '`')) {
      char *q = strchr(p + 1, '`');
      if (!q) break;
      snprintf(documented[n++], sizeof documented[0], "%.*s", (int)(q - p - 1), p + 1);
      p = q;
    }
  }
  fclose(f);
  for (int i = 0; i < n; ++i) {
    const char *k = documented[i];
    const int special = !strcmp(k, "data") || !strcmp(k, "comment") || !strcmp(k, "camera_keys");
    char what[128];
    snprintf(what, sizeof what, "documented key '%.60s' is an option", k);
    CHECK_MSG(special || sl_settings_option(k) != NULL, what);
  }
  for (int i = 0; i < sl_settings_option_count; ++i) {
    int found = 0;
    for (int j = 0; j < n; ++j) found |= !strcmp(documented[j], sl_settings_options[i].name);
    char what[128];
    snprintf(what, sizeof what, "option '%.60s' is documented in SCENES.md", sl_settings_options[i].name);
    CHECK_MSG(found, what);
  }
}

/* A file holding text (a scene). */
static void write_text(const char *path, const char *text)
{
  FILE *f = fopen(path, "w");
  CHECK(f != NULL);
  if (!f) return;
  fputs(text, f);
  fclose(f);
}

static void test_args_and_json(const char *work)
{
  sl_settings a, b;
  sl_settings_defaults(&a);
  sl_settings_defaults(&b);
  char *argv[] = {"storms/s.nc", "--width", "64", "--curvature", "drop", "--origin", "25.2,-90.2", "--light-volume",
                  "--field", "hail=QHAIL,snow=none", "--levels", "2:5", "--max-memory", "1.5G", "--date",
                  "2024-06-21T05:30:00Z", "--sky", "1,2,3", "--lighting", "low-albedo", NULL};
  sl_error err = {0};
  CHECK(sl_settings_parse_args(&a, 20, argv, &err) == SL_OK);
  CHECK(!strcmp(a.data, "storms/s.nc") && a.width == 64 && a.curvature_drop && a.light_volume);
  CHECK_CLOSE(a.origin[1], -90.2, 0, 0);
  CHECK(sl_settings_given(&a, "origin") && !sl_settings_given(&a, "height"));
  CHECK(!strcmp(a.field_variable[SL_HAIL], "QHAIL") && !strcmp(a.field_variable[SL_SNOW], "none"));
  CHECK(a.level_first == 2 && a.level_count == 4);
  CHECK_CLOSE(a.max_memory, 1.5 * 1024 * 1024 * 1024, 0, 0);
  CHECK(a.date.year == 2024 && a.date.hour == 5 && a.date.minute == 30);
  CHECK(a.lighting == SL_LIGHTING_LOW_ALBEDO);
  CHECK_CLOSE(a.sky[2], 3, 0, 0);

  /* The same as a scene file in a folder: data relative to it, a boolean, arrays. */
  char path[1024];
  snprintf(path, sizeof path, "%s/scene.json", work);
  FILE *f = fopen(path, "w");
  CHECK(f != NULL);
  if (!f) return;
  fprintf(f, "{\"comment\": \"x\", \"data\": \"s.nc\", \"width\": 64, \"curvature\": \"drop\", \"origin\": [25.2, -90.2],"
             " \"light-volume\": true, \"field\": \"hail=QHAIL,snow=none\", \"levels\": \"2:5\", \"max-memory\": \"1.5G\","
             " \"date\": \"2024-06-21T05:30:00Z\", \"sky\": [1, 2, 3], \"lighting\": \"low-albedo\", \"terrain\": false}");
  fclose(f);
  CHECK(sl_settings_from_scene_file(&b, path, &err) == SL_OK);
  char data[1100];
  snprintf(data, sizeof data, "%s/s.nc", work);
  CHECK(!strcmp(b.data, data));
  memset(b.data, 0, sizeof b.data);
  strcpy(b.data, a.data);
  /* The dates field by field (a struct's padding is not its value), then the rest byte for byte. */
  CHECK(a.date.year == b.date.year && a.date.month == b.date.month && a.date.day == b.date.day &&
        a.date.hour == b.date.hour && a.date.minute == b.date.minute && a.date.second == b.date.second);
  memcpy(&b.date, &a.date, sizeof a.date);
  CHECK_MSG(memcmp(&a, &b, sizeof a) == 0, "scene file and command line give the same settings");

  /* Bad input: one line naming the option (or the file and the key). */
  struct {
    const char *name, *value, *says;
  } bad[] = {{"width", "0", "--width"},          {"curvature", "bent", "--curvature"}, {"origin", "95,0", "--origin"},
             {"sky", "1,2", "--sky"},            {"max-memory", "lots", "--max-memory"},
             {"field", "sleet=Q", "sleet=Q"},    {"date", "2024-02-30T00:00Z", "out of range"},
             {"xi", "nan", "--xi"},              {"levels", "3:1", "--levels"},
             {"lights-count", "0,3", "--lights-count"}};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
    sl_error e = {0};
    CHECK_MSG(sl_settings_set(&b, bad[i].name, bad[i].value, &e) != SL_OK && strstr(e.message, bad[i].says) &&
                  !strchr(e.message, '\n'),
              bad[i].name);
  }
  sl_error e = {0};
  CHECK(sl_settings_set(&b, "colour", "red", &e) == SL_ERR_ARG);
  f = fopen(path, "w");
  fprintf(f, "{\"colour\": \"red\"}");
  fclose(f);
  e = (sl_error){0};
  CHECK(sl_settings_from_scene_file(&b, path, &e) != SL_OK && strstr(e.message, "unknown scene key 'colour'") &&
        strstr(e.message, path));
  /* A scene as validate and reference read it: the defaults, the file, then the overrides win; a
   * scene with no storm file, or whose options contradict, is refused naming the file. */
  write_text(path, "{\"data\": \"s.nc\", \"width\": 64, \"xi\": 0.2}");
  char *overrides[] = {"--width", "32", "--fov", "30"};
  e = (sl_error){0};
  CHECK(sl_settings_from_scene(&b, path, 4, overrides, &e) == SL_OK);
  CHECK(b.width == 32 && b.height == 512 && b.fov_deg == 30.0 && b.xi == 0.2 && !strcmp(b.data, data));
  CHECK(sl_settings_given(&b, "xi") && !sl_settings_given(&b, "slices"));
  write_text(path, "{\"width\": 64}");
  e = (sl_error){0};
  CHECK(sl_settings_from_scene(&b, path, 0, NULL, &e) == SL_ERR_ARG && strstr(e.message, "names no \"data\"") &&
        strstr(e.message, path));
  write_text(path, "{\"data\": \"s.nc\", \"sun-azimuth\": 90}");
  e = (sl_error){0};
  CHECK(sl_settings_from_scene(&b, path, 0, NULL, &e) == SL_ERR_ARG && strstr(e.message, "--sun-elevation") &&
        strstr(e.message, path));
  char *bad_override[] = {"--width", "-3"};
  e = (sl_error){0};
  CHECK(sl_settings_from_scene(&b, path, 2, bad_override, &e) == SL_ERR_ARG && strstr(e.message, "--width") &&
        strstr(e.message, path));
  sl_settings c;
  sl_settings_defaults(&c);
  sl_settings_set(&c, "sun-azimuth", "90", &e);
  e = (sl_error){0};
  CHECK(sl_settings_check(&c, &e) != SL_OK && strstr(e.message, "--sun-elevation"));
}

static void test_dates(void)
{
  sl_utc t;
  sl_error err = {0};
  /* An offset across midnight into a leap day: 2024-03-01 01:30 at +03:00 is 2024-02-29 22:30 UTC. */
  CHECK(sl_utc_parse_iso8601("2024-03-01T01:30:15.5+03:00", &t, &err) == SL_OK);
  CHECK(t.year == 2024 && t.month == 2 && t.day == 29 && t.hour == 22 && t.minute == 30);
  CHECK_CLOSE(t.second, 15.5, 0, 0);
  CHECK(sl_utc_parse_iso8601("2023-02-29T00:00Z", &t, &err) != SL_OK);
  /* A CM1 run started at 2005-08-31 23:00 UTC, 7230.25 s later: 2005-09-01 01:00:30.25. */
  sl_utc start = {2005, 8, 31, 23, 0, 0.0};
  CHECK(sl_utc_add_seconds(&start, 7230.25, &err) == SL_OK);
  CHECK(start.year == 2005 && start.month == 9 && start.day == 1 && start.hour == 1 && start.minute == 0);
  CHECK_CLOSE(start.second, 30.25, 0, 1e-9);
  /* Back across a year's end. */
  sl_utc y = {2025, 1, 1, 0, 0, 10.0};
  CHECK(sl_utc_add_seconds(&y, -20.0, &err) == SL_OK);
  CHECK(y.year == 2024 && y.month == 12 && y.day == 31 && y.hour == 23 && y.minute == 59);
  CHECK_CLOSE(y.second, 50.0, 0, 0);
}

int main(int argc, char **argv)
{
  if (argc < 3) {
    fprintf(stderr, "usage: test_settings docs/SCENES.md WORKDIR\n");
    return 2;
  }
  test_defaults();
  test_documented_keys(argv[1]);
  test_args_and_json(argv[2]);
  test_dates();
  return sl_test_finish("test_settings");
}
