/* Dates in the calendars of the CF conventions (section 4.4.1): a time coordinate's "<unit> since
 * <date>" counts in the calendar its `calendar` attribute names, and climate models run in
 * calendars without leap days or with 30-day months. Each calendar numbers its days from its own
 * 0001-01-01; the mixed Julian/Gregorian "standard" calendar joins the two at 1582-10-15. */
#include <math.h>
#include <stdio.h>
#include <strings.h>

#include "storm_internal.h"

static const int month_start[2][13] = {{0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334, 365},
                                       {0, 31, 60, 91, 121, 152, 182, 213, 244, 274, 305, 335, 366}};

sl_calendar sl_calendar_named(const char *name)
{
  if (!name[0] || !strcasecmp(name, "standard") || !strcasecmp(name, "gregorian")) return SL_CAL_STANDARD;
  if (!strcasecmp(name, "proleptic_gregorian")) return SL_CAL_PROLEPTIC_GREGORIAN;
  if (!strcasecmp(name, "julian")) return SL_CAL_JULIAN;
  if (!strcasecmp(name, "noleap") || !strcasecmp(name, "365_day")) return SL_CAL_NOLEAP;
  if (!strcasecmp(name, "all_leap") || !strcasecmp(name, "366_day")) return SL_CAL_ALL_LEAP;
  if (!strcasecmp(name, "360_day")) return SL_CAL_360_DAY;
  return SL_CAL_UNKNOWN;
}

static int is_leap(sl_calendar cal, long long y)
{
  switch (cal) {
  case SL_CAL_JULIAN: return y % 4 == 0;
  case SL_CAL_NOLEAP: return 0;
  case SL_CAL_ALL_LEAP: return 1;
  default: return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  }
}

/* Days from 0001-01-01 to y-m-d in one pure calendar (Gregorian, Julian, noleap, all_leap or
 * 360_day), y >= 1. */
static long long day_count(sl_calendar cal, long long y, int m, int d)
{
  const long long p = y - 1;
  if (cal == SL_CAL_360_DAY) return p * 360 + (m - 1) * 30 + (d - 1);
  long long days = p * 365;
  if (cal == SL_CAL_ALL_LEAP) days += p;
  if (cal == SL_CAL_JULIAN) days += p / 4;
  if (cal == SL_CAL_PROLEPTIC_GREGORIAN) days += p / 4 - p / 100 + p / 400;
  return days + month_start[is_leap(cal, y)][m - 1] + (d - 1);
}

/* The date of day n (from 0001-01-01, n >= 0) in one pure calendar. */
static void date_of_count(sl_calendar cal, long long n, long long *y, int *m, int *d)
{
  const double year = cal == SL_CAL_360_DAY ? 360.0 : cal == SL_CAL_NOLEAP ? 365.0 : cal == SL_CAL_ALL_LEAP ? 366.0 : 365.25;
  long long yy = 1 + (long long)(n / year);
  while (yy > 1 && day_count(cal, yy, 1, 1) > n) --yy;
  while (day_count(cal, yy + 1, 1, 1) <= n) ++yy;
  int mm = 1;
  while (mm < 12 && day_count(cal, yy, mm + 1, 1) <= n) ++mm;
  *y = yy, *m = mm, *d = (int)(n - day_count(cal, yy, mm, 1)) + 1;
}

/* The standard calendar is Julian before 1582-10-15 and Gregorian from then on, the day after
 * 1582-10-04 (Julian) being 1582-10-15: days are counted on the Gregorian scale, Julian dates
 * shifted to meet it. */
static long long julian_shift(void) { return day_count(SL_CAL_PROLEPTIC_GREGORIAN, 1582, 10, 15) - (day_count(SL_CAL_JULIAN, 1582, 10, 4) + 1); }

static int before_reform(long long y, int m, int d) { return y < 1582 || (y == 1582 && (m < 10 || (m == 10 && d < 15))); }

static long long days_of(sl_calendar cal, long long y, int m, int d)
{
  if (cal != SL_CAL_STANDARD) return day_count(cal, y, m, d);
  return before_reform(y, m, d) ? day_count(SL_CAL_JULIAN, y, m, d) + julian_shift()
                                : day_count(SL_CAL_PROLEPTIC_GREGORIAN, y, m, d);
}

static void date_of(sl_calendar cal, long long n, long long *y, int *m, int *d)
{
  if (cal != SL_CAL_STANDARD) {
    date_of_count(cal, n, y, m, d);
  } else if (n >= day_count(SL_CAL_PROLEPTIC_GREGORIAN, 1582, 10, 15)) {
    date_of_count(SL_CAL_PROLEPTIC_GREGORIAN, n, y, m, d);
  } else {
    date_of_count(SL_CAL_JULIAN, n - julian_shift(), y, m, d);
  }
}

int sl_calendar_valid(sl_calendar cal, const int date[6])
{
  if (cal == SL_CAL_UNKNOWN || date[0] < 1 || date[0] > 9999 || date[1] < 1 || date[1] > 12 || date[2] < 1) return 0;
  const int leap = is_leap(cal == SL_CAL_STANDARD ? (date[0] < 1582 ? SL_CAL_JULIAN : SL_CAL_PROLEPTIC_GREGORIAN) : cal, date[0]);
  const int month_days = cal == SL_CAL_360_DAY ? 30 : month_start[leap][date[1]] - month_start[leap][date[1] - 1];
  if (date[2] > month_days) return 0;
  if (cal == SL_CAL_STANDARD && date[0] == 1582 && date[1] == 10 && date[2] > 4 && date[2] < 15) return 0;
  /* Clock fields as a model may write them (24:00, a leap second): the arithmetic carries them. */
  return date[3] >= 0 && date[3] <= 24 && date[4] >= 0 && date[4] <= 60 && date[5] >= 0 && date[5] <= 61;
}

void sl_calendar_format(const int date[6], char out[24])
{
  /* Valid dates' fields fit; the modulo tells the compiler so. */
  snprintf(out, 24, "%04u-%02u-%02u_%02u:%02u:%02u", (unsigned)date[0] % 10000u, (unsigned)date[1] % 100u,
           (unsigned)date[2] % 100u, (unsigned)date[3] % 100u, (unsigned)date[4] % 100u, (unsigned)date[5] % 100u);
}

int sl_calendar_add_seconds(sl_calendar cal, const int base[6], double seconds, int out[6])
{
  /* About +-30 000 years: far beyond any simulation, and exact in a double to the second. */
  if (!sl_calendar_valid(cal, base) || !(fabs(seconds) < 1e12)) return 0;
  const double total = base[3] * 3600.0 + base[4] * 60.0 + base[5] + seconds;
  long long days = (long long)floor(total / 86400.0);
  long long rest = llround(total - 86400.0 * (double)days);
  if (rest >= 86400) rest -= 86400, ++days;
  if (rest < 0) rest += 86400, --days;
  const long long n = days_of(cal, base[0], base[1], base[2]) + days;
  if (n < 0) return 0;
  long long y;
  date_of(cal, n, &y, &out[1], &out[2]);
  if (y > 9999) return 0;
  out[0] = (int)y, out[3] = (int)(rest / 3600), out[4] = (int)(rest / 60 % 60), out[5] = (int)(rest % 60);
  return 1;
}

void sl_calendar_sun_date(sl_calendar cal, const int date[6], int out[6])
{
  for (int i = 0; i < 6; ++i) out[i] = date[i];
  if (cal == SL_CAL_STANDARD || cal == SL_CAL_PROLEPTIC_GREGORIAN || cal == SL_CAL_UNKNOWN) return;
  long long y;
  if (cal == SL_CAL_JULIAN) {
    /* A real calendar: the same day, named as the Gregorian calendar names it. */
    date_of_count(SL_CAL_PROLEPTIC_GREGORIAN, day_count(SL_CAL_JULIAN, date[0], date[1], date[2]) + julian_shift(), &y,
                  &out[1], &out[2]);
    out[0] = (int)y;
    return;
  }
  /* A model calendar: its year is the earth's orbit, so the sun's declination goes with the
   * fraction of the year; the clock time is kept (it sets the sun's hour angle). */
  const long long year_start = day_count(cal, date[0], 1, 1);
  const long long year_days = day_count(cal, (long long)date[0] + 1, 1, 1) - year_start;
  const long long g_start = day_count(SL_CAL_PROLEPTIC_GREGORIAN, date[0], 1, 1);
  const long long g_days = day_count(SL_CAL_PROLEPTIC_GREGORIAN, (long long)date[0] + 1, 1, 1) - g_start;
  const long long day = day_count(cal, date[0], date[1], date[2]) - year_start;
  date_of_count(SL_CAL_PROLEPTIC_GREGORIAN, g_start + day * g_days / year_days, &y, &out[1], &out[2]);
  out[0] = (int)y;
}
