// National borders from DCW (gmt_dcw_borders) against GMT's command-line tool and published
// lengths: for France-Spain-Andorra and the US-Mexico border, every border vertex lies within the
// tolerance of the polygons of two different countries as `gmt coast -E<code> -M` writes them
// (a point of open coast lies on one country's outline only), the border is the length the CIA
// World Factbook gives it (within 15 %: DCW is a 1:1 000 000 chart, whose mountain borders are
// shorter than the survey's), and the countries' open
// coast, which DCW's polygons carry too, is not drawn (GSHHG's shoreline, `gmt coast -W`, stays
// away from the border except where it ends at the sea).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "gmt_coast.h"

extern "C" {
#include "sl_testing.h"
}

// A check whose failure prints a formatted line.
#define EXPECT(cond, ...)                                   \
  do {                                                      \
    char what_[320];                                        \
    std::snprintf(what_, sizeof what_, __VA_ARGS__);        \
    CHECK_MSG((cond), what_);                               \
  } while (0)

using Lines = std::vector<sl::GeoLine>;
static constexpr double kR = 6370000.0, kDeg = M_PI / 180.0;

// Segments from `gmt ... -M` text (">" starts one), kept within the box (a point outside ends the
// piece), longitudes put within 180 degrees of the box's centre.
static Lines run_lines(const std::string &cmd, double lon0, double lon1, double lat0, double lat1)
{
  Lines out(1);
  FILE *p = popen(cmd.c_str(), "r");
  if (!p) return {};
  char buf[512];
  const double clon = 0.5 * (lon0 + lon1);
  while (std::fgets(buf, sizeof buf, p)) {
    sl::GeoPoint q;
    const bool point = buf[0] != '>' && std::sscanf(buf, "%lf %lf", &q.lon, &q.lat) == 2;
    if (point) q.lon -= 360.0 * std::round((q.lon - clon) / 360.0);
    if (point && q.lon >= lon0 && q.lon <= lon1 && q.lat >= lat0 && q.lat <= lat1)
      out.back().push_back(q);
    else if (!out.back().empty())
      out.emplace_back();
  }
  pclose(p);
  return out;
}

// The segments of some polylines bucketed on 0.05-degree cells (each in every cell its box
// covers) for distance queries up to a few kilometres.
struct Index {
  static constexpr double cell = 0.05;
  const Lines &lines;
  std::map<std::pair<long, long>, std::vector<std::pair<size_t, size_t>>> cells;
  explicit Index(const Lines &l) : lines(l)
  {
    for (size_t k = 0; k < l.size(); ++k)
      for (size_t i = 0; i + 1 < l[k].size(); ++i) {
        const sl::GeoPoint a = l[k][i], b = l[k][i + 1];
        for (long x = ix(std::fmin(a.lon, b.lon)); x <= ix(std::fmax(a.lon, b.lon)); ++x)
          for (long y = ix(std::fmin(a.lat, b.lat)); y <= ix(std::fmax(a.lat, b.lat)); ++y)
            cells[{x, y}].push_back({k, i});
      }
  }
  static long ix(double deg) { return (long)std::floor(deg / cell); }
  // Distance (m, local plane at q) to the nearest segment in q's cell and its neighbours: exact
  // up to 0.05 degrees (5.5 km north-south, 4.4 km east-west at 37 N), +inf beyond.
  double distance(sl::GeoPoint q) const
  {
    const double kx = kR * kDeg * std::cos(q.lat * kDeg), ky = kR * kDeg;
    double best = INFINITY;
    for (long x = ix(q.lon) - 1; x <= ix(q.lon) + 1; ++x)
      for (long y = ix(q.lat) - 1; y <= ix(q.lat) + 1; ++y) {
        const auto it = cells.find({x, y});
        if (it == cells.end()) continue;
        for (const auto &e : it->second) {
          const sl::GeoPoint a = lines[e.first][e.second], b = lines[e.first][e.second + 1];
          const double ax = (a.lon - q.lon) * kx, ay = (a.lat - q.lat) * ky;
          const double bx = (b.lon - q.lon) * kx, by = (b.lat - q.lat) * ky;
          const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
          const double t = len2 > 0 ? std::fmin(1.0, std::fmax(0.0, -(ax * dx + ay * dy) / len2)) : 0.0;
          best = std::fmin(best, std::hypot(ax + t * dx, ay + t * dy));
        }
      }
    return best;
  }
};

static double length_m(const Lines &lines)
{
  double s = 0.0;
  for (const sl::GeoLine &l : lines)
    for (size_t i = 0; i + 1 < l.size(); ++i)
      s += kR * std::hypot((l[i + 1].lon - l[i].lon) * kDeg * std::cos(0.5 * (l[i].lat + l[i + 1].lat) * kDeg),
                           (l[i + 1].lat - l[i].lat) * kDeg);
  return s;
}

struct Case {
  const char *name;
  double lon0, lon1, lat0, lat1;
  std::vector<const char *> countries;  // every country with a border in the region
  double factbook_km;                   // the borders' published total length
};

int main()
{
  const double tol = 500.0;  // metres; see docs/SCENES.md
  const Case cases[] = {
      // Spain-France 646 km + Andorra-France 55.2 km + Andorra-Spain 63.7 km (Factbook, 2023).
      {"France-Spain-Andorra", -2.5, 3.5, 42.0, 43.6, {"FR", "ES", "AD"}, 646.0 + 55.2 + 63.7},
      // Mexico-US 3111 km (Factbook, 2023).
      {"US-Mexico", -117.5, -96.5, 25.0, 33.0, {"US", "MX"}, 3111.0},
  };
  for (const Case &c : cases) {
    Lines ours;
    std::string why;
    sl::DcwBorderStats st;
    const bool ok = sl::gmt_dcw_borders(c.lon0, c.lon1, c.lat0, c.lat1, tol, &ours, &why, &st);
    EXPECT(ok, "%s", why.c_str());
    const double b0 = c.lon0 - 1, b1 = c.lon1 + 1, a0 = c.lat0 - 1, a1 = c.lat1 + 1;
    std::vector<Lines> cli;
    const std::string gmt = "gmt coast --GMT_HISTORY=false ";
    for (const char *code : c.countries) cli.push_back(run_lines(gmt + "-E" + code + " -M", b0, b1, a0, a1));
    std::vector<Index> outline;
    for (const Lines &l : cli) outline.emplace_back(l);
    char region[128];
    std::snprintf(region, sizeof region, "-R%g/%g/%g/%g", b0, b1, a0, a1);
    // GSHHG's level 1 (the sea's shore; its lakes include reservoirs on the Rio Grande border).
    const Lines shore_lines = run_lines(gmt + region + " -Dl -W -A0/1/1 -M", b0, b1, a0, a1);
    const Index shore(shore_lines);
    size_t n = 0, on_two = 0;
    double worst_second = 0.0, near_shore_m = 0.0;
    for (const sl::GeoLine &l : ours)
      for (size_t i = 0; i < l.size(); ++i) {
        std::vector<double> d;
        for (const Index &o : outline) d.push_back(o.distance(l[i]));
        std::sort(d.begin(), d.end());
        worst_second = std::fmax(worst_second, d[1]);
        on_two += d[1] <= tol;
        ++n;
        if (i + 1 < l.size() && shore.distance(l[i]) < 2000.0) near_shore_m += length_m({{l[i], l[i + 1]}});
      }
    // The same test on the countries' whole outlines in the region finds their open coast.
    double coast_m = 0.0;
    for (size_t k = 0; k < cli.size(); ++k)
      for (const sl::GeoLine &l : cli[k])
        for (size_t i = 0; i + 1 < l.size(); ++i)
          if (l[i].lon >= c.lon0 && l[i].lon <= c.lon1 && l[i].lat >= c.lat0 && l[i].lat <= c.lat1 &&
              shore.distance(l[i]) < 2000.0)
            coast_m += length_m({{l[i], l[i + 1]}});
    const double km = length_m(ours) / 1000.0;
    std::printf("%s: %zu countries read, %zu of %zu vertices on a border; %zu lines, %zu vertices, %.0f km "
                "(Factbook %.0f km); second-nearest CLI outline worst %.0f m; within 2 km of GSHHG's shore %.1f km "
                "(the countries' whole outlines: %.0f km)\n",
                c.name, st.countries, st.vertices_on_border, st.vertices_tested, ours.size(), n, km, c.factbook_km,
                worst_second, near_shore_m / 1000.0, coast_m / 1000.0);
    EXPECT(n > 100, "%s: too few border vertices", c.name);
    EXPECT(on_two == n, "%s: %zu border vertices lie on one country's outline only (worst %.0f m)", c.name, n - on_two,
           worst_second);
    EXPECT(std::fabs(km / c.factbook_km - 1.0) < 0.15, "%s: %.0f km against the Factbook's %.0f km", c.name, km,
           c.factbook_km);
    // Both borders end at the sea twice; GSHHG's low shoreline is a few km off DCW's near a coast.
    EXPECT(near_shore_m < 2 * 10000.0 && coast_m > 20 * near_shore_m,
           "%s: %.1f km of border within 2 km of the shore (the outlines: %.0f km)", c.name, near_shore_m / 1000.0,
           coast_m / 1000.0);
  }
  return sl_test_finish("dcw_borders");
}
