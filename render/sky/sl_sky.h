/* Sky, sun and aerial perspective (Riley et al. 2004, sections 4.1 and 4.2.4).
 *
 * Plan once, use many: sl_atmosphere_init() fixes the wavelengths, the sea-level Rayleigh
 * scattering coefficients, the scale height, the top-of-atmosphere sun irradiance and the earth
 * model; then the query functions below are cheap and allocation-free. The per-sample formulas
 * they use live in sl_sky_sample.h (plain-C subset that can compile as GLSL).
 *
 * World frame: east-north-up metres. With the flat ground (ground_radius 0, the paper's) z is the
 * height above sea level; with the round ground a point's height is its distance above the sphere
 * (sl_sky_altitude) and directions are measured against the vertical there. Directions are unit
 * vectors.
 * Radiances are per unit top-of-atmosphere irradiance unless sun_irradiance says otherwise.
 * Night (the sun's centre at or below the horizon) gives zero sun and zero sky, and a flag. */
#ifndef SL_SKY_H
#define SL_SKY_H

#include <math.h>

#include "sl_camera.h"
#include "sl_sky_sample.h"
#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SL_SKY_MAX_WAVELENGTHS 32

/* The paper's three channels (Riley Table 2: red, green, blue) and the spectral set: 16
 * wavelengths evenly spaced from 380 to 720 nm. */
#define SL_SKY_RGB_COUNT 3
#define SL_SKY_SPECTRAL_COUNT 16
extern const double sl_sky_rgb_wavelengths_nm[SL_SKY_RGB_COUNT];
void sl_sky_spectral_wavelengths(double out_nm[SL_SKY_SPECTRAL_COUNT]);

typedef enum sl_earth_model {
  SL_EARTH_FLAT = 0,  /* the paper: air mass 1 / cos(zenith) for the sunlight (eq. 12) */
  SL_EARTH_ROUND = 1  /* spherical earth: Chapman-function air mass for the sunlight */
} sl_earth_model;

typedef enum sl_rayleigh_source {
  /* Bodhaine et al. 1999 / Bates 1984: standard air (288.15 K, 1013.25 hPa, 360 ppm CO2),
   * Peck & Reeder 1972 refractive index, King factor. The default. */
  SL_RAYLEIGH_BODHAINE1999 = 0,
  /* Riley Table 3 (5.8e-6, 1.35e-5, 3.31e-5 m^-1 at 680, 550, 440 nm), interpolated in
   * log(beta) against log(lambda) and extrapolated with lambda^-4 outside 440-680 nm. */
  SL_RAYLEIGH_RILEY2004 = 1
} sl_rayleigh_source;

typedef struct sl_atmosphere {
  int count;                                       /* wavelengths in use */
  double wavelength_nm[SL_SKY_MAX_WAVELENGTHS];
  double beta_sea_level[SL_SKY_MAX_WAVELENGTHS];   /* Rayleigh scattering = extinction, m^-1 */
  double sun_irradiance[SL_SKY_MAX_WAVELENGTHS];   /* top of atmosphere; 1 by default */
  double scale_height;                             /* m; Riley eq. 9: 8000 (gamma = 1/8000) */
  double earth_radius;                             /* m; used by SL_EARTH_ROUND */
  /* Where eye rays meet the ground. 0 (the default): the plane z = 0. R > 0: the sphere of radius
   * R centred at (0, 0, -R), which touches that plane at the world origin: the earth as
   * `--curvature drop` places the storm (io: sl_curvature_drop), so distant ground and cloud
   * fall below the true horizon. The air keeps the exponential profile along each ray, in the
   * eye's own vertical (docs/GEOREFERENCING.md, "Earth curvature"). */
  double ground_radius;
  sl_earth_model earth;
  sl_rayleigh_source rayleigh;
} sl_atmosphere;

/* Fills atm for the given wavelengths (380..1000 nm, at most SL_SKY_MAX_WAVELENGTHS), earth
 * model, Rayleigh source, scale height 8000 m, earth radius 6 371 000 m, sun irradiance 1, the
 * flat ground (ground_radius 0).
 * The fields may be changed afterwards (e.g. sun_irradiance, scale_height). */
int sl_atmosphere_init(sl_atmosphere *atm, const double *wavelength_nm, int count,
                       sl_earth_model earth, sl_rayleigh_source rayleigh, sl_error *err);

/* Height of world point p above a round ground of radius R > 0 centred at (0, 0, -R), with no
 * branch (loops over samples vectorise): r - R without cancellation, (r^2 - R^2) / (r + R) with
 * r^2 - R^2 = x^2 + y^2 + z (z + 2R). */
static inline double sl_sky_altitude_round(double R, const double p[3])
{
  const double r = sqrt(p[0] * p[0] + p[1] * p[1] + (p[2] + R) * (p[2] + R));
  return (p[0] * p[0] + p[1] * p[1] + p[2] * (p[2] + 2.0 * R)) / (r + R);
}

/* Height of world point p above the ground (p[2] for the flat ground, |p - centre| - R for the
 * round one) and, when up is not NULL, the unit local vertical there. Inline: the volume's eye
 * passes ask it at every sample (the sunlight there), in loops that vectorise. */
static inline double sl_sky_altitude(const sl_atmosphere *atm, const double p[3], double up[3])
{
  const double R = atm->ground_radius;
  if (!(R > 0.0)) {
    if (up) up[0] = 0.0, up[1] = 0.0, up[2] = 1.0;
    return p[2];
  }
  const double c[3] = {p[0], p[1], p[2] + R}; /* from the sphere's centre */
  const double r = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  if (up) {
    if (r > 0.0) up[0] = c[0] / r, up[1] = c[1] / r, up[2] = c[2] / r;
    else up[0] = 0.0, up[1] = 0.0, up[2] = 1.0;
  }
  return sl_sky_altitude_round(R, p);
}

/* Rayleigh volume scattering coefficient of standard air at sea level (m^-1), Bodhaine et al.
 * 1999 eqs. (number density 2.546899e25 m^-3 at 288.15 K and 1013.25 hPa). */
double sl_rayleigh_beta_standard_air(double wavelength_nm);
/* The same, per molecule (m^2). */
double sl_rayleigh_cross_section(double wavelength_nm);

/* Air mass of the path from height z to the sun at the given cos(zenith): 1/cos for the flat
 * earth (Riley eq. 12), the Chapman function Ch(x, chi) with x = (R + z)/H for the round one
 * (computed by adaptive Gauss-Kronrod quadrature to 1e-12). Infinity at night (cos <= 0). */
double sl_sky_airmass(const sl_atmosphere *atm, double z, double cos_zenith);
/* Ch(x, chi) for 0 <= chi <= 90 degrees, x in scale heights (>= 1). */
double sl_chapman(double x, double cos_zenith);

/* Riley eq. 11: transparency between points a and b for every wavelength. */
int sl_sky_transparency(const sl_atmosphere *atm, const double a[3], const double b[3],
                        double *transparency, sl_error *err);

/* Riley eq. 12: direct sunlight (irradiance on a surface facing the sun) reaching point p, for
 * every wavelength, with the atmosphere's earth model. *night is set when the sun is at or below
 * the horizon (zero light). night may be NULL. */
int sl_sky_sunlight(const sl_atmosphere *atm, const double p[3], const double sun_dir[3],
                    double *irradiance, int *night, sl_error *err);

/* Riley eqs. 14-15 (corrected): single-scattered sky radiance gathered along the segment from
 * eye along unit direction dir for distance metres (INFINITY: to the top of the atmosphere, or
 * to the ground for a downward ray), and the transparency of that segment (eq. 11), for every
 * wavelength. Either output may be NULL. *night is set when the sun is down (radiance 0). */
int sl_sky_segment(const sl_atmosphere *atm, const double eye[3], const double dir[3],
                   double distance, const double sun_dir[3], double *radiance,
                   double *transparency, int *night, sl_error *err);

/* Plan once per frame: the eye, the sun and the sun's air mass at the eye (for the round earth
 * one Chapman quadrature, ~2 us), so per-pixel queries cost only the closed forms. */
typedef struct sl_sky_view {
  const sl_atmosphere *atm;
  double eye[3];
  double sun[3];     /* unit, toward the sun */
  double airmass;    /* sun air mass at the eye's height; infinite at night */
  double altitude;   /* the eye's height above the ground (sl_sky_altitude) */
  double up[3];      /* the eye's local vertical */
  int night;
} sl_sky_view;

int sl_sky_view_init(sl_sky_view *view, const sl_atmosphere *atm, const double eye[3],
                     const double sun_dir[3], sl_error *err);
/* Sky light reaching the eye from the part [t_near, t_far] of the ray eye + t dir (t_far may be
 * INFINITY: to the top of the atmosphere, or to where the ray meets the ground), already
 * attenuated by the air between the eye and t_near, and the transparency of [t_near, t_far].
 * Splitting a ray at any t gives front + T(front) * back = whole: the renderer's split at the
 * volume's midplane (section 5) is exact. dir must be a unit vector; either output may be NULL.
 * The air mass is the eye's for the whole ray (docs/SKY.md: below 0.2% from the exact one). */
void sl_sky_view_segment(const sl_sky_view *view, const double dir[3], double t_near, double t_far,
                         double *radiance, double *transparency);

/* The light on a horizontal ground at the atmosphere's origin (sea level under the frame's tangent
 * point): the clear sky's irradiance, the integral of its radiance times the cosine over the upper
 * hemisphere (16-point Gauss in the cosine, 64 azimuths), and the sun's, its attenuated irradiance
 * (eq. 12) times the cosine of its zenith angle, per wavelength. *night when the sun is down (both
 * 0). A Lambertian ground of albedo a sends a (sky + sun) / pi (ground_light.c). */
int sl_sky_ground_irradiance(const sl_atmosphere *atm, const double sun[3], double *sky, double *sun_on_ground,
                             int *night, sl_error *err);

/* Section 4.2.4: the direct sun (its angular diameter, SL_SUN_ANGULAR_DIAMETER_DEG, and the
 * per-ray pieces are in sl_sky_sample.h). */
/* Returns 1 when dir lies within the sun's disk (and the sun is up), else 0. */
int sl_sky_in_sun_disk(const double dir[3], const double sun_dir[3]);
/* Radiance of the sun's disk seen from eye: the attenuated irradiance divided by the disk's
 * solid angle, for dir inside the disk, zero elsewhere. The caller multiplies by the volume's
 * transparency. Returns 1 when dir is inside the disk. */
int sl_sky_sun_disk_radiance(const sl_atmosphere *atm, const double eye[3], const double dir[3],
                             const double sun_dir[3], double *radiance);

/* The unit vector toward the sun from its elevation and azimuth is sl_sun_direction (sl_camera.h). */

/* Solar position: Meeus, Astronomical Algorithms (2nd ed. 1998) ch. 25 (low-accuracy solar
 * coordinates, stated accuracy 0.01 degree), with ch. 22 nutation, ch. 12 apparent sidereal time,
 * ch. 13 horizontal coordinates, the horizontal parallax, and the atmospheric refraction of the
 * NREL SPA (Reda & Andreas 2004, eq. 42). Measured against NREL SPA: docs/ACCURACY.md. */
typedef struct sl_utc {
  int year, month, day, hour, minute;
  double second;
} sl_utc;

/* An ISO 8601 date-time ("2024-06-21T05:30:00Z", "2003-10-17 12:30:30-07:00"; no zone is UTC)
 * into UTC; a one-line error quoting the text otherwise (utc.c). */
int sl_utc_parse_iso8601(const char *text, sl_utc *out, sl_error *err);
/* t moved by `seconds` (any sign), normalised into the calendar; fractions of a second kept. */
int sl_utc_add_seconds(sl_utc *t, double seconds, sl_error *err);

typedef struct sl_solar_options {
  double pressure_hpa;   /* for refraction; default 1010 */
  double temperature_c;  /* for refraction; default 10 */
  double delta_t_s;      /* TT - UT; default 69.2 (2020s) */
  int refraction;        /* 1: apparent (refracted) elevation, the default; 0: geometric */
} sl_solar_options;

typedef struct sl_solar_position {
  double elevation_deg;       /* apparent (with refraction when enabled), topocentric */
  double azimuth_deg;         /* clockwise from north, [0, 360) */
  double zenith_deg;          /* 90 - elevation_deg */
  double elevation_true_deg;  /* topocentric, without refraction */
  double declination_deg, right_ascension_deg, hour_angle_deg;
  double julian_day;          /* UT */
  double direction[3];        /* unit vector toward the sun, ENU */
  int night;                  /* the sun's centre is at or below the horizon */
} sl_solar_position;

void sl_solar_options_default(sl_solar_options *opt);
/* Julian day (UT) of a Gregorian UTC date-time; Meeus ch. 7. */
double sl_julian_day(const sl_utc *t);
/* opt may be NULL (defaults). */
int sl_solar_position_compute(const sl_utc *t, double latitude_deg, double longitude_deg,
                              const sl_solar_options *opt, sl_solar_position *out, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
