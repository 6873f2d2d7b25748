#include "cli.h"

#include "scene.h"
#include "sl_scene_build.h"

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace sl {

Options::Options(std::string command, std::string usage, std::string description)
    : command_(std::move(command)), usage_(std::move(usage)), description_(std::move(description))
{
  flag("help", "show this help and exit");
}

void Options::flag(const std::string &name, const std::string &help)
{
  Spec s;
  s.name = name;
  s.help = help;
  s.is_flag = true;
  specs_.push_back(s);
}

void Options::option(const std::string &name, const std::string &metavar, const std::string &help,
                     const std::string &default_value)
{
  Spec s;
  s.name = name;
  s.metavar = metavar;
  s.help = help;
  s.value = default_value;
  specs_.push_back(s);
}

Options::Spec *Options::find(const std::string &name)
{
  for (Spec &s : specs_)
    if (s.name == name) return &s;
  return nullptr;
}

const Options::Spec *Options::find(const std::string &name) const
{
  for (const Spec &s : specs_)
    if (s.name == name) return &s;
  return nullptr;
}

bool Options::parse(int argc, char **argv)
{
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a.size() > 2 && a[0] == '-' && a[1] == '-') {
      std::string name = a.substr(2), value;
      bool inline_value = false;
      const size_t eq = name.find('=');
      if (eq != std::string::npos) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
        inline_value = true;
      }
      Spec *s = find(name);
      if (!s) {
        error_ = "unknown option --" + name + " (see 'stormlight " + command_ + " --help')";
        return false;
      }
      if (s->is_flag) {
        if (inline_value) {
          error_ = "option --" + name + " takes no value";
          return false;
        }
        s->given = true;
        if (name == "help") help_ = true;
        continue;
      }
      if (!inline_value) {
        if (i + 1 >= argc) {
          error_ = "option --" + name + " needs a value (" + s->metavar + ")";
          return false;
        }
        value = argv[++i];
      }
      s->value = value;
      s->given = true;
    } else if (a == "-h") {
      help_ = true;
    } else if (a.size() > 1 && a[0] == '-' && !(std::isdigit((unsigned char)a[1]) || a[1] == '.')) {
      error_ = "unknown option " + a + " (see 'stormlight " + command_ + " --help')";
      return false;
    } else {
      positional_.push_back(a);
    }
  }
  return true;
}

void Options::print_help() const
{
  std::printf("usage: stormlight %s %s\n\n%s\n\noptions:\n", command_.c_str(), usage_.c_str(),
              description_.c_str());
  for (const Spec &s : specs_) {
    std::string left = "--" + s.name + (s.is_flag ? "" : " " + s.metavar);
    std::printf("  %-28s %s", left.c_str(), s.help.c_str());
    if (!s.is_flag && !s.value.empty()) std::printf(" (default %s)", s.value.c_str());
    std::printf("\n");
  }
}

bool Options::has(const std::string &name) const
{
  const Spec *s = find(name);
  return s && s->given;
}

std::string Options::str(const std::string &name) const
{
  const Spec *s = find(name);
  return s ? s->value : std::string();
}

static bool parse_double(const std::string &text, double *out)
{
  if (text.empty()) return false;
  errno = 0;
  char *end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (errno != 0 || *end != '\0' || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

bool Options::number(const std::string &name, double *out)
{
  const std::string v = str(name);
  if (!parse_double(v, out)) {
    error_ = "option --" + name + ": '" + v + "' is not a finite number";
    return false;
  }
  return true;
}

bool Options::integer(const std::string &name, long *out, long min, long max)
{
  const std::string v = str(name);
  errno = 0;
  char *end = nullptr;
  const long x = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || errno != 0 || *end != '\0' || x < min || x > max) {
    error_ = "option --" + name + ": '" + v + "' is not an integer in [" + std::to_string(min) + ", " +
             std::to_string(max) + "]";
    return false;
  }
  *out = x;
  return true;
}

bool Options::list(const std::string &name, std::vector<double> *out)
{
  out->clear();
  std::stringstream ss(str(name));
  std::string item;
  while (std::getline(ss, item, ',')) {
    double v;
    if (!parse_double(item, &v)) {
      error_ = "option --" + name + ": '" + item + "' is not a finite number";
      return false;
    }
    out->push_back(v);
  }
  if (out->empty()) {
    error_ = "option --" + name + " needs at least one number";
    return false;
  }
  return true;
}

bool Options::vec3(const std::string &name, double out[3])
{
  std::vector<double> v;
  if (!list(name, &v)) return false;
  if (v.size() != 3) {
    error_ = "option --" + name + " needs three numbers x,y,z";
    return false;
  }
  for (int i = 0; i < 3; ++i) out[i] = v[i];
  return true;
}

int parse_or_exit(Options &opts, int argc, char **argv)
{
  if (!opts.parse(argc, argv)) {
    std::fprintf(stderr, "stormlight %s: %s\n", argv[0], opts.error().c_str());
    return 2;
  }
  if (opts.help_requested()) {
    opts.print_help();
    return 0;
  }
  return -1;
}

int fail(const std::string &command, const std::string &message, int code)
{
  std::fprintf(stderr, "stormlight %s: %s\n", command.c_str(), message.c_str());
  return code;
}

bool stderr_is_tty() { return isatty(STDERR_FILENO) != 0; }

double now_seconds()
{
  using clock = std::chrono::steady_clock;
  return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

Progress::Progress(const char *label, bool enabled) : label_(label), enabled_(enabled && stderr_is_tty())
{
  start_ = now_seconds();
}

Progress::~Progress() { done(); }

void Progress::update(double fraction)
{
  if (!enabled_ || finished_) return;
  // Quiet for the first second: short jobs print nothing.
  if (now_seconds() - start_ < 1.0) return;
  const int percent = (int)std::lround(100.0 * (fraction < 0 ? 0 : fraction > 1 ? 1 : fraction));
  if (percent == last_percent_) return;
  last_percent_ = percent;
  const int width = 30, filled = percent * width / 100;
  std::fprintf(stderr, "\r%-12s [%.*s%*s] %3d%%", label_, filled, "##############################",
               width - filled, "", percent);
  // Remaining time at the average rate so far: what a long job (a series) needs to be planned.
  const double elapsed = now_seconds() - start_;
  if (percent > 0 && percent < 100) {
    const long eta = std::lround(elapsed * (1.0 - fraction) / fraction);
    std::fprintf(stderr, "  ETA %ld:%02ld:%02ld ", eta / 3600, eta / 60 % 60, eta % 60);
  } else {
    std::fprintf(stderr, "%16s", "");
  }
  std::fflush(stderr);
}

void Progress::done()
{
  if (!enabled_ || finished_) return;
  if (last_percent_ < 0) {
    finished_ = true;
    return;
  }
  last_percent_ = -2;
  update(1.0);
  finished_ = true;
  std::fprintf(stderr, "  %.1f s\n", now_seconds() - start_);
}

bool parse_load_options(Options &o, LoadOptions *out, std::string *error)
{
  // The load options through the one option table's parser (scene/settings.c).
  sl_settings *s = new sl_settings;
  const bool ok = settings_from_options(o, "", s, error);
  if (ok) {
    sl_settings_load_options(s, 0, &out->load);
    for (int t = 0; t < SL_PARTICLE_COUNT; ++t) {
      out->fields[t] = s->field_variable[t];
      out->load.field_variable[t] = out->fields[t].empty() ? nullptr : out->fields[t].c_str();
    }
  }
  delete s;
  return ok;
}

}  // namespace sl
