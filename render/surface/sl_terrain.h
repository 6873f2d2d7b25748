/* The ground under the storm: a height field that stops eye rays, and its Lambertian lighting by
 * the sun (through the atmosphere and the cloud's shadow) and the sky. C11, no VTK: app/ turns
 * the same triangles and per-vertex radiance into a VTK surface (app/terrain_scene). */
#ifndef SL_TERRAIN_H
#define SL_TERRAIN_H

#include "sl_sky.h"
#include "sl_status.h"
#include "sl_volume.h"

/* Diffuse albedo of the ground where a file gives none (Briegleb et al. 1986): vegetated land
 * and open ocean. One home for the terrain's default and the fog bank's ground airlight. */
#define SL_LAND_ALBEDO 0.15
#define SL_WATER_ALBEDO 0.06

#ifdef __cplusplus
extern "C" {
#endif

/* Heights on a regular horizontal lattice (the storm grid's columns). Each cell (i, j)-(i+1, j+1)
 * is two triangles split along the diagonal from (i, j) to (i+1, j+1): (00, 10, 11) and
 * (00, 11, 01). The VTK surface uses the same triangles, so the depth the renderer stops at is
 * the depth VTK rasterizes. */
typedef struct sl_heightfield {
  int nx, ny;            /* at least 2 x 2 */
  double origin[2];      /* world x, y of sample (0, 0), metres */
  double spacing[2];     /* > 0 */
  const float *height;   /* nx * ny, x fastest, metres above sea level; not owned */
  double zmin, zmax;     /* the heights' range; zmax < zmin: computed on each ray query */
} sl_heightfield;

/* Fills hf, with the heights' range. */
void sl_heightfield_init(sl_heightfield *hf, int nx, int ny, const double origin[2], const double spacing[2],
                         const float *height);

/* The height of the triangles at fractional lattice indices (fi, fj), clamped into the lattice:
 * the surface sl_heightfield_ray hits. */
double sl_heightfield_height_at(const sl_heightfield *hf, double fi, double fj);
/* World position of lattice point (i, j). */
void sl_heightfield_point(const sl_heightfield *hf, int i, int j, double p[3]);
/* Unit upward normal at lattice point (i, j) from central differences (one-sided at the edges). */
void sl_heightfield_normal(const sl_heightfield *hf, int i, int j, double n[3]);

/* First intersection of the ray o + t d (d need not be unit) with the triangles from above (their
 * upper side), for t in (0, t_max]: returns 1 and sets *t_hit, else 0. Walks the cells the ray
 * crosses (2-D DDA). */
int sl_heightfield_ray(const sl_heightfield *hf, const double o[3], const double d[3], double t_max, double *t_hit);

/* Optical depth int beta ds from x along the unit direction dir to the box of the grid (beta in
 * m^-1 on the volume's lattice, sampled trilinearly), midpoint rule with steps of at most
 * `step` metres. */
double sl_optical_depth_along(const sl_grid_view *beta, const double x[3], const double dir[3], double step);

/* Clear-sky irradiance on a horizontal surface at height z: the hemisphere integral of the sky
 * radiance (sl_sky_segment, single scattering), E = int L cos(theta) dOmega, by the midpoint rule
 * in cos(theta) (n_mu bins) and azimuth (n_phi bins). Without an atmosphere, atm NULL and the
 * constant sky_radiance: E = pi L. out has one value per wavelength. */
int sl_sky_irradiance(const sl_atmosphere *atm, const double sun_dir[3], double z, int n_mu, int n_phi,
                      const double *sky_radiance, double *out, sl_error *err);

/* Diffuse transmittance of a conservatively scattering layer of scaled optical depth
 * tau' = (1 - g) tau over a black surface, Eddington approximation: T = 1 / (1 + 3/4 tau')
 * (the scaled optical depth as in Bohren & Clothiaux 2006, Fundamentals of Atmospheric
 * Radiation, sec. 5.2; other two-stream closures put 1/2 to 1 in place of 3/4). */
double sl_diffuse_transmittance(double scaled_optical_depth);

/* Lighting of every lattice point: Lambertian radiance
 *   L = albedo / pi * (E_sun T_cloud max(0, n.s) + E_diffuse),
 * E_sun the direct sunlight through the air to the point (Riley eq. 12, sl_sky_sunlight), T_cloud =
 * exp(-tau) the cloud's transmittance toward the sun, and E_diffuse the sky's irradiance
 * (sl_sky_irradiance) times the cloud's diffuse transmittance overhead plus the sunlight the cloud
 * took out of the direct beam and passes on diffusely:
 *   E_diffuse = E_sky T_d(tau'_up) + E_sun mu_0 max(0, T_d(tau'_sun) - T_cloud),
 * T_d the two-stream transmittance of the scaled optical depth tau' = int sum_j beta_j (1 - g_j) ds
 * (upward, and toward the sun). */
typedef struct sl_terrain_light_params {
  const sl_heightfield *terrain;
  const sl_volume *volume;            /* the storm; NULL: no cloud */
  double sigma_ext[SL_VOLUME_SLOTS]; /* m^2 per particle of each field (0: sl_particles.h's) */
  double asymmetry[SL_VOLUME_SLOTS]; /* g of each field */
  const sl_atmosphere *atmosphere;    /* NULL: sun_irradiance and sky_radiance below, no air */
  double sun_irradiance[3];           /* without an atmosphere */
  double sky_radiance[3];             /* without an atmosphere */
  double sun_direction[3];            /* unit, toward the sun */
  const float *albedo;                /* per lattice point, in [0, 1] */
} sl_terrain_light_params;

/* radiance: nx * ny * nwl (nwl = the atmosphere's wavelength count, else 3); sun_transmittance
 * (the cloud's exp(-tau) toward the sun, per point) may be NULL. */
int sl_terrain_light(const sl_terrain_light_params *p, double *radiance, float *sun_transmittance, sl_error *err);

/* What the eye at `eye` sees of n surface points: T_air L + L_air along the segment from the eye
 * (Riley eqs. 11, 14-15 through sl_sky_view_segment), converted to linear sRGB with the 3 x nwl
 * weights to_rgb (NULL: nwl must be 3, used as they are). atm NULL: L as it is. rgb: n * 3. */
int sl_terrain_seen(const sl_atmosphere *atm, const double eye[3], const double sun_dir[3], const double *points,
                    size_t n, const double *radiance, int nwl, const double *to_rgb, float *rgb, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
