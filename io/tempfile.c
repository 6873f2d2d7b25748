#include <errno.h>
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
