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
