/* Stormlight's public C API, one header: settings from a scene file or flags (sl_settings.h), the
 * scene built once from them (sl_scene_build.h: storm, sun, air, tables, renderer, camera), the
 * renderer (sl_renderer.h), storms (sl_storm.h) and images (sl_image.h, sl_image_io.h).
 * docs/ARCHITECTURE.md, "The C API"; docs/examples/render_frame.c. Link with
 * `pkg-config --cflags --libs stormlight` or CMake's find_package(Stormlight). */
#ifndef STORMLIGHT_H
#define STORMLIGHT_H

#include "sl_camera.h"
#include "sl_georef.h"
#include "sl_image.h"
#include "sl_image_io.h"
#include "sl_optics.h"
#include "sl_renderer.h"
#include "sl_scene_build.h"
#include "sl_scene_frame.h"
#include "sl_settings.h"
#include "sl_sky.h"
#include "sl_status.h"
#include "sl_storm.h"
#include "sl_storm_json.h"
#include "sl_volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The library's version, "MAJOR.MINOR.PATCH" (that of the headers is STORMLIGHT_VERSION). */
const char *sl_version(void);

#ifdef __cplusplus
}
#endif

#include "stormlight_version.h"

#endif
