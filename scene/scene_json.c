/* A scene file (docs/SCENES.md): one JSON object whose keys are the options of sl_settings_options
 * (plus "data", the storm file, and "comment"), turned into the command line it stands for, so
 * that a scene and a command line are read by the same parser. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sl_settings.h"

static int push(sl_scene_args *a, const char *text)
{
  char **grown = realloc(a->argv, (a->argc + 2) * sizeof *grown);
  if (!grown) return 0;
  a->argv = grown;
  a->argv[a->argc] = strdup(text);
  if (!a->argv[a->argc]) return 0;
  a->argv[++a->argc] = NULL;
  return 1;
}

void sl_scene_args_free(sl_scene_args *a)
{
  for (int i = 0; i < a->argc; ++i) free(a->argv[i]);
  free(a->argv);
  a->argv = NULL, a->argc = 0;
}

/* A path from the scene, relative to the scene file's folder unless absolute. */
static int push_path(sl_scene_args *a, const char *path, const char *value)
{
  const char *slash = strrchr(path, '/');
  const int dir_len = slash ? (int)(slash - path) : 1;
  const char *dir = slash ? path : ".";
  char *joined = malloc(strlen(path) + strlen(value) + 4);
  if (!joined) return 0;
  if (value[0] == '/' || !value[0]) strcpy(joined, value);
  else sprintf(joined, "%.*s/%s", dir_len, dir, value);
  const int ok = push(a, joined);
  free(joined);
  return ok;
}

int sl_scene_json_args(const char *text, const char *path, sl_scene_args *out, sl_error *err)
{
  out->argc = 0, out->argv = NULL;
  cJSON *root = cJSON_Parse(text);
  if (!root || !cJSON_IsObject(root)) {
    cJSON_Delete(root);
    return sl_fail(err, SL_ERR_FORMAT, "%s: not a JSON object", path);
  }
  int rc = SL_OK, nomem = 0;
  /* "data" first: the positional storm file. */
  const cJSON *data = cJSON_GetObjectItemCaseSensitive(root, "data");
  if (data && !cJSON_IsString(data)) rc = sl_fail(err, SL_ERR_FORMAT, "%s: 'data' must be a string", path);
  else if (data) nomem |= !push_path(out, path, data->valuestring);
  for (const cJSON *item = root->child; item && !rc && !nomem; item = item->next) {
    const char *key = item->string ? item->string : "";
    if (!strcmp(key, "comment") || !strcmp(key, "data")) continue;
    if (!strcmp(key, "camera_keys")) continue; /* a series' camera path (app/camera_path.cpp reads it) */
    const sl_option *o = sl_settings_option(key);
    if (!o) {
      rc = sl_fail(err, SL_ERR_FORMAT, "%s: unknown scene key '%s'", path, key);
      break;
    }
    char flag[128];
    snprintf(flag, sizeof flag, "--%s", key);
    if (!strcmp(key, "out")) {
      if (!cJSON_IsString(item)) rc = sl_fail(err, SL_ERR_FORMAT, "%s: 'out' must be a string", path);
      else nomem |= !push(out, flag) || !push_path(out, path, item->valuestring);
    } else if (cJSON_IsBool(item)) {
      if (cJSON_IsTrue(item)) nomem |= !push(out, flag);
    } else if (cJSON_IsNumber(item)) {
      if (!isfinite(item->valuedouble)) {
        rc = sl_fail(err, SL_ERR_FORMAT, "%s: '%s' is not a finite number", path, key);
        break;
      }
      char number[64];
      snprintf(number, sizeof number, "%.17g", item->valuedouble);
      nomem |= !push(out, flag) || !push(out, number);
    } else if (cJSON_IsString(item)) {
      nomem |= !push(out, flag) || !push(out, item->valuestring);
    } else if (cJSON_IsArray(item)) {
      char list[1024] = "";
      size_t used = 0;
      for (const cJSON *e = item->child; e; e = e->next) {
        if (!cJSON_IsNumber(e)) {
          rc = sl_fail(err, SL_ERR_FORMAT, "%s: '%s' must hold numbers", path, key);
          break;
        }
        const int n = snprintf(list + used, sizeof list - used, "%s%.17g", used ? "," : "", e->valuedouble);
        if (n < 0 || (size_t)n >= sizeof list - used) {
          rc = sl_fail(err, SL_ERR_FORMAT, "%s: '%s' holds too many numbers", path, key);
          break;
        }
        used += (size_t)n;
      }
      if (!rc) nomem |= !push(out, flag) || !push(out, list);
    } else {
      rc = sl_fail(err, SL_ERR_FORMAT, "%s: '%s' has an unsupported type", path, key);
    }
  }
  cJSON_Delete(root);
  if (nomem && !rc) rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
  if (rc) sl_scene_args_free(out);
  return rc;
}

/* An error about the scene file `path`: err's message with the path in front. */
static int fail_naming(sl_error *err, int rc, const char *path)
{
  char message[sizeof err->message];
  snprintf(message, sizeof message, "%s", err->message);
  err->code = 0;
  return sl_fail(err, rc, "%s: %s", path, message);
}

int sl_scene_file_args(const char *path, sl_scene_args *out, sl_error *err)
{
  FILE *f = fopen(path, "rb");
  if (!f) return sl_fail(err, SL_ERR_IO, "%s: cannot open the scene file", path);
  char *text = NULL;
  size_t size = 0, cap = 0;
  for (;;) {
    if (size + 4096 + 1 > cap) {
      cap = 2 * cap + 4096 + 1;
      char *grown = realloc(text, cap);
      if (!grown) {
        free(text);
        fclose(f);
        return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
      }
      text = grown;
    }
    const size_t n = fread(text + size, 1, 4096, f);
    size += n;
    if (n < 4096) break;
  }
  fclose(f);
  text[size] = '\0';
  const int rc = sl_scene_json_args(text, path, out, err);
  free(text);
  return rc;
}

int sl_settings_from_scene_file(sl_settings *s, const char *path, sl_error *err)
{
  sl_scene_args args;
  int rc = sl_scene_file_args(path, &args, err);
  if (rc) return rc;
  rc = sl_settings_parse_args(s, args.argc, args.argv, err);
  if (rc) rc = fail_naming(err, rc, path);
  sl_scene_args_free(&args);
  return rc;
}

int sl_settings_from_scene(sl_settings *s, const char *path, int argc, char **argv, sl_error *err)
{
  sl_settings_defaults(s);
  int rc = sl_settings_from_scene_file(s, path, err);
  if (rc) return rc;
  if (argc > 0 && (rc = sl_settings_parse_args(s, argc, argv, err))) return fail_naming(err, rc, path);
  if (!s->data[0]) return sl_fail(err, SL_ERR_ARG, "%s: the scene names no \"data\" file", path);
  if ((rc = sl_settings_check(s, err))) return fail_naming(err, rc, path);
  return SL_OK;
}
