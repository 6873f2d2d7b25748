// Map layers against GMT's own command-line tool and PROJ: a synthetic storm over the Mississippi
// delta (Lambert grid), its coastline from GMT's C API (gmt_coast) equals `gmt coast -M`'s, and
// each coastline vertex lands on the grid where `proj` puts it (the grid is centred on the
// projection's origin), through the inversion of the file's XLAT/XLONG (ColumnMap).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "gmt_coast.h"
#include "sl_storm.h"
#include "sl_synth.h"
#include "terrain_scene.h"

static int failures = 0;
#define EXPECT(cond, ...)                          \
  do {                                             \
    if (!(cond)) {                                 \
      std::printf("FAILED %s: ", #cond);           \
      std::printf(__VA_ARGS__);                    \
      std::printf("\n");                           \
      ++failures;                                  \
    }                                              \
  } while (0)

static std::string run(const std::string &cmd)
{
  std::string out;
  FILE *p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  pclose(p);
  return out;
}

int main(int argc, char **argv)
{
  const std::string work = argc > 1 ? argv[1] : ".";
  std::system(("mkdir -p " + work).c_str());
  const std::string path = work + "/delta.nc";
  const double clat = 29.6, clon = -89.6;
  sl_synth_options so;
  sl_synth_defaults(SL_SYNTH_CUMULONIMBUS, &so);
  so.nx = so.ny = 32, so.nz = 12, so.dx = 8000.0, so.center_lat = clat, so.center_lon = clon;
  sl_error err{};
  if (sl_synth_write(path.c_str(), &so, &err)) {
    std::printf("synth: %s\n", err.message);
    return 1;
  }
  sl_storm_frame frame;
  sl_load_options lo{};
  if (sl_storm_load(path.c_str(), &lo, &frame, &err)) {
    std::printf("load: %s\n", err.message);
    return 1;
  }
  sl::ColumnMap map(frame);
  double lon0, lon1, lat0, lat1;
  map.lonlat_range(&lon0, &lon1, &lat0, &lat1);
  std::vector<sl::GeoLine> api;
  std::string why;
  EXPECT(sl::gmt_coast_lines(sl::CoastLayer::Shorelines, lon0, lon1, lat0, lat1, 'l', &api, &why), "%s", why.c_str());
  // The same request to the command-line tool.
  char region[160];
  std::snprintf(region, sizeof region, "-R%.6f/%.6f/%.6f/%.6f", lon0, lon1, lat0, lat1);
  std::istringstream cli(run("cd '" + work + "' && gmt coast " + region + " -Dl -W -M"));
  std::vector<sl::GeoPoint> cli_points;
  std::string line;
  while (std::getline(cli, line)) {
    if (line.empty() || line[0] == '>') continue;
    sl::GeoPoint p;
    if (std::sscanf(line.c_str(), "%lf %lf", &p.lon, &p.lat) == 2) cli_points.push_back(p);
  }
  size_t api_count = 0;
  double worst_deg = 0.0;
  for (const sl::GeoLine &l : api)
    for (const sl::GeoPoint &p : l) {
      if (api_count < cli_points.size())
        worst_deg = std::fmax(worst_deg, std::fmax(std::fabs(p.lon - cli_points[api_count].lon),
                                                   std::fabs(p.lat - cli_points[api_count].lat)));
      ++api_count;
    }
  std::printf("GMT API %zu vertices, gmt coast -M %zu, worst difference %.2e deg\n", api_count, cli_points.size(),
              worst_deg);
  EXPECT(api_count == cli_points.size() && api_count > 50, "vertex counts differ");
  EXPECT(worst_deg < 1e-9, "API and command line disagree");
  // Vertices inside the domain: our world position against PROJ's Lambert conformal conic on
  // WRF's sphere, the synthetic grid's definition (datasets/synth).
  std::ostringstream pts;
  std::vector<double> ours;
  for (const sl::GeoPoint &p : cli_points) {
    double fi, fj;
    if (!map.to_grid(p.lat, p.lon, &fi, &fj)) continue;
    ours.push_back(fi), ours.push_back(fj);
    char row[96];
    std::snprintf(row, sizeof row, "%.10f %.10f\n", p.lon, p.lat);
    pts << row;
  }
  const std::string pts_file = work + "/coast_points.txt";
  if (FILE *f = std::fopen(pts_file.c_str(), "w")) {
    std::fputs(pts.str().c_str(), f);
    std::fclose(f);
  }
  char proj[256];
  std::snprintf(proj, sizeof proj, "proj -f %%.4f +proj=lcc +lat_1=%g +lat_2=%g +lat_0=%g +lon_0=%g +R=6370000 ",
                clat - 5, clat + 5, clat, clon);
  std::istringstream projected(run(std::string(proj) + pts_file));
  double worst_m = 0.0;
  size_t k = 0;
  while (std::getline(projected, line) && 2 * k + 1 < ours.size()) {
    double x, y;
    if (std::sscanf(line.c_str(), "%lf %lf", &x, &y) != 2) continue;
    // PROJ's plane position as a grid position: the synthetic grid is centred on the projection's
    // origin with spacing dx on the plane (the world frame is ENU on the sphere, which
    // test_projection checks; here the inversion of XLAT/XLONG is what is tested).
    const double pi = x / so.dx + 0.5 * (so.nx - 1), pj = y / so.dx + 0.5 * (so.ny - 1);
    worst_m = std::fmax(worst_m, so.dx * std::hypot(pi - ours[2 * k], pj - ours[2 * k + 1]));
    ++k;
  }
  std::printf("%zu coastline vertices in the domain; worst distance from PROJ's position %.2f m (grid %.0f m)\n", k,
              worst_m, so.dx);
  EXPECT(k > 20 && k == ours.size() / 2, "too few vertices in the domain or PROJ failed (%zu)", k);
  EXPECT(worst_m < 0.02 * so.dx, "vertices more than 2%% of a cell from PROJ's");
  sl_storm_frame_free(&frame);
  std::printf("%s\n", failures ? "FAILED" : "passed");
  return failures ? 1 : 0;
}
