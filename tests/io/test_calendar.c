/* Dates in the CF calendars (io/calendar.c) against outside facts: the Gregorian calendar against
 * the C library's timegm/gmtime over random offsets; the standard calendar's reform (the day after
 * 1582-10-04 is 1582-10-15, CF 4.4.1) and the proleptic one's continuity; the Julian calendar's
 * leap day every fourth year (73050 days from 1900-03-01 to 2100-03-01, one more than the
 * Gregorian count) and its 13-day lag in 1900-2099; noleap, all_leap and 360_day dates counted by
 * hand; offsets that go back undone; and the sun's Gregorian day for each model calendar. */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "sl_testing.h"
#include "storm_internal.h"

static unsigned long long rng = 88172645463325252ULL;
static double uniform(void)
{
  rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(rng >> 11) / 9007199254740992.0;
}

static int same(const int a[6], const int b[6]) { return memcmp(a, b, 6 * sizeof(int)) == 0; }

static void check_add(const char *cal_name, const int base[6], double seconds, const int want[6])
{
  int got[6] = {0};
  const int ok = sl_calendar_add_seconds(sl_calendar_named(cal_name), base, seconds, got);
  char what[200];
  snprintf(what, sizeof what, "%s: %04d-%02d-%02d %02d:%02d:%02d + %.0f s = %04d-%02d-%02d %02d:%02d:%02d (want %04d-%02d-%02d %02d:%02d:%02d)",
           cal_name, base[0], base[1], base[2], base[3], base[4], base[5], seconds, got[0], got[1], got[2], got[3],
           got[4], got[5], want[0], want[1], want[2], want[3], want[4], want[5]);
  CHECK_MSG(ok && same(got, want), what);
}

static void check_sun(const char *cal_name, const int date[6], const int want[6])
{
  int got[6];
  sl_calendar_sun_date(sl_calendar_named(cal_name), date, got);
  char what[200];
  snprintf(what, sizeof what, "%s: the sun at %04d-%02d-%02d %02d:%02d stands as on Gregorian %04d-%02d-%02d %02d:%02d (want %04d-%02d-%02d)",
           cal_name, date[0], date[1], date[2], date[3], date[4], got[0], got[1], got[2], got[3], got[4], want[0],
           want[1], want[2]);
  CHECK_MSG(same(got, want), what);
}

int main(void)
{
  const double day = 86400.0;
  /* Gregorian against the C library. */
  int worst = 0;
  for (int k = 0; k < 20000; ++k) {
    const int base[6] = {1601 + (int)(uniform() * 700), 1 + (int)(uniform() * 12), 1 + (int)(uniform() * 28),
                         (int)(uniform() * 24), (int)(uniform() * 60), (int)(uniform() * 60)};
    const double seconds = (double)(long long)((uniform() - 0.5) * 2e10);
    struct tm tm = {.tm_year = base[0] - 1900, .tm_mon = base[1] - 1, .tm_mday = base[2], .tm_hour = base[3],
                    .tm_min = base[4], .tm_sec = base[5]};
    const time_t at = timegm(&tm) + (time_t)seconds;
    struct tm u;
    gmtime_r(&at, &u);
    const int want[6] = {u.tm_year + 1900, u.tm_mon + 1, u.tm_mday, u.tm_hour, u.tm_min, u.tm_sec};
    for (int c = 0; c < 2; ++c) {
      int got[6];
      const int ok = sl_calendar_add_seconds(c ? SL_CAL_PROLEPTIC_GREGORIAN : SL_CAL_STANDARD, base, seconds, got);
      worst += !ok || (want[0] > 1582 && !same(got, want));
    }
  }
  char what[120];
  snprintf(what, sizeof what, "standard and proleptic Gregorian agree with timegm/gmtime: %d of 40000 differ", worst);
  CHECK_MSG(worst == 0, what);

  /* The reform, CF 4.4.1's own example, and the proleptic calendar going straight on. */
  check_add("standard", (int[6]){1582, 10, 4, 0, 0, 0}, day, (int[6]){1582, 10, 15, 0, 0, 0});
  check_add("gregorian", (int[6]){1582, 10, 15, 0, 0, 0}, -day, (int[6]){1582, 10, 4, 0, 0, 0});
  check_add("proleptic_gregorian", (int[6]){1582, 10, 4, 0, 0, 0}, day, (int[6]){1582, 10, 5, 0, 0, 0});
  /* "days since 0001-01-01" in the standard calendar counts Julian years up to the reform:
   * 1582-10-15 is day 577737 (the Julian count of 1582-10-05: 1581 * 365 + 395 leap days
   * + 277 days into 1582). */
  check_add("standard", (int[6]){1, 1, 1, 0, 0, 0}, 577737.0 * day, (int[6]){1582, 10, 15, 0, 0, 0});
  /* Julian: a leap day in every fourth year, 2100 too. */
  check_add("julian", (int[6]){1900, 3, 1, 0, 0, 0}, 73050.0 * day, (int[6]){2100, 3, 1, 0, 0, 0});
  check_add("proleptic_gregorian", (int[6]){1900, 3, 1, 0, 0, 0}, 73050.0 * day, (int[6]){2100, 3, 2, 0, 0, 0});
  check_add("julian", (int[6]){1900, 2, 28, 0, 0, 0}, day, (int[6]){1900, 2, 29, 0, 0, 0});
  /* The review's cases: 400 days since 2000-01-01. */
  check_add("noleap", (int[6]){2000, 1, 1, 0, 0, 0}, 400.0 * day, (int[6]){2001, 2, 5, 0, 0, 0});
  check_add("365_day", (int[6]){2004, 2, 28, 0, 0, 0}, 365.0 * day, (int[6]){2005, 2, 28, 0, 0, 0});
  check_add("360_day", (int[6]){2000, 1, 1, 0, 0, 0}, 400.0 * day, (int[6]){2001, 2, 11, 0, 0, 0});
  check_add("360_day", (int[6]){2000, 2, 30, 6, 0, 0}, 360.0 * day, (int[6]){2001, 2, 30, 6, 0, 0});
  check_add("all_leap", (int[6]){2000, 1, 1, 0, 0, 0}, 400.0 * day, (int[6]){2001, 2, 4, 0, 0, 0});
  check_add("366_day", (int[6]){2001, 3, 1, 0, 0, 0}, -day, (int[6]){2001, 2, 29, 0, 0, 0});
  check_add("noleap", (int[6]){2001, 3, 1, 0, 0, 0}, -1.0, (int[6]){2001, 2, 28, 23, 59, 59});
  check_add("standard", (int[6]){2024, 6, 15, 0, 0, 0}, 22.0 * 3600.0, (int[6]){2024, 6, 15, 22, 0, 0});
  /* Dates a calendar does not have. */
  int out[6];
  CHECK_MSG(!sl_calendar_add_seconds(SL_CAL_NOLEAP, (int[6]){2004, 2, 29, 0, 0, 0}, 0.0, out), "noleap has no Feb 29");
  CHECK_MSG(!sl_calendar_add_seconds(SL_CAL_STANDARD, (int[6]){2001, 2, 30, 0, 0, 0}, 0.0, out), "standard has no Feb 30");
  CHECK_MSG(!sl_calendar_add_seconds(SL_CAL_STANDARD, (int[6]){1582, 10, 10, 0, 0, 0}, 0.0, out),
            "standard has no 1582-10-10");
  CHECK_MSG(sl_calendar_named("mars_sol") == SL_CAL_UNKNOWN && sl_calendar_named("none") == SL_CAL_UNKNOWN,
            "unknown calendars are not taken for any");
  CHECK_MSG(!sl_calendar_add_seconds(SL_CAL_NOLEAP, (int[6]){2000, 1, 1, 0, 0, 0}, 1e13, out), "absurd offsets refused");

  /* Offsets undone: there and back in every calendar. */
  const char *cals[] = {"standard", "proleptic_gregorian", "julian", "noleap", "all_leap", "360_day"};
  int unequal = 0;
  for (int k = 0; k < 6000; ++k) {
    const sl_calendar cal = sl_calendar_named(cals[k % 6]);
    int base[6] = {1 + (int)(uniform() * 4000), 1 + (int)(uniform() * 12), 1 + (int)(uniform() * 28),
                   (int)(uniform() * 24), (int)(uniform() * 60), (int)(uniform() * 60)};
    if (cal == SL_CAL_STANDARD && base[0] == 1582) base[0] = 1583;
    const double seconds = (double)(long long)((uniform() - 0.3) * 3e10);
    int there[6], back[6];
    if (!sl_calendar_add_seconds(cal, base, seconds, there)) continue;
    unequal += !sl_calendar_add_seconds(cal, there, -seconds, back) || !same(back, base);
  }
  snprintf(what, sizeof what, "an offset added and taken away gives the date back: %d of 6000 differ", unequal);
  CHECK_MSG(unequal == 0, what);

  /* The sun's day. The Julian calendar lags the Gregorian by 13 days in 1900-2099. */
  check_sun("julian", (int[6]){2000, 1, 1, 12, 0, 0}, (int[6]){2000, 1, 14, 12, 0, 0});
  check_sun("standard", (int[6]){2000, 1, 1, 12, 0, 0}, (int[6]){2000, 1, 1, 12, 0, 0});
  /* noleap in a common year is the Gregorian date; in a leap year its day 182 (Jul 2) is the
   * 182.5th Gregorian day: Jul 1, the clock kept. */
  check_sun("noleap", (int[6]){2001, 7, 2, 12, 34, 56}, (int[6]){2001, 7, 2, 12, 34, 56});
  check_sun("noleap", (int[6]){2004, 7, 2, 12, 34, 56}, (int[6]){2004, 7, 1, 12, 34, 56});
  /* 360_day: Jun 30 is day 179, 181.5 of 365: Jul 1; Dec 30 is day 359, 363.99: Dec 30; Feb 30
   * is day 59, 59.8: Mar 1. */
  check_sun("360_day", (int[6]){2001, 6, 30, 6, 0, 0}, (int[6]){2001, 7, 1, 6, 0, 0});
  check_sun("360_day", (int[6]){2001, 12, 30, 6, 0, 0}, (int[6]){2001, 12, 30, 6, 0, 0});
  check_sun("360_day", (int[6]){2001, 2, 30, 6, 0, 0}, (int[6]){2001, 3, 1, 6, 0, 0});
  /* all_leap in a common year: Feb 29 (day 59) is 59 * 365 / 366 = 58.8: Feb 28. */
  check_sun("all_leap", (int[6]){2001, 2, 29, 18, 0, 0}, (int[6]){2001, 2, 28, 18, 0, 0});
  return sl_test_finish("test_calendar");
}
