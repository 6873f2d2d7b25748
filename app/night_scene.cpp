#include "night_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

#ifndef SL_WITHOUT_APSF
#include "sl_glow.h"
#endif
#include "sl_terrain.h"

namespace sl {

bool read_night_scene(const sl_settings &s, const sl_storm_frame &frame, NightScene *night, std::string *why)
{
  // Ranges and the lamps' count are checked by the option table (scene/settings.c).
  const double white[3] = {1, 1, 1};
  sl_photometric_to_render(s.night_sky_luminance, white, night->night_sky);
  if (!sl_settings_given(&s, "lights-count")) return true;
  sl_light_grid g{};
  g.spacing = s.lights_spacing, g.height = s.lights_height, g.jitter = s.lights_jitter;
  g.intensity_cd = s.lights_intensity_cd;
  g.count[0] = s.lights_count[0], g.count[1] = s.lights_count[1];
  g.center[0] = s.lights_center[0], g.center[1] = s.lights_center[1];
  for (int c = 0; c < 3; ++c) g.color[c] = s.lights_color[c];
  g.seed = 1;
  night->lights.resize((size_t)g.count[0] * g.count[1]);
  sl_error err{};
  if (sl_light_grid_build(&g, night->lights.data(), &err)) {
    *why = err.message;
    return false;
  }
  // On the ground: the file's HGT through the same triangles the terrain draws (render/surface).
  const sl_volume &v = frame.volume;
  if (frame.terrain_height && v.nx >= 2 && v.ny >= 2) {
    sl_heightfield hf;
    const double origin[2] = {v.origin[0], v.origin[1]}, spacing[2] = {v.spacing[0], v.spacing[1]};
    sl_heightfield_init(&hf, v.nx, v.ny, origin, spacing, frame.terrain_height);
    for (sl_point_light &l : night->lights) {
      // Lamps beyond the grid stand at the height of its nearest edge.
      const double o[3] = {std::min(std::max(l.position[0], origin[0]), origin[0] + (v.nx - 1) * spacing[0]),
                           std::min(std::max(l.position[1], origin[1]), origin[1] + (v.ny - 1) * spacing[1]),
                           hf.zmax + 100.0};
      const double down[3] = {0.0, 0.0, -1.0};
      double t = 0.0;
      l.position[2] += sl_heightfield_ray(&hf, o, down, hf.zmax - hf.zmin + 200.0, &t) ? o[2] - t : hf.zmin;
    }
  }
  return true;
}

bool night_prepare_view(NightScene *night, sl_camera *cam, std::string *why)
{
  if (!night->any_lights()) return true;
  const size_t np = (size_t)cam->width * cam->height;
  night->pixels.resize(night->lights.size());
  int n = 0;
  sl_error err{};
  if (sl_point_lights_project(cam, night->lights.data(), (int)night->lights.size(), night->pixels.data(), &n, &err)) {
    *why = err.message;
    return false;
  }
  night->pixels.resize((size_t)n);
  if (cam->opaque_distance) night->opaque_distance.assign(cam->opaque_distance, cam->opaque_distance + np);
  else night->opaque_distance.assign(np, std::numeric_limits<float>::infinity());
  // Lamps behind an opaque surface (the terrain) are hidden; the others stop their pixel's eye ray.
  std::vector<sl_light_pixel> seen;
  for (const sl_light_pixel &p : night->pixels)
    if (!(night->opaque_distance[p.pixel] < p.ray_distance)) seen.push_back(p);
  night->pixels.swap(seen);
  sl_point_lights_stop_rays(night->pixels.data(), (int)night->pixels.size(), night->opaque_distance.data());
  cam->opaque_distance = night->opaque_distance.data();
  night->source_mask.assign(np, 0);
  return true;
}

#ifndef SL_WITHOUT_APSF
bool fog_airlight(const sl_atmosphere *atm, const double sun_direction[3], const sl_camera &cam,
                  const double night_sky[3], const sl_apsf_medium *const media[3], std::vector<float> *map,
                  std::string *why)
{
  const double *eye = cam.position;
  const double ground_albedo = SL_LAND_ALBEDO;  // the terrain's default over land
  double up[3] = {night_sky[0], night_sky[1], night_sky[2]}, down[3];
  for (int c = 0; c < 3; ++c) down[c] = ground_albedo * up[c];  // E = pi L from a uniform sky
  if (atm) {
    sl_error err{};
    std::vector<double> sky(atm->count), sun(atm->count);
    int night = 0;
    if (sl_sky_irradiance(atm, sun_direction, eye[2], 16, 32, nullptr, sky.data(), &err) ||
        sl_sky_sunlight(atm, eye, sun_direction, sun.data(), &night, &err)) {
      *why = std::string("airlight: ") + err.message;
      return false;
    }
    const double mu0 = night ? 0.0 : std::max(0.0, sun_direction[2]);
    for (int c = 0; c < 3; ++c) {
      // Three wavelengths are the channels; a spectral set is taken grey (its mean).
      double e_sky = 0.0, e_sun = 0.0;
      if (atm->count == 3) e_sky = sky[c], e_sun = night ? 0.0 : sun[c];
      else {
        for (int k = 0; k < atm->count; ++k) e_sky += sky[k] / atm->count, e_sun += (night ? 0.0 : sun[k]) / atm->count;
      }
      up[c] += e_sky / M_PI;
      down[c] += ground_albedo * (e_sky + e_sun * mu0) / M_PI;
    }
  }
  // J per pixel from its centre ray's elevation, tabulated per channel every 0.1 degree.
  const int n_table = 1801;
  std::vector<double> table(3 * (size_t)n_table);
  for (int k = 0; k < n_table; ++k) {
    const double e = (-90.0 + 0.1 * k) * M_PI / 180.0;
    for (int c = 0; c < 3; ++c) table[3 * k + c] = sl_airlight_source(media[c]->albedo, media[c]->q, e, up[c], down[c]);
  }
  map->assign(3 * (size_t)cam.width * cam.height, 0.0f);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      double d[3];
      if (sl_camera_ray(&cam, x, y, d)) {
        *why = "airlight: the camera has no view direction";
        return false;
      }
      const double u = (std::asin(std::max(-1.0, std::min(1.0, d[2]))) * 180.0 / M_PI + 90.0) / 0.1;
      const int k = std::min(n_table - 2, std::max(0, (int)u));
      const double t = std::min(1.0, std::max(0.0, u - k));
      float *o = map->data() + 3 * ((size_t)y * cam.width + x);
      for (int c = 0; c < 3; ++c) o[c] = (float)((1.0 - t) * table[3 * k + c] + t * table[3 * (k + 1) + c]);
    }
  return true;
}
#endif

}  // namespace sl
