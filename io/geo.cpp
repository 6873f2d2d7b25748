// GeographicLib behind a C header: the one C++ file of io/.
#include <GeographicLib/LambertConformalConic.hpp>

#include "sl_geo.h"

namespace {
GeographicLib::LambertConformalConic projection(const sl_lambert *p)
{
  // Flattening 0: WRF's earth is a sphere. Scale 1 on the standard parallels.
  return GeographicLib::LambertConformalConic(SL_WRF_EARTH_RADIUS, 0.0, p->truelat1, p->truelat2, 1.0);
}
}  // namespace

extern "C" int sl_lambert_init(sl_lambert *p, double truelat1, double truelat2, double stand_lon, double center_lat,
                               double center_lon)
{
  p->truelat1 = truelat1;
  p->truelat2 = truelat2;
  p->stand_lon = stand_lon;
  p->x0 = p->y0 = 0.0;
  try {
    projection(p).Forward(stand_lon, center_lat, center_lon, p->x0, p->y0);
  } catch (...) {
    return 1;
  }
  return 0;
}

extern "C" void sl_lambert_forward(const sl_lambert *p, double lat, double lon, double *x, double *y)
{
  projection(p).Forward(p->stand_lon, lat, lon, *x, *y);
  *x -= p->x0;
  *y -= p->y0;
}

extern "C" void sl_lambert_reverse(const sl_lambert *p, double x, double y, double *lat, double *lon)
{
  projection(p).Reverse(p->stand_lon, x + p->x0, y + p->y0, *lat, *lon);
}

// ---- WRF's four projections ----
#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/PolarStereographic.hpp>

#include <cmath>
#include <cstdio>

namespace {
constexpr double kDeg = M_PI / 180.0;

// WRF treats true latitudes closer than this as one (tangent cone): share/module_llxy.F set_lc.
constexpr double kTangentTolerance = 0.1;

GeographicLib::LambertConformalConic lambert_of(const sl_projection *p)
{
  if (std::fabs(p->truelat1 - p->truelat2) > kTangentTolerance)
    return GeographicLib::LambertConformalConic(SL_WRF_EARTH_RADIUS, 0.0, p->truelat1, p->truelat2, 1.0);
  return GeographicLib::LambertConformalConic(SL_WRF_EARTH_RADIUS, 0.0, p->truelat1, 1.0);
}

// Mercator: GeographicLib's LambertConformalConic with the equator as standard parallel, its
// central scale set so the scale is 1 on truelat1.
GeographicLib::LambertConformalConic mercator_of(const sl_projection *p)
{
  return GeographicLib::LambertConformalConic(SL_WRF_EARTH_RADIUS, 0.0, 0.0, p->scale);
}

GeographicLib::PolarStereographic polar_of(const sl_projection *p)
{
  return GeographicLib::PolarStereographic(SL_WRF_EARTH_RADIUS, 0.0, p->scale);
}

// The rotation between WRF's computational (rotated) latitude-longitude and geography, as unit
// vectors: g = M c with M = [[sin pp, 0, -cos pp], [0, 1, 0], [cos pp, 0, sin pp]], the
// computational longitude measured from pole_lon and the geographic one shifted by stand_lon
// (WRF share/module_llxy.F rotate_coords, direction >= 0).
void rotated_to_geographic(const sl_projection *p, double rlat, double rlon, double *lat, double *lon)
{
  const double pp = p->pole_lat * kDeg, phi = rlat * kDeg, lam = (rlon - p->pole_lon) * kDeg;
  const double c[3] = {std::cos(phi) * std::cos(lam), std::cos(phi) * std::sin(lam), std::sin(phi)};
  const double gx = std::sin(pp) * c[0] - std::cos(pp) * c[2], gy = c[1], gz = std::cos(pp) * c[0] + std::sin(pp) * c[2];
  *lat = std::atan2(gz, std::hypot(gx, gy)) / kDeg;
  *lon = GeographicLib::Math::AngNormalize(std::atan2(gy, gx) / kDeg - p->stand_lon);
}

void geographic_to_rotated(const sl_projection *p, double lat, double lon, double *rlat, double *rlon)
{
  const double pp = p->pole_lat * kDeg, phi = lat * kDeg, lam = (lon + p->stand_lon) * kDeg;
  const double g[3] = {std::cos(phi) * std::cos(lam), std::cos(phi) * std::sin(lam), std::sin(phi)};
  const double cx = std::sin(pp) * g[0] + std::cos(pp) * g[2], cy = g[1], cz = -std::cos(pp) * g[0] + std::sin(pp) * g[2];
  *rlat = std::atan2(cz, std::hypot(cx, cy)) / kDeg;
  *rlon = GeographicLib::Math::AngNormalize(std::atan2(cy, cx) / kDeg + p->pole_lon);
}
}  // namespace

extern "C" int sl_projection_init(sl_projection *p, int map_proj, double truelat1, double truelat2,
                                  double stand_lon, double pole_lat, double pole_lon, char *why,
                                  unsigned long why_size)
{
  *p = sl_projection{};
  p->map_proj = map_proj;
  p->truelat1 = truelat1;
  p->truelat2 = std::isfinite(truelat2) ? truelat2 : truelat1;
  p->stand_lon = std::isfinite(stand_lon) ? stand_lon : 0.0;
  p->pole_lat = std::isfinite(pole_lat) ? pole_lat : 90.0;
  p->pole_lon = std::isfinite(pole_lon) ? pole_lon : 0.0;
  p->scale = 1.0;
  auto fail = [&](const char *text) {
    p->map_proj = 0;  // forward/reverse then give NAN rather than use invalid parameters
    if (why && why_size) std::snprintf(why, why_size, "%s", text);
    return 1;
  };
  const bool lat_ok = std::isfinite(truelat1) && std::fabs(truelat1) <= 90.0;
  try {
    switch (map_proj) {
    case SL_MAP_LAMBERT:
      if (!lat_ok || std::fabs(truelat1) >= 90.0 || std::fabs(p->truelat2) >= 90.0 || truelat1 * p->truelat2 < 0.0)
        return fail("Lambert conformal needs TRUELAT1/TRUELAT2 in one hemisphere, away from the poles");
      lambert_of(p);
      break;
    case SL_MAP_POLAR:
      if (!lat_ok || truelat1 == 0.0) return fail("polar stereographic needs TRUELAT1 away from the equator");
      // The sphere's polar stereographic scale is 2 k0 / (1 + sin|lat|); GeographicLib sets k0.
      {
        GeographicLib::PolarStereographic ps(SL_WRF_EARTH_RADIUS, 0.0, 1.0);
        ps.SetScale(std::fabs(truelat1), 1.0);
        p->scale = ps.CentralScale();
      }
      break;
    case SL_MAP_MERCATOR:
      if (!lat_ok || std::fabs(truelat1) >= 90.0) return fail("Mercator needs TRUELAT1 away from the poles");
      p->scale = std::cos(truelat1 * kDeg);  // the sphere's Mercator scale is k0 / cos(lat)
      p->x_period = 2.0 * M_PI * SL_WRF_EARTH_RADIUS * p->scale;
      break;
    case SL_MAP_LATLON:
      p->rotated = !(p->pole_lat == 90.0 && p->pole_lon == 0.0);
      p->x_period = 2.0 * M_PI * SL_WRF_EARTH_RADIUS;
      break;
    default: return fail("unsupported MAP_PROJ (Stormlight reads 1 Lambert, 2 polar stereographic, 3 Mercator, 6 latitude-longitude)");
    }
  } catch (const std::exception &e) {
    return fail(e.what());
  }
  return 0;
}

extern "C" void sl_projection_forward(const sl_projection *p, double lat, double lon, double *x, double *y)
{
  switch (p->map_proj) {
  case SL_MAP_LAMBERT: lambert_of(p).Forward(p->stand_lon, lat, lon, *x, *y); return;
  case SL_MAP_MERCATOR: mercator_of(p).Forward(p->stand_lon, lat, lon, *x, *y); return;
  case SL_MAP_POLAR: polar_of(p).Forward(p->truelat1 > 0.0, lat, lon - p->stand_lon, *x, *y); return;
  case SL_MAP_LATLON: {
    double rlat = lat, rlon = lon;
    if (p->rotated) geographic_to_rotated(p, lat, lon, &rlat, &rlon);
    *x = SL_WRF_EARTH_RADIUS * rlon * kDeg;
    *y = SL_WRF_EARTH_RADIUS * rlat * kDeg;
    return;
  }
  default: *x = *y = NAN;
  }
}

extern "C" void sl_projection_reverse(const sl_projection *p, double x, double y, double *lat, double *lon)
{
  switch (p->map_proj) {
  case SL_MAP_LAMBERT: lambert_of(p).Reverse(p->stand_lon, x, y, *lat, *lon); return;
  case SL_MAP_MERCATOR: mercator_of(p).Reverse(p->stand_lon, x, y, *lat, *lon); return;
  case SL_MAP_POLAR:
    polar_of(p).Reverse(p->truelat1 > 0.0, x, y, *lat, *lon);
    *lon = GeographicLib::Math::AngNormalize(*lon + p->stand_lon);
    return;
  case SL_MAP_LATLON: {
    const double rlat = y / SL_WRF_EARTH_RADIUS / kDeg, rlon = x / SL_WRF_EARTH_RADIUS / kDeg;
    if (p->rotated) rotated_to_geographic(p, rlat, rlon, lat, lon);
    else *lat = rlat, *lon = GeographicLib::Math::AngNormalize(rlon);
    return;
  }
  default: *lat = *lon = NAN;
  }
}

extern "C" void sl_enu_forward(double lat0, double lon0, double lat, double lon, double h, double enu[3])
{
  const GeographicLib::Geocentric sphere(SL_WRF_EARTH_RADIUS, 0.0);
  GeographicLib::LocalCartesian(lat0, lon0, 0.0, sphere).Forward(lat, lon, h, enu[0], enu[1], enu[2]);
}

extern "C" void sl_sphere_inverse(double lat1, double lon1, double lat2, double lon2, double *distance,
                                  double *azimuth)
{
  double azi2;
  GeographicLib::Geodesic(SL_WRF_EARTH_RADIUS, 0.0).Inverse(lat1, lon1, lat2, lon2, *distance, *azimuth, azi2);
}
