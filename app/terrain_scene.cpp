#include "terrain_scene.h"

#include <vtkActor.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCellArray.h>
#include <vtkDataObject.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkOpenGLPolyDataMapper.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkShaderProperty.h>
#include <vtkSmartPointer.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli.h"
#include "gmt_coast.h"
#include "sl_cie.h"
#include "sl_optics.h"

namespace sl {

bool read_map_options(const sl_settings &s, MapLayers *m, std::string *error)
{
  // Ranges are checked by the option table (scene/settings.c).
  (void)error;
  m->terrain = s.terrain, m->coastlines = s.coastlines, m->borders = s.borders, m->graticule = s.graticule;
  m->outline = s.domain_outline, m->scale_bar = s.scale_bar;
  if (sl_settings_given(&s, "terrain-albedo")) m->albedo = s.terrain_albedo;
  m->graticule_step = s.graticule_step;
  return true;
}

// ---- ColumnMap: io/column_map.c and render/surface's triangles ----

ColumnMap::ColumnMap(const sl_storm_frame &f)
{
  const double origin[2] = {f.volume.origin[0], f.volume.origin[1]};
  const double spacing[2] = {f.volume.spacing[0], f.volume.spacing[1]};
  sl_column_map_init(&map_, f.volume.nx, f.volume.ny, f.column_lat, f.column_lon, origin, spacing);
  if (f.terrain_height) sl_heightfield_init(&terrain_, f.volume.nx, f.volume.ny, origin, spacing, f.terrain_height);
}

bool ColumnMap::to_grid(double lat, double lon, double *fi, double *fj) const
{
  return sl_column_map_to_grid(&map_, lat, lon, fi, fj) != 0;
}

void ColumnMap::grid_to_world(double fi, double fj, double *x, double *y) const
{
  sl_column_map_world(&map_, fi, fj, x, y);
}

double ColumnMap::height(double fi, double fj) const { return sl_heightfield_height_at(&terrain_, fi, fj); }

void ColumnMap::lonlat_range(double *lon0, double *lon1, double *lat0, double *lat1) const
{
  sl_column_map_range(&map_, lon0, lon1, lat0, lat1);
}

// ---- TerrainScene ----

namespace {

struct Polyline {
  std::vector<double> xyz;  // world points
};

struct LineLayer {
  std::vector<Polyline> lines;
  double rgb[3];  // radiance (overlays are drawn, not lit)
  float width;
};

}  // namespace

struct TerrainScene::Impl {
  MapLayers layers;
  int nx = 0, ny = 0, nwl = 3;
  std::vector<float> height;
  sl_heightfield hf{};
  std::vector<double> points, radiance;  // per vertex: world xyz, radiance per wavelength
  std::vector<float> seen;               // per vertex linear sRGB for the current camera
  std::vector<float> opaque;             // per pixel
  std::vector<LineLayer> overlays;
  double to_rgb[3 * SL_SKY_MAX_WAVELENGTHS] = {0};
  bool spectral = false;
  const sl_atmosphere *atm = nullptr;
  double sun[3] = {0, 0, 1};
  double scale_km = 0, scale_at[3] = {0, 0, 0};
  Polyline scale_line;
  std::unique_ptr<ColumnMap> map;
  double lift = 50.0;
};

TerrainScene::TerrainScene() : impl_(new Impl) {}
TerrainScene::~TerrainScene() = default;

// Splits a lat/lon polyline into the pieces inside the domain, sampled at most half a cell apart
// in the grid so that the line follows the terrain.
static void drape(const ColumnMap &map, const GeoLine &line, std::vector<Polyline> *out)
{
  Polyline cur;
  auto flush = [&]() {
    if (cur.xyz.size() >= 6) out->push_back(cur);
    cur.xyz.clear();
  };
  double prev_i = 0, prev_j = 0;
  bool prev_in = false;
  for (size_t k = 0; k < line.size(); ++k) {
    const int pieces = k == 0 ? 1 : 8;
    for (int s = 1; s <= pieces; ++s) {
      const double w = k == 0 ? 1.0 : (double)s / pieces;
      const GeoPoint a = k == 0 ? line[0] : line[k - 1];
      const double lat = a.lat + w * (line[k].lat - a.lat), lon = a.lon + w * (line[k].lon - a.lon);
      double fi, fj;
      const bool in = map.to_grid(lat, lon, &fi, &fj);
      if (!in) {
        flush();
        prev_in = false;
        continue;
      }
      if (prev_in && std::hypot(fi - prev_i, fj - prev_j) < 0.25 && s < pieces) continue;
      double x, y;
      map.grid_to_world(fi, fj, &x, &y);
      cur.xyz.insert(cur.xyz.end(), {x, y, map.height(fi, fj)});
      prev_i = fi, prev_j = fj, prev_in = true;
    }
  }
  flush();
}

static double nice_step(double range, int min_lines)
{
  const double steps[] = {0.1, 0.25, 0.5, 1, 2, 5, 10, 15, 30};
  double best = steps[0];
  for (double s : steps)
    if (range / s >= min_lines) best = s;
  return best;
}

bool TerrainScene::build(const sl_storm_frame &frame, const MapLayers &layers, const sl_scene &scene,
                         std::string *error)
{
  Impl &m = *impl_;
  m.layers = layers;
  if (!frame.terrain_height || !frame.column_lat || !frame.column_lon) {
    *error = "the storm file gave no terrain height and latitude/longitude per column (HGT, XLAT, XLONG)";
    return false;
  }
  const sl_volume &v = frame.volume;
  m.nx = v.nx, m.ny = v.ny;
  m.atm = scene.atmosphere;
  for (int a = 0; a < 3; ++a) m.sun[a] = scene.sun_direction[a];
  m.nwl = m.atm ? m.atm->count : 3;
  m.spectral = m.nwl != 3;
  if (m.spectral) {
    sl_error err{};
    if (sl_cie_srgb_weights(m.atm->wavelength_nm, m.nwl, 1, m.to_rgb, &err)) {
      *error = err.message;
      return false;
    }
  }
  m.height.assign(frame.terrain_height, frame.terrain_height + (size_t)m.nx * m.ny);
  const double origin[2] = {v.origin[0], v.origin[1]}, spacing[2] = {v.spacing[0], v.spacing[1]};
  sl_heightfield_init(&m.hf, m.nx, m.ny, origin, spacing, m.height.data());
  const size_t n = (size_t)m.nx * m.ny;
  m.points.resize(3 * n);
  for (int j = 0; j < m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) sl_heightfield_point(&m.hf, i, j, &m.points[3 * ((size_t)j * m.nx + i)]);
  m.map.reset(new ColumnMap(frame));
  const ColumnMap &map = *m.map;
  char note[256];
  summary_.clear();

  if (layers.terrain) {
    // Albedo: the user's, the file's land-surface ALBEDO, else land/water (Briegleb et al. 1986:
    // vegetated land about 0.15, open ocean about 0.06 for diffuse light).
    std::vector<float> albedo(n);
    std::string source;
    std::vector<float> land;
    if (layers.albedo >= 0) {
      std::fill(albedo.begin(), albedo.end(), (float)layers.albedo);
      source = "given";
    } else if (frame.surface_albedo) {
      albedo.assign(frame.surface_albedo, frame.surface_albedo + n);
      source = "the file's ALBEDO";
    } else {
      if (frame.land_mask) {
        land.assign(frame.land_mask, frame.land_mask + n);
        source = "land 0.15 / water 0.06 from the file's land mask";
      } else {
        std::string why;
        if (!gmt_land_mask(frame.column_lat, frame.column_lon, n, 0.5 * v.spacing[0] / 111e3, 'l', &land, &why)) {
          *error = why;
          return false;
        }
        source = "land 0.15 / water 0.06 from GSHHG (GMT grdlandmask)";
      }
      for (size_t c = 0; c < n; ++c) albedo[c] = (float)(land[c] > 0.5f ? SL_LAND_ALBEDO : SL_WATER_ALBEDO);
    }
    sl_terrain_light_params p{};
    p.terrain = &m.hf;
    p.volume = scene.volume;
    for (int q = 0; q < SL_VOLUME_SLOTS; ++q) {
      // The renderer's cross-sections (the tables' mean over wavelengths) and the tables' g; the
      // low-albedo model's Table 2 cross-sections with its isotropic phase (g = 0).
      if (!scene.optics || !scene.volume->eta[q]) continue;
      const int nw = sl_optics_wavelength_count(scene.optics);
      for (int w = 0; w < nw; ++w) {
        const sl_phase_table *t =
            sl_optics_table_sized(scene.optics, sl_volume_field_type(scene.volume, q), scene.volume->effective_radius_m[q], w);
        if (!t) continue;
        p.sigma_ext[q] += t->sigma_ext / nw;
        p.asymmetry[q] += t->asymmetry / nw;
      }
    }
    p.atmosphere = m.atm;
    for (int c = 0; c < 3; ++c) p.sun_irradiance[c] = scene.sun_irradiance[c], p.sky_radiance[c] = scene.sky_radiance[c];
    for (int a = 0; a < 3; ++a) p.sun_direction[a] = scene.sun_direction[a];
    p.albedo = albedo.data();
    m.radiance.resize(n * m.nwl);
    sun_transmittance_.resize(n);
    sl_error err{};
    if (sl_terrain_light(&p, m.radiance.data(), sun_transmittance_.data(), &err)) {
      *error = err.message;
      return false;
    }
    const auto mm = std::minmax_element(sun_transmittance_.begin(), sun_transmittance_.end());
    std::snprintf(note, sizeof note, "terrain %.0f-%.0f m, albedo: %s; the storm's transmittance toward the sun %.3g-%.3g",
                  m.hf.zmin, m.hf.zmax, source.c_str(), *mm.first, *mm.second);
    summary_ += note;
  }

  double lon0, lon1, lat0, lat1;
  map.lonlat_range(&lon0, &lon1, &lat0, &lat1);
  auto add_geo = [&](const std::vector<GeoLine> &lines, double r, double g, double b, float width) {
    LineLayer layer{{}, {r, g, b}, width};
    for (const GeoLine &l : lines) drape(map, l, &layer.lines);
    m.overlays.push_back(layer);
    return layer.lines.size();
  };
  for (int which = 0; which < 2; ++which) {
    if (!(which ? layers.borders : layers.coastlines)) continue;
    std::vector<GeoLine> lines;
    std::string why;
    // Borders: DCW's land borders (gmt_dcw_borders; 500 m, see docs/SCENES.md); coast: GSHHG low.
    if (!(which ? gmt_dcw_borders(lon0 - 1, lon1 + 1, lat0 - 1, lat1 + 1, 500.0, &lines, &why)
                : gmt_coast_lines(CoastLayer::Shorelines, lon0 - 1, lon1 + 1, lat0 - 1, lat1 + 1, 'l', &lines, &why))) {
      *error = why;
      return false;
    }
    const size_t k = which ? add_geo(lines, 0.35, 0.06, 0.04, 2.0f) : add_geo(lines, 0.30, 0.30, 0.26, 2.0f);
    std::snprintf(note, sizeof note, "%s%zu %s piece(s) in the domain", summary_.empty() ? "" : "; ", k,
                  which ? "border" : "coastline");
    summary_ += note;
  }
  if (layers.graticule) {
    const double step = layers.graticule_step > 0 ? layers.graticule_step : nice_step(std::min(lat1 - lat0, lon1 - lon0), 3);
    std::vector<GeoLine> lines;
    for (double lon = std::ceil(lon0 / step) * step; lon <= lon1; lon += step) {
      GeoLine l;
      for (int s = 0; s <= 64; ++s) l.push_back({lon, lat0 + (lat1 - lat0) * s / 64.0});
      lines.push_back(l);
    }
    for (double lat = std::ceil(lat0 / step) * step; lat <= lat1; lat += step) {
      GeoLine l;
      for (int s = 0; s <= 64; ++s) l.push_back({lon0 + (lon1 - lon0) * s / 64.0, lat});
      lines.push_back(l);
    }
    add_geo(lines, 0.05, 0.05, 0.05, 1.0f);
    std::snprintf(note, sizeof note, "%sgraticule every %g deg", summary_.empty() ? "" : "; ", step);
    summary_ += note;
  }
  if (layers.outline) {
    LineLayer layer{{}, {0.30, 0.24, 0.02}, 2.0f};
    Polyline p;
    auto push = [&](int i, int j) {
      p.xyz.insert(p.xyz.end(), {v.origin[0] + i * v.spacing[0], v.origin[1] + j * v.spacing[1],
                                 (double)m.height[(size_t)j * m.nx + i]});
    };
    for (int i = 0; i < m.nx; ++i) push(i, 0);
    for (int j = 1; j < m.ny; ++j) push(m.nx - 1, j);
    for (int i = m.nx - 2; i >= 0; --i) push(i, m.ny - 1);
    for (int j = m.ny - 2; j >= 0; --j) push(0, j);
    layer.lines.push_back(p);
    m.overlays.push_back(layer);
  }
  return true;
}

bool TerrainScene::prepare_view(const sl_camera &cam, std::string *error)
{
  Impl &m = *impl_;
  const size_t n = (size_t)m.nx * m.ny;
  double dist = 0.0;
  for (int a = 0; a < 3; ++a) dist += (cam.target[a] - cam.position[a]) * (cam.target[a] - cam.position[a]);
  // Overlays float above the surface by a depth-buffer-safe margin that grows with distance.
  m.lift = std::max(20.0, 2e-3 * std::sqrt(dist));
  if (m.layers.scale_bar) {
    // Where the camera sees it: on the ground under the lower-left of the frame, a round length
    // near a third of the ground the frame's lower edge spans, pointing east.
    auto ground = [&](double fx, double fy, double p[3]) {
      double d[3], t;
      if (sl_camera_ray(&cam, (int)(fx * cam.width), (int)(fy * cam.height), d)) return false;
      if (!sl_heightfield_ray(&m.hf, cam.position, d, INFINITY, &t)) {
        if (!(d[2] < 0.0)) return false;
        t = (m.hf.zmin - cam.position[2]) / d[2];  // beyond the domain: its lowest level
      }
      for (int a = 0; a < 3; ++a) p[a] = cam.position[a] + t * d[a];
      return true;
    };
    double a[3], b[3];
    if (!ground(0.12, 0.88, a) || !ground(0.88, 0.88, b)) {
      a[0] = m.hf.origin[0], a[1] = m.hf.origin[1], a[2] = m.hf.zmin;
      b[0] = a[0] + (m.nx - 1) * m.hf.spacing[0], b[1] = a[1];
    }
    const double x_east = m.hf.origin[0] + (m.nx - 1) * m.hf.spacing[0];
    const double span_km = std::min(std::hypot(b[0] - a[0], b[1] - a[1]), x_east - m.hf.origin[0]) / 1000.0 / 3.0;
    const double mag = std::pow(10.0, std::floor(std::log10(std::max(span_km, 1e-3))));
    m.scale_km = mag;
    for (double f : {2.0, 5.0})
      if (f * mag <= span_km) m.scale_km = f * mag;
    // Kept on the domain: inside its columns, and ending before its east edge.
    a[0] = std::clamp(a[0], m.hf.origin[0], x_east - m.scale_km * 1000.0);
    a[1] = std::clamp(a[1], m.hf.origin[1], m.hf.origin[1] + (m.ny - 1) * m.hf.spacing[1]);
    a[2] = m.map->height((a[0] - m.hf.origin[0]) / m.hf.spacing[0], (a[1] - m.hf.origin[1]) / m.hf.spacing[1]);
    for (int k = 0; k < 3; ++k) m.scale_at[k] = a[k];
    m.scale_line.xyz.clear();
    for (int s = 0; s <= 32; ++s) {
      const double x = a[0] + m.scale_km * 1000.0 * s / 32, y = a[1];
      const double fi = (x - m.hf.origin[0]) / m.hf.spacing[0], fj = (y - m.hf.origin[1]) / m.hf.spacing[1];
      const bool inside = fi >= 0 && fj >= 0 && fi <= m.nx - 1 && fj <= m.ny - 1;
      m.scale_line.xyz.insert(m.scale_line.xyz.end(), {x, y, inside ? m.map->height(fi, fj) : a[2]});
    }
  }
  if (!m.layers.terrain) return true;
  m.seen.resize(3 * n);
  sl_error err{};
  if (sl_terrain_seen(m.atm, cam.position, m.sun, m.points.data(), n, m.radiance.data(), m.nwl,
                      m.spectral ? m.to_rgb : nullptr, m.seen.data(), &err)) {
    *error = err.message;
    return false;
  }
  m.opaque.assign((size_t)cam.width * cam.height, INFINITY);
#pragma omp parallel for schedule(dynamic, 4)
  for (int py = 0; py < cam.height; ++py)
    for (int px = 0; px < cam.width; ++px) {
      double d[3], t;
      if (sl_camera_ray(&cam, px, py, d)) continue;
      if (sl_heightfield_ray(&m.hf, cam.position, d, INFINITY, &t)) m.opaque[(size_t)py * cam.width + px] = (float)t;
    }
  return true;
}

const float *TerrainScene::opaque_distance() const
{
  return impl_->layers.terrain && !impl_->opaque.empty() ? impl_->opaque.data() : nullptr;
}

void TerrainScene::paint_background(const sl_camera &cam, float *bg) const
{
  const Impl &m = *impl_;
  if (!m.layers.terrain || m.opaque.empty()) return;
  for (int py = 0; py < cam.height; ++py)
    for (int px = 0; px < cam.width; ++px) {
      const size_t q = (size_t)py * cam.width + px;
      if (!std::isfinite(m.opaque[q])) continue;
      double d[3];
      sl_camera_ray(&cam, px, py, d);
      const double x = cam.position[0] + m.opaque[q] * d[0], y = cam.position[1] + m.opaque[q] * d[1];
      const double fi = std::clamp((x - m.hf.origin[0]) / m.hf.spacing[0], 0.0, m.nx - 1.0);
      const double fj = std::clamp((y - m.hf.origin[1]) / m.hf.spacing[1], 0.0, m.ny - 1.0);
      const int i = std::min((int)fi, m.nx - 2), j = std::min((int)fj, m.ny - 2);
      const double u = fi - i, v = fj - j;
      auto c = [&](int ii, int jj, int ch) { return (double)m.seen[3 * ((size_t)jj * m.nx + ii) + ch]; };
      for (int ch = 0; ch < 3; ++ch)
        bg[4 * q + ch] = (float)(u >= v ? (1 - u) * c(i, j, ch) + (u - v) * c(i + 1, j, ch) + v * c(i + 1, j + 1, ch)
                                        : (1 - v) * c(i, j, ch) + u * c(i + 1, j + 1, ch) + (v - u) * c(i, j + 1, ch));
      bg[4 * q + 3] = 1.0f;
    }
}

void TerrainScene::add_props(vtkRenderer *renderer) const
{
  const Impl &m = *impl_;
  if (m.layers.terrain && !m.seen.empty()) {
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    const size_t n = (size_t)m.nx * m.ny;
    for (size_t c = 0; c < n; ++c) pts->InsertNextPoint(&m.points[3 * c]);
    vtkNew<vtkCellArray> tris;
    for (int j = 0; j + 1 < m.ny; ++j)
      for (int i = 0; i + 1 < m.nx; ++i) {
        const vtkIdType p00 = (vtkIdType)j * m.nx + i, p10 = p00 + 1, p01 = p00 + m.nx, p11 = p01 + 1;
        const vtkIdType a[3] = {p00, p10, p11}, b[3] = {p00, p11, p01};  // sl_heightfield's split
        tris->InsertNextCell(3, a);
        tris->InsertNextCell(3, b);
      }
    vtkNew<vtkFloatArray> radiance;
    radiance->SetName("slRadiance");
    radiance->SetNumberOfComponents(3);
    radiance->SetNumberOfTuples((vtkIdType)n);
    for (size_t c = 0; c < n; ++c) radiance->SetTypedTuple((vtkIdType)c, &m.seen[3 * c]);
    vtkNew<vtkPolyData> surface;
    surface->SetPoints(pts);
    surface->SetPolys(tris);
    surface->GetPointData()->AddArray(radiance);
    vtkNew<vtkOpenGLPolyDataMapper> mapper;
    mapper->SetInputData(surface);
    mapper->ScalarVisibilityOff();
    // The float radiance goes to the float framebuffer as it is: a vertex attribute, not 8-bit
    // colours, and no lighting by VTK (render/surface lit it).
    mapper->MapDataArrayToVertexAttribute("slRadianceMC", "slRadiance", vtkDataObject::FIELD_ASSOCIATION_POINTS, -1);
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    // Seen from below, the ground is behind the round earth's horizon (sl_heightfield_ray likewise).
    actor->GetProperty()->BackfaceCullingOn();
    vtkShaderProperty *sp = actor->GetShaderProperty();
    sp->AddVertexShaderReplacement("//VTK::Color::Dec", true,
                                   "//VTK::Color::Dec\nin vec3 slRadianceMC;\nout vec3 slRadianceVSOut;", false);
    sp->AddVertexShaderReplacement("//VTK::Color::Impl", true, "//VTK::Color::Impl\nslRadianceVSOut = slRadianceMC;",
                                   false);
    sp->AddFragmentShaderReplacement("//VTK::Color::Dec", true, "//VTK::Color::Dec\nin vec3 slRadianceVSOut;", false);
    sp->AddFragmentShaderReplacement("//VTK::Light::Impl", true,
                                     "//VTK::Light::Impl\ngl_FragData[0] = vec4(slRadianceVSOut, 1.0);", false);
    renderer->AddActor(actor);
  }
  for (const LineLayer &layer : m.overlays) {
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    vtkNew<vtkCellArray> cells;
    for (const Polyline &l : layer.lines) {
      const vtkIdType count = (vtkIdType)(l.xyz.size() / 3);
      cells->InsertNextCell(count);
      for (vtkIdType k = 0; k < count; ++k)
        cells->InsertCellPoint(pts->InsertNextPoint(l.xyz[3 * k], l.xyz[3 * k + 1], l.xyz[3 * k + 2] + m.lift));
    }
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(pts);
    poly->SetLines(cells);
    vtkNew<vtkOpenGLPolyDataMapper> mapper;
    mapper->SetInputData(poly);
    mapper->ScalarVisibilityOff();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->LightingOff();
    actor->GetProperty()->SetColor(layer.rgb[0], layer.rgb[1], layer.rgb[2]);
    actor->GetProperty()->SetLineWidth(layer.width);
    renderer->AddActor(actor);
  }
  if (m.layers.scale_bar && m.scale_km > 0) {
    vtkNew<vtkPoints> pts;
    vtkNew<vtkCellArray> cells;
    const vtkIdType count = (vtkIdType)(m.scale_line.xyz.size() / 3);
    cells->InsertNextCell(count);
    for (vtkIdType k = 0; k < count; ++k)
      cells->InsertCellPoint(pts->InsertNextPoint(m.scale_line.xyz[3 * k], m.scale_line.xyz[3 * k + 1],
                                                  m.scale_line.xyz[3 * k + 2] + m.lift));
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(pts);
    poly->SetLines(cells);
    vtkNew<vtkOpenGLPolyDataMapper> mapper;
    mapper->SetInputData(poly);
    vtkNew<vtkActor> bar;
    bar->SetMapper(mapper);
    bar->GetProperty()->LightingOff();
    bar->GetProperty()->SetColor(0.6, 0.6, 0.6);
    bar->GetProperty()->SetLineWidth(4.0f);
    renderer->AddActor(bar);
    vtkNew<vtkBillboardTextActor3D> label;
    char text[64];
    std::snprintf(text, sizeof text, "%g km", m.scale_km);
    label->SetInput(text);
    label->SetPosition(m.scale_at[0] + 0.5 * m.scale_km * 1000.0, m.scale_at[1], m.scale_at[2] + 4.0 * m.lift);
    label->GetTextProperty()->SetFontSize(14);
    label->GetTextProperty()->SetColor(0.6, 0.6, 0.6);
    label->GetTextProperty()->SetJustificationToCentered();
    renderer->AddActor(label);
  }
}

}  // namespace sl
