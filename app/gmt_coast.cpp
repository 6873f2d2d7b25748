#include "gmt_coast.h"

#include <gmt/gmt.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <unordered_map>

namespace sl {

namespace {

// GMT reports through a print function without a user pointer: its last message is kept here,
// per thread, for the one-line error.
thread_local std::string gmt_last_message;

int keep_gmt_message(FILE *, const char *message)
{
  gmt_last_message = message;
  while (!gmt_last_message.empty() && (gmt_last_message.back() == '\n' || gmt_last_message.back() == '\r'))
    gmt_last_message.pop_back();
  return 0;
}

// One GMT session, destroyed on every path.
struct Session {
  void *api = nullptr;
  Session()
  {
    gmt_last_message.clear();
    api = GMT_Create_Session("stormlight", 0U, GMT_SESSION_NOEXIT | GMT_SESSION_NOHISTORY, keep_gmt_message);
  }
  ~Session()
  {
    if (api) GMT_Destroy_Session(api);
  }
  std::string why(const std::string &what) const
  {
    return "GMT " + what + (gmt_last_message.empty() ? "" : ": " + gmt_last_message);
  }
};

std::string region(double lon0, double lon1, double lat0, double lat1)
{
  char text[160];
  std::snprintf(text, sizeof text, "-R%.6f/%.6f/%.6f/%.6f", lon0, lon1, lat0, lat1);
  return text;
}

// `coast OPTIONS -M` into a virtual file: the dataset (nullptr with *error set on failure; a
// successful call may also return nullptr when nothing was selected, *error left empty).
GMT_DATASET *coast_dump(const Session &s, const std::string &options, std::string *error)
{
  error->clear();
  char vfile[GMT_VF_LEN];
  if (GMT_Open_VirtualFile(s.api, GMT_IS_DATASET, GMT_IS_LINE, GMT_OUT, nullptr, vfile) != GMT_NOERROR) {
    *error = s.why("could not open a virtual file");
    return nullptr;
  }
  const std::string args = options + " -M ->" + vfile;
  if (GMT_Call_Module(s.api, "coast", GMT_MODULE_CMD, (void *)args.c_str()) != GMT_NOERROR) {
    *error = s.why("coast " + args);
    GMT_Close_VirtualFile(s.api, vfile);
    return nullptr;
  }
  auto *data = static_cast<GMT_DATASET *>(GMT_Read_VirtualFile(s.api, vfile));
  GMT_Close_VirtualFile(s.api, vfile);
  return data;
}

}  // namespace

bool gmt_coast_lines(CoastLayer layer, double lon0, double lon1, double lat0, double lat1, char resolution,
                     std::vector<GeoLine> *lines, std::string *error)
{
  Session s;
  if (!s.api) {
    *error = s.why("could not start a session");
    return false;
  }
  // -W: the shorelines, the one GSHHG layer drawn (borders come from DCW: gmt_dcw_borders).
  const char *which = layer == CoastLayer::Shorelines ? " -W" : "";
  auto *data = coast_dump(s, region(lon0, lon1, lat0, lat1) + " -D" + resolution + which, error);
  if (!data && !error->empty()) return false;
  lines->clear();
  if (!data) return true;  // nothing in the region
  for (uint64_t t = 0; t < data->n_tables; ++t)
    for (uint64_t g = 0; g < data->table[t]->n_segments; ++g) {
      const GMT_DATASEGMENT *seg = data->table[t]->segment[g];
      if (seg->n_columns < 2 || seg->n_rows < 2) continue;
      GeoLine line(seg->n_rows);
      for (uint64_t r = 0; r < seg->n_rows; ++r) line[r] = GeoPoint{seg->data[0][r], seg->data[1][r]};
      lines->push_back(std::move(line));
    }
  GMT_Destroy_Data(s.api, &data);
  return true;
}

namespace {

// One DCW polygon ring near the region, longitudes put within 180 degrees of the region's centre.
struct Ring {
  int country;  // index into the country codes
  std::vector<GeoPoint> p;
};

// Edges of the rings hashed on a grid of square cells at least `tolerance` wide in both directions
// (metres on WRF's sphere, local equirectangular), so that every edge within the tolerance of a
// point lies in the point's cell or its 8 neighbours.
class EdgeGrid {
 public:
  EdgeGrid(const std::vector<Ring> &rings, double tolerance_m, double max_abs_lat)
      : rings_(rings), tol_m_(tolerance_m)
  {
    cell_deg_ = tolerance_m / (metres_per_degree * std::cos(std::min(max_abs_lat, 89.0) * M_PI / 180.0));
    for (uint32_t r = 0; r < rings.size(); ++r)
      for (uint32_t i = 0; i + 1 < rings[r].p.size(); ++i) {
        const GeoPoint &a = rings[r].p[i], &b = rings[r].p[i + 1];
        const long x0 = cell(std::min(a.lon, b.lon)), x1 = cell(std::max(a.lon, b.lon));
        const long y0 = cell(std::min(a.lat, b.lat)), y1 = cell(std::max(a.lat, b.lat));
        if ((x1 - x0 + 1) * (y1 - y0 + 1) > 4096) continue;  // a degenerate jump (none in DCW's rings)
        for (long x = x0; x <= x1; ++x)
          for (long y = y0; y <= y1; ++y) cells_[key(x, y)].push_back({r, i});
      }
  }
  // The country of the nearest edge within the tolerance that is not `country`'s, or -1.
  int nearest_other(GeoPoint q, int country) const
  {
    const long cx = cell(q.lon), cy = cell(q.lat);
    const double kx = metres_per_degree * std::cos(q.lat * M_PI / 180.0), ky = metres_per_degree;
    double best = tol_m_ * tol_m_;
    int who = -1;
    for (long x = cx - 1; x <= cx + 1; ++x)
      for (long y = cy - 1; y <= cy + 1; ++y) {
        const auto it = cells_.find(key(x, y));
        if (it == cells_.end()) continue;
        for (const EdgeRef &e : it->second) {
          const Ring &ring = rings_[e.ring];
          if (ring.country == country) continue;
          // Point-to-segment distance on the local plane at q.
          const double ax = (ring.p[e.i].lon - q.lon) * kx, ay = (ring.p[e.i].lat - q.lat) * ky;
          const double bx = (ring.p[e.i + 1].lon - q.lon) * kx, by = (ring.p[e.i + 1].lat - q.lat) * ky;
          const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
          const double t = len2 > 0 ? std::clamp(-(ax * dx + ay * dy) / len2, 0.0, 1.0) : 0.0;
          const double px = ax + t * dx, py = ay + t * dy, d2 = px * px + py * py;
          if (d2 <= best) best = d2, who = ring.country;
        }
      }
    return who;
  }

  static constexpr double metres_per_degree = 6370000.0 * M_PI / 180.0;  // WRF's sphere

 private:
  struct EdgeRef {
    uint32_t ring, i;
  };
  long cell(double deg) const { return (long)std::floor(deg / cell_deg_); }
  static long long key(long x, long y) { return (long long)x * 4000003LL + y; }
  const std::vector<Ring> &rings_;
  double tol_m_, cell_deg_;
  std::unordered_map<long long, std::vector<EdgeRef>> cells_;
};

}  // namespace

bool gmt_dcw_borders(double lon0, double lon1, double lat0, double lat1, double tolerance_m,
                     std::vector<GeoLine> *lines, std::string *error, DcwBorderStats *stats)
{
  Session s;
  if (!s.api) {
    *error = s.why("could not start a session");
    return false;
  }
  // Every country of the seven continents (DCW has no spatial index for -R to use), each segment
  // headed "-Z<code> <name> Segment <n>" (+z).
  auto *data = coast_dump(s, "-E=AF,=AN,=AS,=EU,=NA,=OC,=SA+z", error);
  if (!data) {
    if (error->empty()) *error = s.why("coast -E returned no DCW polygons");
    return false;
  }
  // The rings that come within the tolerance (plus a margin) of the region.
  const double clon = 0.5 * (lon0 + lon1), max_abs_lat = std::max(std::fabs(lat0), std::fabs(lat1));
  const double margin =
      2.0 * tolerance_m / (EdgeGrid::metres_per_degree * std::cos(std::min(max_abs_lat, 89.0) * M_PI / 180.0));
  std::vector<std::string> codes;
  std::vector<Ring> rings;
  for (uint64_t t = 0; t < data->n_tables; ++t)
    for (uint64_t g = 0; g < data->table[t]->n_segments; ++g) {
      const GMT_DATASEGMENT *seg = data->table[t]->segment[g];
      if (seg->n_columns < 2 || seg->n_rows < 2) continue;
      const char *h = seg->header ? std::strstr(seg->header, "-Z") : nullptr;
      if (!h) continue;
      const std::string code(h + 2, std::strcspn(h + 2, " \t"));
      Ring ring;
      bool near = false;
      ring.p.resize(seg->n_rows);
      for (uint64_t r = 0; r < seg->n_rows; ++r) {
        GeoPoint p{seg->data[0][r], seg->data[1][r]};
        p.lon -= 360.0 * std::round((p.lon - clon) / 360.0);
        near = near || (p.lon >= lon0 - margin && p.lon <= lon1 + margin && p.lat >= lat0 - margin &&
                        p.lat <= lat1 + margin);
        ring.p[r] = p;
      }
      if (!near) continue;
      const auto it = std::find(codes.begin(), codes.end(), code);
      ring.country = (int)(it - codes.begin());
      if (it == codes.end()) codes.push_back(code);
      rings.push_back(std::move(ring));
    }
  GMT_Destroy_Data(s.api, &data);

  const EdgeGrid grid(rings, tolerance_m, max_abs_lat + margin);
  DcwBorderStats st;
  st.countries = codes.size();
  lines->clear();
  auto inside = [&](GeoPoint p) { return p.lon >= lon0 && p.lon <= lon1 && p.lat >= lat0 && p.lat <= lat1; };
  for (const Ring &ring : rings) {
    // on[i]: the country of another polygon's edge within the tolerance of vertex i, or -1.
    std::vector<int> on(ring.p.size());
    for (size_t i = 0; i < ring.p.size(); ++i) {
      on[i] = grid.nearest_other(ring.p[i], ring.country);
      if (inside(ring.p[i])) ++st.vertices_tested, st.vertices_on_border += on[i] >= 0;
    }
    GeoLine run;
    for (size_t i = 0; i + 1 < ring.p.size(); ++i) {
      const GeoPoint a = ring.p[i], b = ring.p[i + 1], mid{0.5 * (a.lon + b.lon), 0.5 * (a.lat + b.lat)};
      const bool ends_on = on[i] >= 0 && on[i + 1] >= 0 && (inside(a) || inside(b));
      const int other = ends_on ? grid.nearest_other(mid, ring.country) : -1;
      // Each border once: drawn from the country whose code sorts first.
      if (other >= 0 && codes[ring.country] < codes[other]) {
        if (run.empty()) run.push_back(a);
        run.push_back(b);
      } else if (!run.empty()) {
        lines->push_back(std::move(run));
        run.clear();
      }
    }
    if (!run.empty()) lines->push_back(std::move(run));
  }
  if (stats) *stats = st;
  return true;
}

bool gmt_land_mask(const double *lat, const double *lon, size_t n, double step_deg, char resolution,
                   std::vector<float> *mask, std::string *error)
{
  if (n == 0) return true;
  double lon0 = lon[0], lon1 = lon[0], lat0 = lat[0], lat1 = lat[0];
  for (size_t i = 0; i < n; ++i) {
    lon0 = std::min(lon0, lon[i]), lon1 = std::max(lon1, lon[i]);
    lat0 = std::min(lat0, lat[i]), lat1 = std::max(lat1, lat[i]);
  }
  lon0 -= step_deg, lon1 += step_deg, lat0 -= step_deg, lat1 += step_deg;
  Session s;
  if (!s.api) {
    *error = s.why("could not start a session");
    return false;
  }
  char vfile[GMT_VF_LEN];
  if (GMT_Open_VirtualFile(s.api, GMT_IS_GRID, GMT_IS_SURFACE, GMT_OUT, nullptr, vfile) != GMT_NOERROR) {
    *error = s.why("could not open a virtual grid");
    return false;
  }
  char inc[64];
  std::snprintf(inc, sizeof inc, " -I%.6f", step_deg);
  // -N wet/dry/wet/dry/wet for ocean/land/lake/island/pond: 1 on land and islands.
  const std::string args = region(lon0, lon1, lat0, lat1) + inc + " -D" + resolution + " -N0/1/0/1/0 -G" + vfile;
  if (GMT_Call_Module(s.api, "grdlandmask", GMT_MODULE_CMD, (void *)args.c_str()) != GMT_NOERROR) {
    *error = s.why("grdlandmask " + args);
    GMT_Close_VirtualFile(s.api, vfile);
    return false;
  }
  auto *grid = static_cast<GMT_GRID *>(GMT_Read_VirtualFile(s.api, vfile));
  GMT_Close_VirtualFile(s.api, vfile);
  if (!grid) {
    *error = s.why("grdlandmask returned no grid");
    return false;
  }
  const GMT_GRID_HEADER *h = grid->header;
  mask->assign(n, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    // Nearest node; GMT_Get_Index accounts for the grid's padding; rows run from the north.
    const double fx = (lon[i] - h->wesn[GMT_XLO]) / h->inc[GMT_X] - (h->registration ? 0.5 : 0.0);
    const double fy = (h->wesn[GMT_YHI] - lat[i]) / h->inc[GMT_Y] - (h->registration ? 0.5 : 0.0);
    const int col = std::clamp((int)std::lround(fx), 0, (int)h->n_columns - 1);
    const int row = std::clamp((int)std::lround(fy), 0, (int)h->n_rows - 1);
    (*mask)[i] = grid->data[GMT_Get_Index(s.api, const_cast<GMT_GRID_HEADER *>(h), row, col)] > 0.5f ? 1.0f : 0.0f;
  }
  GMT_Destroy_Data(s.api, &grid);
  return true;
}

}  // namespace sl
