#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "sl_tempfile.h"

int sl_temp_name(const char *path, char *tmp, size_t size, sl_error *err)
{
  if (!path || !*path) return sl_fail(err, SL_ERR_ARG, "empty output path");
  const char *slash = strrchr(path, '/');
  char dir[4096];
  const char *base = path;
  if (slash) {
    const size_t len = (size_t)(slash - path);
    if (len >= sizeof dir) return sl_fail(err, SL_ERR_ARG, "%s: path too long", path);
    memcpy(dir, path, len);
    dir[len] = '\0';
    if (len == 0) strcpy(dir, "/");
    base = slash + 1;
  } else {
    strcpy(dir, ".");
  }
  if (!*base) return sl_fail(err, SL_ERR_ARG, "%s: output path names a folder, not a file", path);
  if (access(dir, W_OK) != 0)
    return sl_fail(err, SL_ERR_IO, "%s: cannot write into folder '%s': %s", path, dir, strerror(errno));
  const int n = snprintf(tmp, size, "%s/.%s.%ld.tmp", dir, base, (long)getpid());
  if (n < 0 || (size_t)n >= size) return sl_fail(err, SL_ERR_ARG, "%s: path too long", path);
  return SL_OK;
}

int sl_temp_commit(const char *tmp, const char *path, sl_error *err)
{
  if (rename(tmp, path) != 0) {
    const int e = errno;
    unlink(tmp);
    return sl_fail(err, SL_ERR_IO, "%s: cannot move the finished file into place: %s", path, strerror(e));
  }
  return SL_OK;
}

int sl_temp_remove_stale(const char *path, int *removed, sl_error *err)
{
  if (removed) *removed = 0;
  if (!path || !*path) return sl_fail(err, SL_ERR_ARG, "empty output path");
  const char *slash = strrchr(path, '/');
  char dir[4096];
  const char *base = slash ? slash + 1 : path;
  const size_t len = slash ? (size_t)(slash - path) : 1;
  if (len >= sizeof dir) return sl_fail(err, SL_ERR_ARG, "%s: path too long", path);
  if (slash) memcpy(dir, path, len), dir[len] = '\0';
  else strcpy(dir, ".");
  if (slash && len == 0) strcpy(dir, "/");
  DIR *d = opendir(dir);
  if (!d) return errno == ENOENT ? SL_OK : sl_fail(err, SL_ERR_IO, "%s: cannot read folder '%s': %s", path, dir, strerror(errno));
  const size_t nb = strlen(base);
  struct dirent *e;
  int status = SL_OK;
  while ((e = readdir(d))) {
    /* exactly sl_temp_name's pattern: "." base "." digits ".tmp" */
    const char *n = e->d_name;
    if (n[0] != '.' || strncmp(n + 1, base, nb) != 0 || n[1 + nb] != '.') continue;
    char *end;
    const long pid = strtol(n + 2 + nb, &end, 10);
    if (end == n + 2 + nb || strcmp(end, ".tmp") != 0 || pid <= 0) continue;
    if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue; /* its writer is alive (or not ours to judge) */
    char full[4096 + 256];
    snprintf(full, sizeof full, "%s/%s", dir, n);
    if (unlink(full) != 0 && errno != ENOENT) {
      status = sl_fail(err, SL_ERR_IO, "%s: cannot remove the stale temporary file: %s", full, strerror(errno));
      break;
    }
    if (removed) ++*removed;
  }
  closedir(d);
  return status;
}
