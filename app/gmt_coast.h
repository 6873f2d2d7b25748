// Coastlines and a land mask from GMT's GSHHG data (Debian's gmt-gshhg-low), national borders
// from the Digital Chart of the World (Debian's gmt-dcw), through GMT's C API (GMT_Create_Session, GMT_Call_Module "coast" / "grdlandmask" into virtual
// files): no parser of GMT's own formats here.
#pragma once

#include <string>
#include <vector>

namespace sl {

struct GeoPoint {
  double lon, lat;  // degrees east, north
};
using GeoLine = std::vector<GeoPoint>;

enum class CoastLayer { Shorelines };

// The polylines of a layer around the region [lon0, lon1] x [lat0, lat1] (GMT returns whole bins:
// the caller clips). resolution: GSHHG's c (crude) or l (low), the two Debian's gmt-gshhg-low has.
bool gmt_coast_lines(CoastLayer layer, double lon0, double lon1, double lat0, double lat1, char resolution,
                     std::vector<GeoLine> *lines, std::string *error);

// National land borders from DCW's country polygons (`coast -E... -M`): DCW outlines each
// country whole, coast included, so a border is kept where two countries' outlines coincide: the
// runs of a country's polygon whose vertices and edge midpoints all lie within `tolerance_m` of
// another country's polygon edge, each border once (from the country whose code sorts first).
// Every country whose outline reaches [lon0, lon1] x [lat0, lat1] is read; the lines are cut to
// that region (longitudes put within 180 degrees of its centre).
struct DcwBorderStats {
  size_t countries = 0, vertices_tested = 0, vertices_on_border = 0;
};
bool gmt_dcw_borders(double lon0, double lon1, double lat0, double lat1, double tolerance_m,
                     std::vector<GeoLine> *lines, std::string *error, DcwBorderStats *stats = nullptr);

// 1 on land, 0 on water (oceans, and lakes as water) at each point, from GSHHG shorelines via
// GMT's grdlandmask on a grid of `step_deg` over the points' extent (nearest node).
bool gmt_land_mask(const double *lat, const double *lon, size_t n, double step_deg, char resolution,
                   std::vector<float> *mask, std::string *error);

}  // namespace sl
