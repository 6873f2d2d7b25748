#include "scene.h"

#include <cstring>
#include <fstream>
#include <sstream>

namespace sl {

namespace {

void declare_from_table(Options &o, const sl_option &opt)
{
  if (opt.type == SL_OPTION_FLAG) o.flag(opt.name, opt.help);
  else o.option(opt.name, opt.metavar, opt.help, opt.fallback ? opt.fallback : "");
}

bool in_list(const char *name, const char *const *names)
{
  for (; *names; ++names)
    if (std::strcmp(name, *names) == 0) return true;
  return false;
}

const char *const kLoadOptions[] = {"field", "particles", "max-fields", "droplet-number", "region",
                                    "levels", "stride", "max-memory", nullptr};

}  // namespace

void declare_load_options(Options &o)
{
  for (int i = 0; i < sl_settings_option_count; ++i)
    if (in_list(sl_settings_options[i].name, kLoadOptions)) declare_from_table(o, sl_settings_options[i]);
}

void declare_render_options(Options &o)
{
  for (int i = 0; i < sl_settings_option_count; ++i) declare_from_table(o, sl_settings_options[i]);
}

bool settings_from_options(Options &o, const std::string &data, sl_settings *s, std::string *why)
{
  sl_settings_defaults(s);
  sl_error err{};
  for (int i = 0; i < sl_settings_option_count; ++i) {
    const char *name = sl_settings_options[i].name;
    if (!o.declared(name) || !o.has(name)) continue;
    if (sl_settings_set(s, name, o.is_flag(name) ? nullptr : o.str(name).c_str(), &err)) {
      *why = err.message;
      return false;
    }
  }
  if (data.size() >= sizeof s->data) {
    *why = "the storm file's path is too long";
    return false;
  }
  std::strcpy(s->data, data.c_str());
  return true;
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
  sl_scene_args a{};
  sl_error err{};
  if (sl_scene_json_args(text.c_str(), path.c_str(), &a, &err)) {
    *error = err.message;
    return false;
  }
  args->insert(args->end(), a.argv, a.argv + a.argc);
  sl_scene_args_free(&a);
  return true;
}

}  // namespace sl
