/* Writing WRF-style wrfout NetCDF files (used by the synthetic-storm generator, so synthetic
 * and real storms travel the same reader path). */
#ifndef SL_WRF_WRITE_H
#define SL_WRF_WRITE_H

#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Arrays are C-ordered [time][level][south_north][west_east]; PH/PHB have nz+1 levels. */
typedef struct sl_wrf_fields {
  int nx, ny, nz, ntimes;
  double dx, dy;                           /* m */
  int map_proj;                            /* WRF MAP_PROJ code */
  double truelat1, truelat2, stand_lon, cen_lat, cen_lon, moad_cen_lat;
  int mp_physics;
  const char *title;
  const char (*times)[20];                 /* "YYYY-MM-DD_hh:mm:ss" per time */
  const float *qcloud, *qrain, *qice, *qsnow, *qvapor; /* kg/kg; NULL omits the variable */
  const float *p, *pb, *t, *ph, *phb;      /* Pa, Pa, K (theta - 300), m2/s2, m2/s2 */
  const float *hgt, *xlat, *xlong;         /* [time][south_north][west_east] */
} sl_wrf_fields;

/* Writes netCDF-4 with deflate, to a temporary name renamed on success. */
int sl_wrf_write(const char *path, const sl_wrf_fields *f, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
