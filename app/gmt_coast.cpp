#include "gmt_coast.h"

#include <gmt/gmt.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

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

}  // namespace

bool gmt_coast_lines(CoastLayer layer, double lon0, double lon1, double lat0, double lat1, char resolution,
                     std::vector<GeoLine> *lines, std::string *error)
{
  Session s;
  if (!s.api) {
    *error = s.why("could not start a session");
    return false;
  }
  char vfile[GMT_VF_LEN];
  if (GMT_Open_VirtualFile(s.api, GMT_IS_DATASET, GMT_IS_LINE, GMT_OUT, nullptr, vfile) != GMT_NOERROR) {
    *error = s.why("could not open a virtual file");
    return false;
  }
  // -M dumps the line segments instead of plotting; -W shorelines, -N1 national boundaries.
  const std::string args = region(lon0, lon1, lat0, lat1) + " -D" + resolution +
                           (layer == CoastLayer::Shorelines ? " -W" : " -N1") + " -M ->" + vfile;
  if (GMT_Call_Module(s.api, "coast", GMT_MODULE_CMD, (void *)args.c_str()) != GMT_NOERROR) {
    *error = s.why("coast " + args);
    GMT_Close_VirtualFile(s.api, vfile);
    return false;
  }
  auto *data = static_cast<GMT_DATASET *>(GMT_Read_VirtualFile(s.api, vfile));
  GMT_Close_VirtualFile(s.api, vfile);
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
