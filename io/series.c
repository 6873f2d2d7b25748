/* Storm time series over files: glob expansion, per-file times, time order. */
#include "sl_series.h"

#include <glob.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sl_storm.h"

static int add_path(sl_series *s, const char *p, int *cap, sl_error *err)
{
  if (s->npaths == *cap) {
    *cap = *cap ? 2 * *cap : 16;
    char **grown = realloc(s->paths, (size_t)*cap * sizeof *grown);
    if (!grown) return sl_fail(err, SL_ERR_NOMEM, "series: out of memory");
    s->paths = grown;
  }
  if (!(s->paths[s->npaths] = strdup(p))) return sl_fail(err, SL_ERR_NOMEM, "series: out of memory");
  s->npaths++;
  return SL_OK;
}

static int by_time(const void *a, const void *b)
{
  const sl_series_frame *x = a, *y = b;
  const int c = strcmp(x->time, y->time);
  return c ? c : (x->path != y->path ? (x->path < y->path ? -1 : 1) : x->time_index - y->time_index);
}

static int by_elapsed(const void *a, const void *b)
{
  const sl_series_frame *x = a, *y = b;
  return x->elapsed_s < y->elapsed_s ? -1 : x->elapsed_s > y->elapsed_s ? 1 : 0;
}

int sl_series_open(const char *const *paths, int npaths, sl_series *s, sl_error *err)
{
  memset(s, 0, sizeof *s);
  int cap = 0, rc = SL_OK;
  for (int i = 0; i < npaths && !rc; ++i) {
    struct stat st;
    if (strpbrk(paths[i], "*?[") && stat(paths[i], &st) != 0) {
      glob_t g;
      if (glob(paths[i], 0, NULL, &g) != 0 || g.gl_pathc == 0) {
        rc = sl_fail(err, SL_ERR_IO, "%s: no file matches this pattern", paths[i]);
      } else {
        for (size_t k = 0; k < g.gl_pathc && !rc; ++k) rc = add_path(s, g.gl_pathv[k], &cap, err);
      }
      globfree(&g);
    } else {
      rc = add_path(s, paths[i], &cap, err);
    }
  }
  if (!rc && s->npaths == 0) rc = sl_fail(err, SL_ERR_ARG, "series: no files");
  sl_storm_info *info = rc ? NULL : malloc(sizeof *info);
  if (!rc && !info) rc = sl_fail(err, SL_ERR_NOMEM, "series: out of memory");
  int fcap = 0;
  s->has_times = 1;
  s->has_elapsed = 1;
  for (int i = 0; i < s->npaths && !rc; ++i) {
    if ((rc = sl_storm_read_info(s->paths[i], info, err))) break;
    if (s->count + info->ntimes > fcap) {
      fcap = 2 * (s->count + info->ntimes);
      sl_series_frame *grown = realloc(s->frames, (size_t)fcap * sizeof *grown);
      if (!grown) {
        rc = sl_fail(err, SL_ERR_NOMEM, "series: out of memory");
        break;
      }
      s->frames = grown;
    }
    for (int t = 0; t < info->ntimes; ++t) {
      sl_series_frame *f = &s->frames[s->count++];
      f->path = s->paths[i];
      f->time_index = t;
      snprintf(f->time, sizeof f->time, "%s", info->has_times ? info->times[t] : "");
      f->elapsed_s = info->has_elapsed ? info->elapsed_s[t] : 0.0;
    }
    if (!info->has_times) s->has_times = 0;
    if (!info->has_elapsed) s->has_elapsed = 0;
  }
  free(info);
  if (!rc && s->has_times) {
    qsort(s->frames, (size_t)s->count, sizeof *s->frames, by_time);
    for (int i = 1; i < s->count && !rc; ++i)
      if (strcmp(s->frames[i].time, s->frames[i - 1].time) == 0)
        rc = sl_fail(err, SL_ERR_DATA, "%s: time %s appears twice (also in %s)", s->frames[i].path,
                     s->frames[i].time, s->frames[i - 1].path);
  }
  if (s->has_times) s->has_elapsed = 0;
  if (!rc && s->has_elapsed) {
    /* qsort is not stable: equal seconds keep no order, so they are refused like equal dates. */
    qsort(s->frames, (size_t)s->count, sizeof *s->frames, by_elapsed);
    for (int i = 1; i < s->count && !rc; ++i)
      if (s->frames[i].elapsed_s == s->frames[i - 1].elapsed_s)
        rc = sl_fail(err, SL_ERR_DATA, "%s: time %g s appears twice (also in %s)", s->frames[i].path,
                     s->frames[i].elapsed_s, s->frames[i - 1].path);
  }
  if (rc) sl_series_free(s);
  return rc;
}

void sl_series_free(sl_series *s)
{
  for (int i = 0; i < s->npaths; ++i) free(s->paths[i]);
  free(s->paths);
  free(s->frames);
  memset(s, 0, sizeof *s);
}
