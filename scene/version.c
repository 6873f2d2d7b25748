/* The library's version, from the project's (CMakeLists.txt). */
#include "stormlight.h"

const char *sl_version(void) { return STORMLIGHT_VERSION; }
