/* Stale temporary files (io/sl_tempfile.h): a killed writer's ".<name>.<pid>.tmp" goes, a live
 * writer's stays, and so do other names that only look alike. The dead pid is a child that has
 * exited and been reaped. */
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "sl_tempfile.h"
#include "sl_testing.h"

static void touch(const char *path)
{
  FILE *f = fopen(path, "w");
  if (f) fclose(f);
}

static int exists(const char *path)
{
  struct stat st;
  return stat(path, &st) == 0;
}

int main(void)
{
  char dir[] = "/tmp/sl_tempfile_XXXXXX";
  CHECK(mkdtemp(dir) != NULL);
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, NULL, 0);
  char target[256], dead[320], live[320], other_name[320], other_pid[320];
  snprintf(target, sizeof target, "%s/storm_0003.exr", dir);
  snprintf(dead, sizeof dead, "%s/.storm_0003.exr.%ld.tmp", dir, (long)child);
  snprintf(live, sizeof live, "%s/.storm_0003.exr.%ld.tmp", dir, (long)getpid());
  snprintf(other_name, sizeof other_name, "%s/.storm_0004.exr.%ld.tmp", dir, (long)child);
  snprintf(other_pid, sizeof other_pid, "%s/.storm_0003.exr.x%ld.tmp", dir, (long)child);
  touch(dead), touch(live), touch(other_name), touch(other_pid), touch(target);
  int removed = -1;
  sl_error err = {0};
  CHECK(sl_temp_remove_stale(target, &removed, &err) == SL_OK);
  CHECK(removed == 1);
  CHECK_MSG(!exists(dead), "the killed writer's temporary file is removed");
  CHECK_MSG(exists(live), "a live writer's is kept");
  CHECK_MSG(exists(other_name) && exists(other_pid) && exists(target), "other files are kept");
  /* a folder that does not exist has no stale files */
  char missing[320];
  snprintf(missing, sizeof missing, "%s/none/storm.exr", dir);
  CHECK(sl_temp_remove_stale(missing, &removed, &err) == SL_OK && removed == 0);
  unlink(live), unlink(other_name), unlink(other_pid), unlink(target);
  rmdir(dir);
  return sl_test_finish("test_tempfile");
}
