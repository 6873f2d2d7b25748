/* A time series of storm files: several times per file, one file per time, or both. A list of
 * paths (glob patterns are expanded) becomes (file, time index) pairs in time order. */
#ifndef SL_SERIES_H
#define SL_SERIES_H

#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sl_series_frame {
  const char *path;     /* points into the series' own copy of the path */
  int time_index;       /* within that file */
  char time[24];        /* "YYYY-MM-DD_hh:mm:ss"; "" when the file has no times */
  double elapsed_s;     /* seconds since the run's start where the files count so (CM1), else 0 */
} sl_series_frame;

typedef struct sl_series {
  int count;               /* frames */
  sl_series_frame *frames; /* in time order: by date, else by elapsed seconds (CM1), else in
                              argument order, then index */
  int npaths;
  char **paths;            /* the files, after glob expansion */
  int has_times;           /* every frame has a time */
  int has_elapsed;         /* no dates, but every frame has seconds since the start */
} sl_series;

/* Reads each file's times (nothing else) and orders the frames. A pattern with * ? or [ that is
 * not an existing file is expanded (glob(3), sorted); one that matches nothing is an error. Two
 * frames with the same time are an error naming both files. */
int sl_series_open(const char *const *paths, int npaths, sl_series *series, sl_error *err);
void sl_series_free(sl_series *series);

#ifdef __cplusplus
}
#endif
#endif
