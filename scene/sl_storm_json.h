/* What a storm file holds, as `stormlight info --json` prints it and the Python package's
 * Storm.info() returns it: the file's grid, times, projection and scheme (sl_storm_read_info),
 * and the loaded time's uniform grid, placement, species with their sizes, size tables, field
 * statistics and memory (sl_storm_load). */
#ifndef SL_STORM_JSON_H
#define SL_STORM_JSON_H

#include "sl_storm.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A WRF MAP_PROJ, a netCDF format code (NC_FORMAT_*) and a storm file's kind in words. */
const char *sl_projection_name(int map_proj);
const char *sl_storm_kind_name(sl_storm_format kind);
const char *sl_netcdf_format_name(int format);

/* The JSON text (malloc'd; the caller frees it), or NULL with err naming the file. */
char *sl_storm_info_json(const char *path, const sl_load_options *load, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
