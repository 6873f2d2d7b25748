/* Lighting of the ground under the storm: Lambertian reflection of the sun, shadowed by the
 * cloud (its optical depth toward the sun through the volume) and by the terrain itself, plus the
 * sky's light and the sunlight the cloud diffuses (docs/SCENES.md, "The scene around the storm"). */
#include <math.h>
#include <stdlib.h>

#include "sl_particles.h"
#include "sl_terrain.h"

double sl_optical_depth_along(const sl_grid_view *beta, const double x[3], const double dir[3], double step)
{
  double t0, t1;
  if (!sl_ray_box(beta->lo, beta->hi, x, dir, &t0, &t1) || t1 <= 0.0) return 0.0;
  if (t0 < 0.0) t0 = 0.0;
  const int n = (int)ceil((t1 - t0) / step);
  if (n < 1) return 0.0;
  const double dt = (t1 - t0) / n;
  double tau = 0.0;
  for (int k = 0; k < n; ++k) {
    const double t = t0 + (k + 0.5) * dt;
    const double p[3] = {x[0] + t * dir[0], x[1] + t * dir[1], x[2] + t * dir[2]};
    tau += sl_grid_sample(beta, p) * dt; /* Riley et al. 2004, eq. 4 */
  }
  return tau;
}

double sl_diffuse_transmittance(double scaled_optical_depth)
{
  return 1.0 / (1.0 + 0.75 * (scaled_optical_depth > 0.0 ? scaled_optical_depth : 0.0));
}

int sl_sky_irradiance(const sl_atmosphere *atm, const double sun_dir[3], double z, int n_mu, int n_phi,
                      const double *sky_radiance, double *out, sl_error *err)
{
  if (n_mu < 1 || n_phi < 1) return sl_fail(err, SL_ERR_ARG, "sky irradiance: need at least one bin");
  if (!atm) {
    for (int c = 0; c < 3; ++c) out[c] = M_PI * sky_radiance[c];
    return SL_OK;
  }
  const int nwl = atm->count;
  for (int c = 0; c < nwl; ++c) out[c] = 0.0;
  const double eye[3] = {0.0, 0.0, z};
  const double dmu = 1.0 / n_mu, dphi = 2.0 * M_PI / n_phi;
  for (int k = 0; k < n_mu; ++k) {
    const double mu = (k + 0.5) * dmu, s = sqrt(1.0 - mu * mu);
    for (int l = 0; l < n_phi; ++l) {
      const double phi = (l + 0.5) * dphi;
      const double dir[3] = {s * cos(phi), s * sin(phi), mu};
      double L[SL_SKY_MAX_WAVELENGTHS];
      int night = 0;
      if (sl_sky_segment(atm, eye, dir, INFINITY, sun_dir, L, NULL, &night, err)) return err->code;
      if (night) continue;
      for (int c = 0; c < nwl; ++c) out[c] += L[c] * mu * dmu * dphi;
    }
  }
  return SL_OK;
}

/* Extinction and scaled extinction (1 - g) beta summed over the fields, on the volume's lattice. */
static int cloud_grids(const sl_terrain_light_params *p, float **beta, float **scaled, sl_error *err)
{
  const sl_volume *v = p->volume;
  const size_t n = sl_volume_count(v);
  *beta = calloc(n, sizeof(float));
  *scaled = calloc(n, sizeof(float));
  if (!*beta || !*scaled) return sl_fail(err, SL_ERR_NOMEM, "terrain light: out of memory for the extinction grids");
  for (int f = 0; f < SL_VOLUME_SLOTS; ++f) {
    if (!v->eta[f]) continue;
    const double sigma =
        p->sigma_ext[f] > 0.0 ? p->sigma_ext[f] : sl_particle_properties(sl_volume_field_type(v, f))->sigma_ext_m2;
    const double keep = 1.0 - p->asymmetry[f];
    int lo[3], hi[3]; /* outside the content box every field is zero */
    const int any = sl_volume_content_samples(v, lo, hi);
    for (long r = 0; any && r < sl_volume_box_rows(lo, hi); ++r)
      for (size_t i = sl_volume_box_row(v, lo, hi, r), end = i + (size_t)(hi[0] - lo[0]) + 1; i < end; ++i) {
        const double b = v->eta[f][i] * sigma; /* Riley et al. 2004, eq. 2 */
        (*beta)[i] += (float)b;
        (*scaled)[i] += (float)(b * keep);
      }
  }
  return SL_OK;
}

#define SKY_LEVELS 9

int sl_terrain_light(const sl_terrain_light_params *p, double *radiance, float *sun_transmittance, sl_error *err)
{
  const sl_heightfield *hf = p->terrain;
  if (!hf || hf->nx < 2 || hf->ny < 2 || !hf->height || !p->albedo)
    return sl_fail(err, SL_ERR_ARG, "terrain light: need a height field of at least 2x2 points and an albedo");
  const sl_atmosphere *atm = p->atmosphere;
  const int nwl = atm ? atm->count : 3;
  float *beta = NULL, *scaled = NULL;
  sl_grid_view beta_view, scaled_view;
  double step = INFINITY;
  if (p->volume) {
    if (cloud_grids(p, &beta, &scaled, err)) {
      free(beta), free(scaled);
      return err->code;
    }
    sl_grid_view_init(&beta_view, beta, p->volume);
    sl_grid_view_init(&scaled_view, scaled, p->volume);
    for (int a = 0; a < 3; ++a) step = fmin(step, 0.5 * p->volume->spacing[a]);
  }
  /* The sky's irradiance hardly changes over a few kilometres of height: tabulated, then linear. */
  /* Heights above the atmosphere's ground: a storm placed on the round earth (curvature drop)
   * has world z below the tangent plane far from the origin but its true height above the sphere. */
  double zmin = INFINITY, zmax = -INFINITY;
  for (int j = 0; j < hf->ny; ++j)
    for (int i = 0; i < hf->nx; ++i) {
      double x[3];
      sl_heightfield_point(hf, i, j, x);
      const double z = atm ? sl_sky_altitude(atm, x, NULL) : x[2];
      zmin = fmin(zmin, z), zmax = fmax(zmax, z);
    }
  double sky[SKY_LEVELS][SL_SKY_MAX_WAVELENGTHS];
  const double dzs = (zmax - zmin) / (SKY_LEVELS - 1);
  for (int l = 0; l < SKY_LEVELS; ++l)
    if (sl_sky_irradiance(atm, p->sun_direction, zmin + l * dzs, 16, 32, p->sky_radiance, sky[l], err)) {
      free(beta), free(scaled);
      return err->code;
    }
  const double *s = p->sun_direction;
  const double up[3] = {0.0, 0.0, 1.0};
  const double mu0 = s[2] > 0.0 ? s[2] : 0.0;
  int status = SL_OK;
#pragma omp parallel for schedule(dynamic, 16)
  for (int j = 0; j < hf->ny; ++j)
    for (int i = 0; i < hf->nx; ++i) {
      const size_t c = (size_t)j * hf->nx + i;
      double x[3], n[3];
      sl_heightfield_point(hf, i, j, x);
      sl_heightfield_normal(hf, i, j, n);
      double sun[SL_SKY_MAX_WAVELENGTHS];
      int night = 0;
      sl_error local;
      if (atm) {
        if (sl_sky_sunlight(atm, x, s, sun, &night, &local)) {
#pragma omp critical
          status = local.code, *err = local;
          continue;
        }
      } else {
        for (int k = 0; k < 3; ++k) sun[k] = s[2] > 0.0 ? p->sun_irradiance[k] : 0.0;
      }
      double cloud_t = 1.0, scaled_sun = 0.0, scaled_up = 0.0;
      if (p->volume) {
        cloud_t = exp(-sl_optical_depth_along(&beta_view, x, s, step));
        scaled_sun = sl_optical_depth_along(&scaled_view, x, s, step);
        scaled_up = sl_optical_depth_along(&scaled_view, x, up, step);
      }
      if (sun_transmittance) sun_transmittance[c] = (float)cloud_t;
      /* The terrain's own shadow: the ray toward the sun from just above the surface. */
      double t_hit;
      const double lift = 1e-3 * (hf->spacing[0] + hf->spacing[1]);
      const double xo[3] = {x[0] + lift * n[0], x[1] + lift * n[1], x[2] + lift * n[2]};
      const int in_shadow = mu0 > 0.0 && sl_heightfield_ray(hf, xo, s, INFINITY, &t_hit);
      const double facing = n[0] * s[0] + n[1] * s[1] + n[2] * s[2];
      const double direct = in_shadow || facing <= 0.0 ? 0.0 : facing * cloud_t;
      const double diffused_sun = mu0 * fmax(0.0, sl_diffuse_transmittance(scaled_sun) - cloud_t);
      /* Skylight on a tilted surface sees the fraction (1 + n_z) / 2 of the sky hemisphere. */
      const double sky_view = 0.5 * (1.0 + n[2]) * sl_diffuse_transmittance(scaled_up);
      double u = dzs > 0.0 ? ((atm ? sl_sky_altitude(atm, x, NULL) : x[2]) - zmin) / dzs : 0.0;
      int l = (int)u;
      if (l > SKY_LEVELS - 2) l = SKY_LEVELS - 2;
      if (l < 0) l = 0;
      u -= l;
      for (int k = 0; k < nwl; ++k) {
        const double e_sky = (1.0 - u) * sky[l][k] + u * sky[l + 1][k];
        const double e = sun[k] * (direct + diffused_sun) + e_sky * sky_view;
        radiance[c * nwl + k] = p->albedo[c] / M_PI * e; /* Lambert: L = rho E / pi */
      }
    }
  free(beta), free(scaled);
  return status;
}

int sl_terrain_seen(const sl_atmosphere *atm, const double eye[3], const double sun_dir[3], const double *points,
                    size_t n, const double *radiance, int nwl, const double *to_rgb, float *rgb, sl_error *err)
{
  if (!to_rgb && nwl != 3) return sl_fail(err, SL_ERR_ARG, "terrain: %d wavelengths need RGB weights", nwl);
  sl_sky_view view;
  if (atm && sl_sky_view_init(&view, atm, eye, sun_dir, err)) return err->code;
#pragma omp parallel for schedule(static)
  for (size_t q = 0; q < n; ++q) {
    const double *x = points + 3 * q;
    double d[3] = {x[0] - eye[0], x[1] - eye[1], x[2] - eye[2]};
    const double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double spectrum[SL_SKY_MAX_WAVELENGTHS], air[SL_SKY_MAX_WAVELENGTHS], t_air[SL_SKY_MAX_WAVELENGTHS];
    for (int k = 0; k < nwl; ++k) spectrum[k] = radiance[q * nwl + k];
    if (atm && dist > 0.0) {
      for (int a = 0; a < 3; ++a) d[a] /= dist;
      sl_sky_view_segment(&view, d, 0.0, dist, air, t_air); /* Riley et al. 2004, eqs. 11, 14-15 */
      for (int k = 0; k < nwl; ++k) spectrum[k] = t_air[k] * spectrum[k] + air[k];
    }
    for (int c = 0; c < 3; ++c) {
      double v = 0.0;
      if (to_rgb)
        for (int k = 0; k < nwl; ++k) v += to_rgb[c * nwl + k] * spectrum[k];
      else
        v = spectrum[c];
      rgb[3 * q + c] = (float)v;
    }
  }
  return SL_OK;
}
