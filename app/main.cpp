// stormlight: the command-line front door. Each subcommand lives in app/cmd_<name>.cpp.
#include <cstdio>
#include <cstring>

#include "commands.h"

namespace {

struct Command {
  const char *name;
  int (*fn)(int, char **);
  const char *summary;
};

const Command kCommands[] = {
#define SL_COMMAND(name, fn, summary) {#name, fn, summary},
#include "commands.def"
#undef SL_COMMAND
};

void print_help(FILE *out)
{
  std::fprintf(out,
               "usage: stormlight <command> [options]\n"
               "       stormlight --version | --help\n\n"
               "Physically based rendering of storm simulations (Riley et al. 2004).\n\ncommands:\n");
  for (const Command &c : kCommands) std::fprintf(out, "  %-10s %s\n", c.name, c.summary);
  std::fprintf(out, "\nRun 'stormlight <command> --help' for a command's options.\n");
}

}  // namespace

int main(int argc, char **argv)
{
  if (argc < 2) {
    print_help(stderr);
    return 2;
  }
  if (!std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
    print_help(stdout);
    return 0;
  }
  if (!std::strcmp(argv[1], "--version")) {
    std::printf("stormlight %s\n", SL_VERSION);
    return 0;
  }
  for (const Command &c : kCommands)
    if (!std::strcmp(argv[1], c.name)) return c.fn(argc - 1, argv + 1);
  std::fprintf(stderr, "stormlight: unknown command '%s' (see 'stormlight --help')\n", argv[1]);
  return 2;
}
