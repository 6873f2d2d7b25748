/* Map projections used by WRF, through GeographicLib (io/geo.cpp). WRF's projections are on a
 * sphere of radius 6 370 000 m (WRF share/module_model_constants.F: EARTH_RADIUS_M). */
#ifndef SL_GEO_H
#define SL_GEO_H

#ifdef __cplusplus
extern "C" {
#endif

#define SL_WRF_EARTH_RADIUS 6370000.0

/* A Lambert conformal conic projection with standard parallels truelat1/2 and central meridian
 * stand_lon, whose plane coordinates are shifted so (0,0) is (center_lat, center_lon). */
typedef struct sl_lambert {
  double truelat1, truelat2, stand_lon;
  double x0, y0; /* plane coordinates of the centre before the shift */
} sl_lambert;

int sl_lambert_init(sl_lambert *p, double truelat1, double truelat2, double stand_lon, double center_lat,
                    double center_lon);
void sl_lambert_forward(const sl_lambert *p, double lat, double lon, double *x, double *y);
void sl_lambert_reverse(const sl_lambert *p, double x, double y, double *lat, double *lon);

/* WRF's MAP_PROJ codes. */
enum {
  SL_MAP_LAMBERT = 1,  /* Lambert conformal conic, one or two true latitudes */
  SL_MAP_POLAR = 2,    /* polar stereographic, true at TRUELAT1, either hemisphere */
  SL_MAP_MERCATOR = 3, /* Mercator, true at TRUELAT1 */
  SL_MAP_LATLON = 6    /* cylindrical equidistant latitude-longitude, optionally with a rotated pole */
};

/* One of WRF's projections on its sphere. Plane coordinates are metres with no false origin;
 * WRF's grid is uniform in them (spacing DX, DY). Lambert, polar stereographic and Mercator come
 * from GeographicLib (LambertConformalConic with the equator as standard parallel is Mercator;
 * PolarStereographic); GeographicLib has no rotated pole, so MAP_PROJ 6 is a few lines of
 * spherical rotation (WRF share/module_llxy.F rotate_coords) with x = R lambda, y = R phi in the
 * computational frame. */
typedef struct sl_projection {
  int map_proj;
  double truelat1, truelat2, stand_lon, pole_lat, pole_lon; /* degrees, as WRF's attributes */
  int rotated;        /* MAP_PROJ 6 with a pole other than (90, 0) */
  double x_period;    /* m: x repeats after this (longitude wraps); 0 when it does not */
  double scale;       /* GeographicLib k0 that makes the scale 1 on truelat1 */
} sl_projection;

/* Returns 0, or 1 with a reason in why (unsupported MAP_PROJ, a true latitude out of range). */
int sl_projection_init(sl_projection *p, int map_proj, double truelat1, double truelat2, double stand_lon,
                       double pole_lat, double pole_lon, char *why, unsigned long why_size);
void sl_projection_forward(const sl_projection *p, double lat, double lon, double *x, double *y);
void sl_projection_reverse(const sl_projection *p, double x, double y, double *lat, double *lon);

/* East-north-up coordinates (m) of (lat, lon, h) in the local tangent frame at (lat0, lon0) on
 * WRF's sphere (GeographicLib LocalCartesian with flattening 0). */
void sl_enu_forward(double lat0, double lon0, double lat, double lon, double h, double enu[3]);
/* Great-circle distance (m) on WRF's sphere and the azimuth at the first point (degrees,
 * clockwise from true north), GeographicLib Geodesic with flattening 0. */
void sl_sphere_inverse(double lat1, double lon1, double lat2, double lon2, double *distance, double *azimuth);

#ifdef __cplusplus
}
#endif
#endif
