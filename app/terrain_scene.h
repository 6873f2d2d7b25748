// The scene around the storm in the VTK window: the terrain as a surface whose per-vertex radiance
// comes from render/surface (sun through the cloud's shadow, sky, aerial perspective), and map
// overlays draped on it: GSHHG coastlines and national borders (gmt_coast), a latitude/longitude
// graticule, the domain's outline and a scale bar. Positions come from the file's own XLAT/XLONG,
// inverted (ColumnMap), so any projection places them. Props only: the physics is in render/.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sl_settings.h"

#include "sl_renderer.h"
#include "sl_storm.h"
#include "sl_terrain.h"

class vtkRenderer;

namespace sl {

class Options;

struct MapLayers {
  bool terrain = false, coastlines = false, borders = false, graticule = false, outline = false, scale_bar = false;
  double albedo = -1.0;          // < 0: the file's ALBEDO, else land 0.15 / water 0.06
  double graticule_step = 0.0;   // degrees; 0 picks 3-8 lines across the domain
  bool any() const { return terrain || coastlines || borders || graticule || outline || scale_bar; }
};

// The layer options come from the option table (sl_settings_options) with the scene's others.
// Reads them; false with a one-line error.
bool read_map_options(const sl_settings &s, MapLayers *layers, std::string *error);

// Latitude/longitude to fractional column indices by inverting the bilinear interpolation of the
// file's XLAT/XLONG (Newton's method from the nearest column).
class ColumnMap {
 public:
  explicit ColumnMap(const sl_storm_frame &frame);
  // False when the point lies outside the columns' lattice.
  bool to_grid(double lat, double lon, double *fi, double *fj) const;
  void grid_to_world(double fi, double fj, double *x, double *y) const;
  // Height of the terrain's triangles (sl_heightfield's split) at fractional indices.
  double height(double fi, double fj) const;
  void lonlat_range(double *lon0, double *lon1, double *lat0, double *lat1) const;

 private:
  sl_column_map map_{};
  sl_heightfield terrain_{};
};

class TerrainScene {
 public:
  TerrainScene();
  ~TerrainScene();
  // Lights the terrain for the scene's sun and storm and builds the overlays' lines.
  bool build(const sl_storm_frame &frame, const MapLayers &layers, const sl_scene &scene, std::string *error);
  // For one camera: what the eye sees of each vertex, and the distance to the ground per pixel.
  bool prepare_view(const sl_camera &cam, std::string *error);
  // Per pixel, rows from the top; for sl_camera.opaque_distance. NULL without the terrain layer.
  const float *opaque_distance() const;
  void add_props(vtkRenderer *renderer) const;
  // The CPU composite: the terrain's pixels replace the background (overlays need VTK).
  void paint_background(const sl_camera &cam, float *background_rgba) const;
  // The cloud's transmittance toward the sun per column (for reports and tests).
  const std::vector<float> &sun_transmittance() const { return sun_transmittance_; }
  std::string summary() const { return summary_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<float> sun_transmittance_;
  std::string summary_;
};

}  // namespace sl
