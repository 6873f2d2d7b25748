/* Seeded synthetic storms written as WRF-style NetCDF, so that synthetic and real storms travel
 * the same reader path. */
#ifndef SL_SYNTH_H
#define SL_SYNTH_H

#include <stdint.h>

#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sl_synth_kind {
  SL_SYNTH_CUMULONIMBUS = 0, /* rain shaft below cloud base, mixed-phase tower, ice/snow anvil */
  SL_SYNTH_CIRRUS = 1,       /* thin streaky ice deck near 10 km */
  SL_SYNTH_STRATOCUMULUS = 2, /* flat-topped cellular liquid deck near 1 km */
  SL_SYNTH_CUMULUS = 3        /* small thin fair-weather cumulus, optical depth ~1-10 (validation) */
} sl_synth_kind;

typedef struct sl_synth_options {
  sl_synth_kind kind;
  uint64_t seed;
  int nx, ny, nz, ntimes;
  double dx;                 /* m; dy = dx */
  double top;                /* model top, m */
  double center_lat, center_lon;
  char start_time[20];       /* "YYYY-MM-DD_hh:mm:ss" (UTC) */
  int minutes_per_step;
} sl_synth_options;

/* Returns -1 for an unknown name; names: cumulonimbus, cirrus, stratocumulus, cumulus. */
int sl_synth_kind_from_name(const char *name);
const char *sl_synth_kind_name(sl_synth_kind kind);
void sl_synth_defaults(sl_synth_kind kind, sl_synth_options *opt);
int sl_synth_write(const char *path, const sl_synth_options *opt, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
