/* Per-sample atmospheric light: Riley et al. 2004, eqs. 1, 9-15, in a plain-C subset.
 *
 * Everything here takes and returns scalars (double), uses no pointers, no varargs, no library
 * calls beyond exp/sqrt/abs and isinf (INFINITY for a ray that meets no ground): the bodies,
 * in sky_sample_shared.h, are one text that the C library compiles with double and the GPU
 * pass's shaders embed as GLSL (tests/gpu/test_gpu_sky checks that the two agree). Units:
 * metres, m^-1; heights z are above sea level; the direction cosine mu is the z component (up)
 * of the unit view direction, p_Omega_y in the paper.
 *
 * Night is encoded as an infinite air mass: every function here then returns zero light, never
 * NaN. See docs/SKY.md for the derivations. */
#ifndef SL_SKY_SAMPLE_H
#define SL_SKY_SAMPLE_H

#ifdef __cplusplus
extern "C" {
#endif

/* (1 - exp(-x)) / x, equal to 1 at x = 0, accurate to a few ulp for every x (series near 0,
 * where the direct form cancels). The one helper every closed form below is written with. */
double sl_sky_exprel(double x);

/* Riley eq. 1, Rayleigh phase function (sr^-1) of the cosine of the scattering angle. Owned
 * by render/optics for particles; repeated here because the sky must not depend on optics. */
double sl_sky_rayleigh_phase(double cos_theta);

/* The length factor D of an exponential atmosphere along a straight segment that rises dz over
 * distance K: integral_0^K exp(-gamma * dz * t / K) dt = K * exprel(gamma * dz). The optical
 * depth of the segment is beta(z_start) * D. Stable for horizontal (dz = 0) and long segments. */
double sl_sky_path_length_factor(double inv_scale_height, double dz, double distance);

/* Riley eq. 11: optical depth between two points at heights z0 and z1 a distance apart
 * (flat earth). Symmetric in the two points. Transparency is exp(-this). */
double sl_sky_optical_depth(double beta_sea_level, double inv_scale_height, double z0, double z1,
                            double distance);

/* Riley eq. 12 exponent: optical depth from height z to the sun along a path of the given air
 * mass (1/cos(zenith) for the flat earth, the Chapman function for the round one). Sunlight at
 * the point is I * exp(-this). Infinite air mass (night) gives infinity. */
double sl_sky_sun_optical_depth(double beta_sea_level, double inv_scale_height, double z,
                                double airmass);

/* Distance along a ray from an eye at height z_eye above the ground, with direction cosine mu to
 * the local vertical, to where it meets the ground: the plane z = 0 when ground_radius is 0 (the
 * paper's flat earth), z_eye / -mu; else the sphere of that radius under the eye,
 *   t = -(R + h) mu - sqrt((R + h)^2 mu^2 - h (2R + h)),
 * and INFINITY when the ray does not go down or passes above the sphere's horizon, whose dip
 * below the horizontal is acos(R / (R + h)). Heights below the ground count as on it. */
double sl_sky_ground_distance(double z_eye, double mu, double ground_radius);

/* Length of the view segment that the sky integral covers: `distance` itself, except that a ray
 * stops where it meets the ground (sl_sky_ground_distance), and an infinite distance otherwise
 * means the top of the atmosphere (kept infinite: the closed form handles it). */
double sl_sky_segment_length(double z_eye, double mu, double distance, double ground_radius);

/* Riley eqs. 14-15, corrected: single-scattered sunlight gathered along the segment from an eye
 * at height z_eye along a ray of direction cosine mu for `distance` metres (may be infinite),
 * per unit top-of-atmosphere sun irradiance, for a sun of the given air mass and scattering-angle
 * cosine cos_view_sun (view direction dotted with the direction toward the sun).
 *
 *   L = P(cos) * beta_eye * exp(-min(c, e)) * D * exprel(|e - c|)
 *   c = beta_eye * m / gamma            (sun optical depth at the eye)
 *   e = tau_K + beta_K * m / gamma      (optical depth eye -> far end -> sun)
 *   D = K * exprel(gamma * mu * K),  tau_K = beta_eye * D,  e - c = tau_K * (1 - mu * m)
 *
 * which is the paper's eq. 15 times the missing factor exp(-beta_eye / (gamma * mu)), rewritten
 * without the divisions by mu and by (mu - l) that make the printed form singular. */
double sl_sky_inscatter(double beta_sea_level, double inv_scale_height, double z_eye, double mu,
                        double distance, double airmass, double cos_view_sun);

/* The same, split for callers that evaluate many wavelengths along one ray: the geometry is
 * wavelength-independent. D = sl_sky_segment_length_factor(gamma, mu, K) (K may be infinite),
 * far_density = exp(-gamma mu K) (0 for an infinite upward ray), beta_eye = beta_sl exp(-gamma z);
 * returns L / (P(theta) I). */
double sl_sky_segment_length_factor(double inv_scale_height, double mu, double distance);
double sl_sky_inscatter_gathered(double beta_eye, double inv_scale_height, double mu, double length,
                                 double far_density, double airmass);

/* Section 4.2.4: the direct sun's angular diameter, and the pieces of sl_sky_in_sun_disk and
 * sl_sky_sun_disk_radiance (sl_sky.h): the disk's solid angle; whether a view direction lies in
 * the disk, from its difference (dx, dy, dz) to the unit vector toward the sun and that vector's
 * z (a sun below the horizon shows no disk); one wavelength's radiance of the disk seen from
 * height z through an air mass (0 at night: infinite air mass). */
#define SL_SUN_ANGULAR_DIAMETER_DEG 0.5
double sl_sun_disk_solid_angle(void);
int sl_sky_in_sun_disk_at(double dx, double dy, double dz, double sun_z);
double sl_sky_sun_disk_light(double irradiance, double beta_sea_level, double inv_scale_height, double z,
                             double airmass);

/* The view-segment pieces of sl_sky_view_segment (sl_sky.h), one wavelength at a time over a
 * geometry computed once per ray: see sky_sample_shared.h. */
void sl_sky_segment_geometry(double inv_scale_height, double z_eye, double mu, double near, double end, double g[5]);
double sl_sky_view_geometry(double inv_scale_height, double z_eye, double mu, double ground_radius, double t_near,
                            double t_far, double g[5]);
double sl_sky_segment_radiance(double beta, double irradiance, double phase, double inv_scale_height, double mu,
                               double near, double airmass, const double g[5]);
double sl_sky_segment_transparency(double beta, const double g[5]);

#ifdef __cplusplus
}
#endif
#endif
