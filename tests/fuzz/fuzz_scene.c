/* libFuzzer target: the scene-file parser on arbitrary text: JSON to arguments
 * (sl_scene_json_args), then the arguments into settings (sl_settings_parse_args, every option's
 * value parser) and the checks between them. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sl_settings.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  char *text = malloc(size + 1);
  if (!text) return 0;
  memcpy(text, data, size);
  text[size] = '\0';
  sl_scene_args args;
  sl_error err = {0};
  if (sl_scene_json_args(text, "fuzz/scene.json", &args, &err) == SL_OK) {
    sl_settings *s = malloc(sizeof *s);
    if (s) {
      sl_settings_defaults(s);
      if (sl_settings_parse_args(s, args.argc, args.argv, &err) == SL_OK) sl_settings_check(s, &err);
      free(s);
    }
    sl_scene_args_free(&args);
  }
  free(text);
  return 0;
}
