/* UTC date-times (sl_utc): ISO 8601 text into a date-time, and a date-time moved by a number of
 * seconds, both through the C library's proleptic Gregorian UTC (timegm, gmtime_r: no time-zone
 * rules, no leap seconds), which is what the solar position takes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "sl_sky.h"

/* t with its minutes shifted by minutes and whole seconds added, normalised into a calendar date;
 * 0 when the C library cannot represent it. */
static int normalise(sl_utc *t, long long minutes, long long seconds)
{
  struct tm tm = {0};
  tm.tm_year = t->year - 1900, tm.tm_mon = t->month - 1, tm.tm_mday = t->day;
  tm.tm_hour = t->hour, tm.tm_min = t->minute;
  const time_t base = timegm(&tm);
  if (base == (time_t)-1) return 0;
  const time_t when = base + (time_t)(minutes * 60 + seconds);
  struct tm utc;
  if (!gmtime_r(&when, &utc)) return 0;
  t->year = utc.tm_year + 1900, t->month = utc.tm_mon + 1, t->day = utc.tm_mday;
  t->hour = utc.tm_hour, t->minute = utc.tm_min;
  t->second = utc.tm_sec;
  return 1;
}

int sl_utc_parse_iso8601(const char *text, sl_utc *out, sl_error *err)
{
  int y, mo, d, h, mi, used = 0;
  char sep;
  if (sscanf(text, "%4d-%2d-%2d%c%2d:%2d%n", &y, &mo, &d, &sep, &h, &mi, &used) != 6 || (sep != 'T' && sep != ' '))
    return sl_fail(err, SL_ERR_ARG, "'%s' is not an ISO 8601 date-time like 2024-06-21T05:30:00Z", text);
  const char *p = text + used;
  double second = 0.0;
  if (*p == ':') {
    char *end = NULL;
    second = strtod(p + 1, &end);
    if (end == p + 1 || !(second >= 0.0 && second < 61.0)) return sl_fail(err, SL_ERR_ARG, "'%s': bad seconds", text);
    p = end;
  }
  int offset_min = 0;
  if (*p == 'Z' && p[1] == '\0') {
    p++;
  } else if ((*p == '+' || *p == '-') && p[1]) {
    int oh = 0, om = 0, n = 0;
    if (sscanf(p + 1, "%2d:%2d%n", &oh, &om, &n) != 2 || p[1 + n] != '\0' || oh > 23 || om > 59)
      return sl_fail(err, SL_ERR_ARG, "'%s': bad time zone offset (use Z, +hh:mm or -hh:mm)", text);
    offset_min = (*p == '-' ? -1 : 1) * (oh * 60 + om);
    p += 1 + n;
  }
  if (*p != '\0') return sl_fail(err, SL_ERR_ARG, "'%s': unexpected '%s'", text, p);
  static const int days[12] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const int leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  if (mo < 1 || mo > 12 || d < 1 || d > days[mo - 1] || (mo == 2 && d == 29 && !leap) || h < 0 || h > 23 || mi < 0 ||
      mi > 59)
    return sl_fail(err, SL_ERR_ARG, "'%s': field out of range", text);
  /* Local time minus the offset. */
  sl_utc t = {y, mo, d, h, mi, 0.0};
  if (!normalise(&t, -offset_min, 0)) return sl_fail(err, SL_ERR_ARG, "'%s': date out of range", text);
  t.second = second;
  *out = t;
  return SL_OK;
}

int sl_utc_add_seconds(sl_utc *t, double seconds, sl_error *err)
{
  if (!isfinite(seconds)) return sl_fail(err, SL_ERR_ARG, "a time shift of %g seconds", seconds);
  const double total = t->second + seconds, whole = floor(total);
  sl_utc moved = *t;
  if (!normalise(&moved, 0, (long long)whole)) return sl_fail(err, SL_ERR_ARG, "a date out of range");
  moved.second += total - whole;
  *t = moved;
  return SL_OK;
}
