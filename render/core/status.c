#include "sl_status.h"

#include <stdarg.h>
#include <stdio.h>

int sl_fail(sl_error *err, int code, const char *fmt, ...)
{
  if (err && err->code == SL_OK) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    err->code = code;
  }
  return code;
}

void sl_error_clear(sl_error *err)
{
  if (err) {
    err->code = SL_OK;
    err->message[0] = '\0';
  }
}
