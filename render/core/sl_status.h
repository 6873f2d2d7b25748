/* Status codes and error messages shared by every Stormlight C module.
 * Functions return SL_OK or an error code and fill an sl_error with one line that names the
 * thing (file, field, option) and the problem. Nothing below app/ prints or exits. */
#ifndef SL_STATUS_H
#define SL_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

enum sl_status {
  SL_OK = 0,
  SL_ERR_IO = 1,      /* file cannot be opened, read or written */
  SL_ERR_FORMAT = 2,  /* file is not what it claims: not NetCDF, truncated, wrong shape */
  SL_ERR_DATA = 3,    /* values are wrong: NaN, Inf, absurd sizes */
  SL_ERR_ARG = 4,     /* a caller passed an invalid argument */
  SL_ERR_NOMEM = 5
};

typedef struct sl_error {
  int code;
  char message[512];
} sl_error;

/* Records the first failure only: a later, more generic message never hides the root cause. */
int sl_fail(sl_error *err, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
void sl_error_clear(sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
