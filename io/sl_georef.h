/* Georeferencing a WRF grid: its projection (from the file's attributes) checked against the
 * file's own XLAT/XLONG, and its placement in the renderer's world frame, the local east-north-up
 * frame of an origin on WRF's sphere. docs/GEOREFERENCING.md explains the choices and numbers. */
#ifndef SL_GEOREF_H
#define SL_GEOREF_H

#include "sl_geo.h"
#include "sl_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Above this disagreement (in grid cells) between the projection and XLAT/XLONG the placement
 * comes from XLAT/XLONG. A correctly described grid agrees to metres (WRF computes XLAT/XLONG
 * with the same spherical formulas and stores them as float32, ~1 m); a tenth of a cell is far
 * above that and below what the renderer resolves, so exceeding it means the attributes do not
 * describe the grid (wrong parameters, a regridded or re-projected file). */
#define SL_GEOREF_TRUST_CELLS 0.1

typedef struct sl_georef {
  sl_projection projection;
  int nx, ny;                     /* mass points */
  double dx, dy;                  /* m on the projection plane */
  double x0, y0;                  /* plane coordinates of mass point (0,0), least-squares fit to XLAT/XLONG */
  double max_error_deg;           /* largest |dlat| or |dlon| between the projected grid and XLAT/XLONG */
  double max_error_m;             /* the largest great-circle distance between them */
  int from_xlat;                  /* 1: the placement below comes from XLAT/XLONG, not the projection */
  double center_lat, center_lon;  /* degrees, at grid position ((nx-1)/2, (ny-1)/2) */
  double corner_lat[4], corner_lon[4]; /* mass points SW (0,0), SE, NE, NW */
  double ground_dx, ground_dy;    /* m on the sphere between neighbouring mass points at the centre */
  double grid_north_deg;          /* azimuth of the grid's +y axis at the centre, clockwise from true north */
  double map_factor_min, map_factor_max; /* plane over ground distance, over the grid (centre, edges, corners) */
  /* The world frame (sl_georef_place): local ENU at the origin, z up. */
  double origin_lat, origin_lon;
  double center_enu[3];           /* the grid centre at sea level, m */
  double frame_rotation_deg;      /* azimuth in the world frame of true north at the centre */
  char note[256];                 /* one line when the projection was not trusted, else empty */
  int placed;                     /* 1 when the grid has a place on the earth (sl_georef_build); 0 for
                                     a flat grid (sl_georef_flat) and for readers that build none */
} sl_georef;

/* Builds the projection from WRF's attributes and fits the grid to xlat/xlon (ny x nx, degrees).
 * Fails (naming path) for an unsupported MAP_PROJ or XLAT/XLONG out of range. A supported
 * MAP_PROJ whose parameters are missing or invalid is placed by XLAT/XLONG with a note (and
 * max_error_deg/_m NAN; sl_georef_grid_latlon is then not available and gives NAN). */
int sl_georef_build(sl_georef *g, int map_proj, double truelat1, double truelat2, double stand_lon,
                    double pole_lat, double pole_lon, int nx, int ny, double dx, double dy, const double *xlat,
                    const double *xlon, const char *path, sl_error *err);
/* A grid without a place on the earth (WRF's idealized runs, MAP_PROJ 0): flat, columns dx and dy
 * apart on the ground, +y the world's north, centred on the world origin; latitudes, corners and
 * the XLAT/XLONG check NAN, with a note that says so. */
void sl_georef_flat(sl_georef *g, int nx, int ny, double dx, double dy);
/* Latitude and longitude of grid position (i, j) (0-based, fractional allowed) by the projection. */
void sl_georef_grid_latlon(const sl_georef *g, double i, double j, double *lat, double *lon);
/* Places the grid in the ENU frame of (origin_lat, origin_lon); NAN places it at its own centre. */
void sl_georef_place(sl_georef *g, double origin_lat, double origin_lon);
/* A compass azimuth (clockwise from true north at the grid centre) as an azimuth from the grid's
 * +y axis: the renderer's volume axes are the grid's, so the sun is rotated into them. */
double sl_georef_grid_azimuth(const sl_georef *g, double compass_azimuth_deg);
/* Depth (m) of WRF's sphere below its tangent plane at horizontal distance r (m) from the
 * tangent point: R - sqrt(R^2 - r^2), written without cancellation; about r^2 / 2R. */
double sl_curvature_drop(double r);

/* The grid's columns by latitude and longitude (column_map.c): per mass point its latitude and
 * longitude (nx x ny, row-major from the south-west; not owned), and the world frame's x, y of
 * column (i, j) = origin + (i, j) spacing. */
typedef struct sl_column_map {
  int nx, ny;
  const double *lat, *lon;
  double origin[2], spacing[2];
} sl_column_map;
void sl_column_map_init(sl_column_map *m, int nx, int ny, const double *lat, const double *lon, const double origin[2],
                        const double spacing[2]);
/* The latitude and longitude at fractional indices (fi, fj): bilinear within the cell. */
void sl_column_map_lonlat(const sl_column_map *m, double fi, double fj, double *lon, double *lat);
/* The fractional indices of (lat, lon), by Newton's method on the bilinear map from the nearest
 * column; 0 when the point lies outside the lattice (or the map has no columns). */
int sl_column_map_to_grid(const sl_column_map *m, double lat, double lon, double *fi, double *fj);
void sl_column_map_world(const sl_column_map *m, double fi, double fj, double *x, double *y);
void sl_column_map_range(const sl_column_map *m, double *lon0, double *lon1, double *lat0, double *lat1);

#ifdef __cplusplus
}
#endif
#endif
