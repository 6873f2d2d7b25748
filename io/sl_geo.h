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

#ifdef __cplusplus
}
#endif
#endif
