// The subcommand table (commands.def) and the small pieces every subcommand shares.
#pragma once

#define SL_COMMAND(name, fn, summary) int fn(int argc, char **argv);
#include "commands.def"
#undef SL_COMMAND
