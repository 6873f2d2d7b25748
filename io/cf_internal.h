/* What the CF/CM1 reader's two halves share: the file's layout (cf_read.c, from the attributes
 * and coordinates) that the level reader (cf_load.c) streams the grid by. Not a public header. */
#ifndef SL_CF_INTERNAL_H
#define SL_CF_INTERNAL_H

#include <netcdf.h>

#include "storm_internal.h"

#define CF_RD 287.0          /* J/(kg K), as WRF and CM1 */
#define CF_RV 461.6
#define CF_EARTH_RADIUS 6371000.0 /* m: spacing of latitude-longitude grids on a sphere */

/* Which dimension is which, and the coordinates that size the grid. */
typedef struct cf_layout {
  int cm1;
  char ref[64];                 /* a hydrometeor variable that fixes the dimensions */
  char dim[4][NC_MAX_NAME + 1]; /* time, z, y, x ("" time when the variable has none) */
  char coord[4][NC_MAX_NAME + 1]; /* their coordinate variables: CM1's xh/yh/zh, else CF's dim names */
  size_t len[4];
  double x_to_m, y_to_m, z_to_m;
  double dx, dy;
  int flip[4];                  /* per slot: the coordinate decreases (north-to-south latitudes,
                                   levels from the top), so the reader reverses that axis */
  double lat0;                  /* degrees, for latitude-longitude grids */
  double z_to_pa;               /* > 0: z is pressure levels (Pa per unit); heights then come from a
                                   geopotential on the same grid */
  int hybrid_height;            /* z is atmosphere_hybrid_height_coordinate: z = a + b orog */
  int altitude_3d;              /* z is model levels with a 3-D altitude on the same grid */
  char terms[3][NC_MAX_NAME + 1]; /* hybrid height's formula_terms a, b, orog */
} cf_layout;

/* What a variable measures, for its units. */
typedef enum cf_quantity { CF_MASS_FRACTION, CF_PRESSURE, CF_TEMPERATURE, CF_DENSITY, CF_HEIGHT, CF_NUMBER_PER_MASS } cf_quantity;

/* A variable by CM1 name (when cm1) or by CF standard_name, into out; 0 when there is none. */
int cf_find_var(const sl_nc *f, int cm1, const char *cm1_name, const char *standard_name, char *out);

/* A units string without spaces, '*' and '^' (so "kg kg-1", "kg kg**-1" and "kg kg^-1" read alike). */
void cf_units_squeezed(const char *in, char *out, size_t cap);

/* SI value = value * scale + offset for quantity q in `units`: 1 when known, 0 when not, -1 for
 * an empty string (no units: read as SI). Geopotential (m2 s-2) reads as a height through WMO's
 * standard gravity: geopotential height, as WRF's (PH+PHB)/g. */
int cf_unit_factor(cf_quantity q, const char *units, double *scale, double *offset);

/* The file's layout (which dimension is which, spacing, vertical coordinate), and what info says
 * of it (grid size, spacing); a one-line error naming the file when it is not a storm grid. */
int cf_layout_of(const sl_nc *f, cf_layout *L, sl_storm_info *info, sl_error *err);

/* The x and y coordinate values of the subset's centre; 0 when they cannot be read. */
int cf_centre_coords(const sl_nc *f, const cf_layout *L, const sl_subset *s, double *x, double *y);

/* The latitude and longitude of a projected grid's centre column into frame (through its
 * grid_mapping); left NaN when the mapping does not place it. */
void cf_projected_centre(const sl_nc *f, const cf_layout *L, const sl_storm_info *info, const sl_subset *s,
                         sl_storm_frame *frame);

#endif
