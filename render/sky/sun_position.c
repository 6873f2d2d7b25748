/* Solar position from a UTC date-time and a place.
 *
 * Meeus, Astronomical Algorithms, 2nd ed. (1998):
 *   ch. 7  Julian day;  ch. 25 low-accuracy solar coordinates (stated accuracy 0.01 deg);
 *   ch. 22 nutation in longitude (the four largest terms) and obliquity;
 *   ch. 12 apparent sidereal time;  ch. 13 horizontal coordinates;
 *   ch. 40 horizontal parallax of the sun (8.794" / R).
 * Refraction as in NREL's SPA (Reda & Andreas 2004, eq. 42, Bennett's formula scaled by pressure
 * and temperature), applied when the sun's upper limb is above the refracted horizon.
 * Accuracy against NREL SPA (+-0.0003 deg) is measured in tests/sky and docs/ACCURACY.md. */
#include <math.h>

#include "sl_sky.h"

static const double kPi = 3.14159265358979323846;
#define RAD (kPi / 180.0)

static double wrap360(double deg)
{
  double w = fmod(deg, 360.0);
  return w < 0.0 ? w + 360.0 : w;
}

void sl_solar_options_default(sl_solar_options *opt)
{
  opt->pressure_hpa = 1010.0;
  opt->temperature_c = 10.0;
  opt->delta_t_s = 69.2;
  opt->refraction = 1;
}

double sl_julian_day(const sl_utc *t)
{
  int y = t->year, m = t->month;
  if (m <= 2) y -= 1, m += 12;
  double a = floor(y / 100.0);
  double b = 2.0 - a + floor(a / 4.0);
  double day = t->day + (t->hour + (t->minute + t->second / 60.0) / 60.0) / 24.0;
  return floor(365.25 * (y + 4716)) + floor(30.6001 * (m + 1)) + day + b - 1524.5;
}

static int days_in_month(int year, int month)
{
  static const int days[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  int leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  return days[month - 1] + (month == 2 && leap);
}

int sl_solar_position_compute(const sl_utc *t, double latitude_deg, double longitude_deg,
                              const sl_solar_options *opt, sl_solar_position *out, sl_error *err)
{
  if (!t || !out) return sl_fail(err, SL_ERR_ARG, "sun: NULL argument");
  if (t->year < 1583 || t->year > 3000 || t->month < 1 || t->month > 12 || t->day < 1 ||
      t->day > days_in_month(t->year, t->month) || t->hour < 0 || t->hour > 23 || t->minute < 0 ||
      t->minute > 59 || !(t->second >= 0.0 && t->second < 61.0))
    return sl_fail(err, SL_ERR_ARG, "sun: invalid date-time %04d-%02d-%02dT%02d:%02d:%g", t->year,
                   t->month, t->day, t->hour, t->minute, t->second);
  if (!(latitude_deg >= -90.0 && latitude_deg <= 90.0))
    return sl_fail(err, SL_ERR_ARG, "sun: latitude %g outside [-90, 90]", latitude_deg);
  if (!(longitude_deg >= -180.0 && longitude_deg <= 360.0))
    return sl_fail(err, SL_ERR_ARG, "sun: longitude %g outside [-180, 360]", longitude_deg);
  sl_solar_options defaults;
  if (!opt) {
    sl_solar_options_default(&defaults);
    opt = &defaults;
  }

  double jd = sl_julian_day(t);
  double jde = jd + opt->delta_t_s / 86400.0;
  double T = (jde - 2451545.0) / 36525.0;

  /* ch. 25: geometric mean longitude, mean anomaly, eccentricity, equation of centre */
  double L0 = 280.46646 + T * (36000.76983 + T * 0.0003032);
  double M = 357.52911 + T * (35999.05029 - T * 0.0001537);
  double e = 0.016708634 - T * (0.000042037 + T * 0.0000001267);
  double C = (1.914602 - T * (0.004817 + T * 0.000014)) * sin(M * RAD) +
             (0.019993 - T * 0.000101) * sin(2.0 * M * RAD) + 0.000289 * sin(3.0 * M * RAD);
  double true_longitude = L0 + C;
  double nu = M + C;
  double radius_au = 1.000001018 * (1.0 - e * e) / (1.0 + e * cos(nu * RAD));

  /* ch. 22: nutation in longitude and obliquity (largest terms), mean obliquity (22.2) */
  double omega = 125.04452 - T * 1934.136261;
  double Ls = 280.4665 + 36000.7698 * T, Lm = 218.3165 + 481267.8813 * T;
  double dpsi = (-17.20 * sin(omega * RAD) - 1.32 * sin(2 * Ls * RAD) - 0.23 * sin(2 * Lm * RAD) +
                 0.21 * sin(2 * omega * RAD)) / 3600.0;
  double deps = (9.20 * cos(omega * RAD) + 0.57 * cos(2 * Ls * RAD) + 0.10 * cos(2 * Lm * RAD) -
                 0.09 * cos(2 * omega * RAD)) / 3600.0;
  double eps0 = 23.0 + 26.0 / 60.0 + (21.448 - T * (46.8150 + T * (0.00059 - T * 0.001813))) / 3600.0;
  double eps = eps0 + deps;

  /* apparent longitude: nutation plus aberration (-20.4898" / R) */
  double lambda = true_longitude + dpsi - 20.4898 / 3600.0 / radius_au;
  double alpha = wrap360(atan2(cos(eps * RAD) * sin(lambda * RAD), cos(lambda * RAD)) / RAD);
  double delta = asin(sin(eps * RAD) * sin(lambda * RAD)) / RAD;

  /* ch. 12: apparent sidereal time at Greenwich (UT) */
  double Tu = (jd - 2451545.0) / 36525.0;
  double theta0 = 280.46061837 + 360.98564736629 * (jd - 2451545.0) + Tu * Tu * (0.000387933 - Tu / 38710000.0);
  double theta = theta0 + dpsi * cos(eps * RAD);
  double H = wrap360(theta + longitude_deg - alpha);

  /* ch. 13: horizontal coordinates; azimuth measured from north, clockwise */
  double phi = latitude_deg * RAD;
  double sin_el = sin(phi) * sin(delta * RAD) + cos(phi) * cos(delta * RAD) * cos(H * RAD);
  if (sin_el > 1.0) sin_el = 1.0;
  if (sin_el < -1.0) sin_el = -1.0;
  double elevation = asin(sin_el) / RAD;
  double azimuth = wrap360(atan2(sin(H * RAD), cos(H * RAD) * sin(phi) - tan(delta * RAD) * cos(phi)) / RAD + 180.0);

  /* topocentric: parallax lowers the sun by (8.794" / R) cos(elevation) */
  elevation -= 8.794 / 3600.0 / radius_au * cos(elevation * RAD);

  double apparent = elevation;
  const double sun_radius = 0.26667, horizon_refraction = 0.5667;
  if (opt->refraction && elevation >= -(sun_radius + horizon_refraction)) {
    /* Reda & Andreas 2004, eq. 42 */
    apparent += opt->pressure_hpa / 1010.0 * 283.0 / (273.0 + opt->temperature_c) * 1.02 /
                (60.0 * tan((elevation + 10.3 / (elevation + 5.11)) * RAD));
  }

  out->elevation_deg = apparent;
  out->azimuth_deg = azimuth;
  out->zenith_deg = 90.0 - apparent;
  out->elevation_true_deg = elevation;
  out->declination_deg = delta;
  out->right_ascension_deg = alpha;
  out->hour_angle_deg = H;
  out->julian_day = jd;
  sl_sun_direction(apparent, azimuth, out->direction);
  out->night = !(apparent > 0.0);
  return SL_OK;
}
