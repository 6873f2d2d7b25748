// A small option parser shared by every subcommand: declared options, generated --help,
// one-line errors for unknown options and malformed values.
#pragma once

#include <string>
#include <vector>

#include "sl_storm.h"

namespace sl {

class Options {
 public:
  Options(std::string command, std::string usage, std::string description);

  // Declares a flag (no value) or an option with a value and its default ("" = none).
  void flag(const std::string &name, const std::string &help);
  void option(const std::string &name, const std::string &metavar, const std::string &help,
              const std::string &default_value = "");

  // Parses argv (argv[0] is the command name). Returns false and fills error() for bad input;
  // sets help_requested() on --help. Positional arguments are collected in order.
  bool parse(int argc, char **argv);
  bool help_requested() const { return help_; }
  const std::string &error() const { return error_; }
  void print_help() const;

  bool has(const std::string &name) const;  // given on the command line (or a flag set)
  bool declared(const std::string &name) const { return find(name) != nullptr; }
  bool is_flag(const std::string &name) const { const Spec *s = find(name); return s && s->is_flag; }
  std::string str(const std::string &name) const;
  // Typed getters return false and fill error() when the value does not parse.
  bool number(const std::string &name, double *out);
  bool integer(const std::string &name, long *out, long min, long max);
  bool vec3(const std::string &name, double out[3]);
  bool list(const std::string &name, std::vector<double> *out);
  const std::vector<std::string> &positional() const { return positional_; }

 private:
  struct Spec {
    std::string name, metavar, help, value;
    bool is_flag = false, given = false;
  };
  Spec *find(const std::string &name);
  const Spec *find(const std::string &name) const;

  std::string command_, usage_, description_, error_;
  std::vector<Spec> specs_;
  std::vector<std::string> positional_;
  bool help_ = false;
};

// Standard handling at the top of a subcommand: prints help (returns 0) or the one-line error
// (returns 2); returns -1 when the command should go on.
int parse_or_exit(Options &opts, int argc, char **argv);

// Prints "stormlight <command>: <message>" on stderr and returns the exit code.
int fail(const std::string &command, const std::string &message, int code = 1);

// Tells whether stderr is a terminal (progress bars only go there).
bool stderr_is_tty();

// A terminal progress bar for work longer than a second; silent when stderr is not a terminal.
class Progress {
 public:
  Progress(const char *label, bool enabled);
  ~Progress();
  void update(double fraction);  // 0..1, thread-safe enough for one caller
  void done();

 private:
  const char *label_;
  bool enabled_;
  double start_;
  int last_percent_ = -1;
  bool finished_ = false;
};

double now_seconds();

// How much of a storm file to read (render, info): --field TYPE=VARIABLE,..., --region, --levels,
// --stride, --max-memory. The strings behind field_variable live in `LoadOptions` itself.
struct LoadOptions {
  sl_load_options load{};
  std::string fields[SL_PARTICLE_COUNT];
};
void declare_load_options(Options &o);
// Fills *out from the declared options (time and dz are left to the caller); false with the
// one-line error in *error for a malformed value.
bool parse_load_options(Options &o, LoadOptions *out, std::string *error);

}  // namespace sl
