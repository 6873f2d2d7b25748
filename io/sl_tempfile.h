/* Output files are written to a temporary name beside the target and renamed when complete,
 * so a failed or interrupted write never leaves a half-written file under the real name. */
#ifndef SL_TEMPFILE_H
#define SL_TEMPFILE_H

#include <stddef.h>

#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fills tmp with "<dir>/.<name>.<pid>.tmp" beside path and checks that the folder is writable. */
int sl_temp_name(const char *path, char *tmp, size_t size, sl_error *err);
/* Renames tmp to path, removing tmp on failure. */
int sl_temp_commit(const char *tmp, const char *path, sl_error *err);

/* Removes the temporary files that writers of path left when they were killed: "<dir>/.<name>.
 * <pid>.tmp" beside path whose process no longer exists (a live writer's are kept). *removed (may
 * be NULL) gets how many went. A folder that does not exist has none. */
int sl_temp_remove_stale(const char *path, int *removed, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
