/* CF-NetCDF and CM1 storm files. CM1 (Bryan's cloud model) writes xh/yh/zh in km and the mixing
 * ratios qc qr qi qs qg with pressure prs and potential temperature th; generic CF files name their
 * hydrometeors by standard_name (mass_fraction_of_..._in_air) and their projection by grid_mapping.
 * Both stream through the same level-by-level remap as WRF (remap.c). */
#include <ctype.h>
#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "sl_geo.h"
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

static int find_var(const sl_nc *f, int cm1, const char *cm1_name, const char *standard_name, char *out);

static int coord_values(const sl_nc *f, const char *dim, size_t n, double *v, char *units, size_t ucap,
                        char *stdname, size_t scap)
{
  int id;
  if (nc_inq_varid(f->id, dim, &id) != NC_NOERR) return 0;
  sl_nc_attr_text(f, id, "units", units, ucap);
  sl_nc_attr_text(f, id, "standard_name", stdname, scap);
  /* A coordinate variable is 1-D along its own dimension; anything else named like one (a 2-D
   * field, a shorter axis) is not read as coordinates: start/count below describe one dimension. */
  if (!sl_nc_var_is_1d(f, id, n, NULL)) return 0;
  size_t start = 0;
  return v ? nc_get_vara_double(f->id, id, &start, &n, v) == NC_NOERR : 1;
}

/* Metres per unit of a length unit; 0 when not a length (degrees: handled by the caller). */
static double length_scale(const char *units)
{
  if (strcmp(units, "m") == 0 || strcmp(units, "meter") == 0 || strcmp(units, "meters") == 0 ||
      strcmp(units, "metre") == 0 || strcmp(units, "metres") == 0)
    return 1.0;
  if (strcmp(units, "km") == 0 || strcmp(units, "kilometer") == 0 || strcmp(units, "kilometers") == 0) return 1000.0;
  return 0.0;
}

static int is_degrees(const char *units) { return strncmp(units, "degree", 6) == 0; }

/* What a variable measures, for its units. */
typedef enum cf_quantity { CF_MASS_FRACTION, CF_PRESSURE, CF_TEMPERATURE, CF_DENSITY, CF_HEIGHT, CF_NUMBER_PER_MASS } cf_quantity;

/* A units string without spaces, '*' and '^' (so "kg kg-1", "kg kg**-1" and "kg kg^-1" read alike). */
static void cf_units_squeezed(const char *in, char *out, size_t cap)
{
  size_t n = 0;
  for (; *in && n + 1 < cap; ++in)
    if (*in != ' ' && *in != '*' && *in != '^') out[n++] = *in;
  out[n] = '\0';
}

/* SI value = value * scale + offset for quantity q in `units`: 1 when known, 0 when not, -1 for
 * an empty string (no units: read as SI). Geopotential (m2 s-2) reads as a height through WMO's
 * standard gravity: geopotential height, as WRF's (PH+PHB)/g. */
static int cf_unit_factor(cf_quantity q, const char *units, double *scale, double *offset)
{
  static const struct {
    cf_quantity q;
    const char *units;
    double scale, offset;
  } known[] = {
      {CF_MASS_FRACTION, "kgkg-1", 1, 0},   {CF_MASS_FRACTION, "kg/kg", 1, 0},  {CF_MASS_FRACTION, "1", 1, 0},
      {CF_MASS_FRACTION, "gkg-1", 1e-3, 0}, {CF_MASS_FRACTION, "g/kg", 1e-3, 0},
      {CF_MASS_FRACTION, "g/g", 1, 0},      {CF_MASS_FRACTION, "gg-1", 1, 0},     {CF_PRESSURE, "Pa", 1, 0},
      {CF_PRESSURE, "hPa", 100, 0},         {CF_PRESSURE, "mbar", 100, 0},        {CF_PRESSURE, "millibar", 100, 0},
      {CF_PRESSURE, "millibars", 100, 0},   {CF_PRESSURE, "mb", 100, 0},          {CF_PRESSURE, "kPa", 1000, 0},
      {CF_TEMPERATURE, "K", 1, 0},
      {CF_TEMPERATURE, "kelvin", 1, 0},     {CF_TEMPERATURE, "degK", 1, 0},       {CF_TEMPERATURE, "deg_K", 1, 0},
      {CF_TEMPERATURE, "degC", 1, 273.15},  {CF_TEMPERATURE, "deg_C", 1, 273.15}, {CF_TEMPERATURE, "celsius", 1, 273.15},
      {CF_TEMPERATURE, "degree_Celsius", 1, 273.15}, {CF_TEMPERATURE, "degrees_Celsius", 1, 273.15},
      {CF_DENSITY, "kgm-3", 1, 0},          {CF_DENSITY, "kg/m3", 1, 0},          {CF_DENSITY, "gm-3", 1e-3, 0},
      {CF_DENSITY, "g/m3", 1e-3, 0},        {CF_HEIGHT, "m", 1, 0},               {CF_HEIGHT, "gpm", 1, 0},
      {CF_HEIGHT, "meter", 1, 0},           {CF_HEIGHT, "meters", 1, 0},          {CF_HEIGHT, "metre", 1, 0},
      {CF_HEIGHT, "metres", 1, 0},          {CF_HEIGHT, "km", 1000, 0},           {CF_HEIGHT, "m2s-2", 1 / 9.80665, 0},
      {CF_HEIGHT, "m2/s2", 1 / 9.80665, 0},
      /* Number mixing ratios of two-moment schemes (CM1 writes "#/kg"). */
      {CF_NUMBER_PER_MASS, "#/kg", 1, 0},   {CF_NUMBER_PER_MASS, "kg-1", 1, 0},   {CF_NUMBER_PER_MASS, "#kg-1", 1, 0},
      {CF_NUMBER_PER_MASS, "1/kg", 1, 0},   {CF_NUMBER_PER_MASS, "/kg", 1, 0},    {CF_NUMBER_PER_MASS, "1kg-1", 1, 0},
      {CF_NUMBER_PER_MASS, "#/g", 1e3, 0},  {CF_NUMBER_PER_MASS, "g-1", 1e3, 0},
  };
  char squeezed[128];
  cf_units_squeezed(units, squeezed, sizeof squeezed);
  if (!squeezed[0]) return -1;
  for (size_t i = 0; i < sizeof known / sizeof known[0]; ++i)
    if (known[i].q == q && strcasecmp(known[i].units, squeezed) == 0) {
      *scale = known[i].scale, *offset = known[i].offset;
      return 1;
    }
  return 0;
}

/* Horizontal spacing (m) of coordinate `dim`, uniform within 1 %. */
static int axis_spacing(const sl_nc *f, const char *dim, size_t n, int is_x, int cm1, double *scale, double *spacing,
                        double *lat_mid, int *flip, sl_error *err)
{
  double *v = malloc(n * sizeof(double));
  char units[64] = "", stdname[128] = "";
  if (!v) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", f->path);
  int rc = SL_OK;
  if (!coord_values(f, dim, n, v, units, sizeof units, stdname, sizeof stdname)) {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: no 1-D coordinate variable '%s' to size the grid", f->path, dim);
    goto done;
  }
  if (cm1 && !units[0]) snprintf(units, sizeof units, "km");
  *scale = length_scale(units);
  if (n < 2) {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: coordinate '%s' has %zu point: a grid needs at least 2 along x and y", f->path,
                 dim, n);
    goto done;
  }
  /* A decreasing axis (latitudes from north to south, as ERA5 and GFS write them) is read
   * reversed: the spacing is the step's size. */
  double step = (v[n - 1] - v[0]) / (double)(n - 1);
  for (size_t i = 1; i < n && !rc; ++i)
    if (fabs((v[i] - v[i - 1]) - step) > 0.01 * fabs(step))
      rc = sl_fail(err, SL_ERR_FORMAT, "%s: coordinate '%s' is not evenly spaced", f->path, dim);
  if (!rc && !(fabs(step) > 0.0))
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: coordinate '%s' does not change (all %zu values equal)", f->path, dim, n);
  if (rc) goto done;
  *flip = step < 0.0;
  step = fabs(step);
  if (*scale > 0.0) {
    *spacing = step * *scale;
  } else if (is_degrees(units) && strncmp(stdname, "projection_", 11) == 0) {
    rc = sl_fail(err, SL_ERR_FORMAT,
                 "%s: coordinate '%s' is a %s in '%s': projected coordinates are lengths (m or km), not degrees",
                 f->path, dim, stdname, units);
  } else if (is_degrees(units)) {
    /* Latitude-longitude: metres on a sphere at the domain's middle latitude (placement on the
     * ellipsoid is the georeferencing's business). */
    if (!is_x) *lat_mid = 0.5 * (v[0] + v[n - 1]);
    *spacing = step * M_PI / 180.0 * CF_EARTH_RADIUS;
  } else {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: coordinate '%s' has units '%s', not a length or degrees", f->path, dim, units);
  }
done:
  free(v);
  return rc;
}

/* The CF axis a coordinate variable declares ('X', 'Y', 'Z' or 'T'), by its axis attribute, its
 * standard_name or its units (degrees_east/north, a time "since"); 0 when it says nothing. */
static char cf_axis_of(const sl_nc *f, const char *coord)
{
  int id;
  if (nc_inq_varid(f->id, coord, &id) != NC_NOERR) return 0;
  char axis[8] = "", std[128] = "", units[128] = "";
  sl_nc_attr_text(f, id, "axis", axis, sizeof axis);
  if (strlen(axis) == 1 && strchr("XYZTxyzt", axis[0])) return (char)(axis[0] & ~0x20);
  sl_nc_attr_text(f, id, "standard_name", std, sizeof std);
  static const struct {
    const char *name;
    char axis;
  } names[] = {{"projection_x_coordinate", 'X'}, {"longitude", 'X'}, {"grid_longitude", 'X'},
               {"projection_y_coordinate", 'Y'}, {"latitude", 'Y'},  {"grid_latitude", 'Y'},
               {"height", 'Z'},                  {"altitude", 'Z'},  {"time", 'T'}};
  for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
    if (strcmp(std, names[i].name) == 0) return names[i].axis;
  sl_nc_attr_text(f, id, "units", units, sizeof units);
  if (strcasecmp(units, "degrees_east") == 0 || strcasecmp(units, "degree_east") == 0 ||
      strcasecmp(units, "degree_E") == 0 || strcasecmp(units, "degrees_E") == 0)
    return 'X';
  if (strcasecmp(units, "degrees_north") == 0 || strcasecmp(units, "degree_north") == 0 ||
      strcasecmp(units, "degree_N") == 0 || strcasecmp(units, "degrees_N") == 0)
    return 'Y';
  if (strstr(units, " since ")) return 'T';
  return 0;
}

/* The values of `name` at the first and last index of dimension `zdim` (length n), at index 0 of
 * every other dimension. 0 when it cannot be read or either is not finite. */
static int level_ends(const sl_nc *f, const char *name, const char *zdim, size_t n, double ends[2])
{
  int id, nd, dims[NC_MAX_VAR_DIMS], at = -1;
  if (nc_inq_varid(f->id, name, &id) != NC_NOERR || nc_inq_varndims(f->id, id, &nd) != NC_NOERR || nd < 1 ||
      nd > 4 || nc_inq_vardimid(f->id, id, dims) != NC_NOERR)
    return 0;
  size_t index[4] = {0, 0, 0, 0}, len;
  for (int d = 0; d < nd; ++d) {
    char dname[NC_MAX_NAME + 1];
    if (nc_inq_dim(f->id, dims[d], dname, &len) == NC_NOERR && strcmp(dname, zdim) == 0 && len == n) at = d;
  }
  if (at < 0) return 0;
  if (nc_get_var1_double(f->id, id, index, &ends[0]) != NC_NOERR) return 0;
  index[at] = n - 1;
  if (nc_get_var1_double(f->id, id, index, &ends[1]) != NC_NOERR) return 0;
  return isfinite(ends[0]) && isfinite(ends[1]);
}

static int cf_layout_of(const sl_nc *f, cf_layout *L, sl_storm_info *info, sl_error *err)
{
  memset(L, 0, sizeof *L);
  L->cm1 = sl_nc_has_var(f, "xh") && sl_nc_has_var(f, "yh") && sl_nc_has_var(f, "zh");
  /* The hydrometeor variables: CM1 names or CF standard names. */
  int nvars;
  nc_inq_nvars(f->id, &nvars);
  info->nspecies = 0;
  for (int id = 0; id < nvars && info->nspecies < SL_MAX_SPECIES; ++id) {
    char name[NC_MAX_NAME + 1], stdname[256] = "";
    nc_inq_varname(f->id, id, name);
    sl_nc_attr_text(f, id, "standard_name", stdname, sizeof stdname);
    if (sl_species_cf_match(name, stdname, L->cm1, &info->species[info->nspecies])) info->nspecies++;
  }
  if (info->nspecies == 0)
    return sl_fail(err, SL_ERR_FORMAT,
                   "%s: no hydrometeor variables (not a WRF, CM1 or CF storm file: no QCLOUD..., qc..., "
                   "standard_name mass_fraction_of_..._in_air, or ECMWF clwc...)",
                   f->path);
  snprintf(L->ref, sizeof L->ref, "%s", info->species[0].variable);
  int varid, nd, dimids[NC_MAX_VAR_DIMS], unlimited = -1;
  nc_inq_varid(f->id, L->ref, &varid);
  nc_inq_varndims(f->id, varid, &nd);
  nc_inq_vardimid(f->id, varid, dimids);
  nc_inq_unlimdim(f->id, &unlimited);
  if (nd != 3 && nd != 4)
    return sl_fail(err, SL_ERR_FORMAT, "%s: '%s' has %d dimensions, expected (time,) z, y, x", f->path, L->ref, nd);
  for (int d = 0; d < nd; ++d) {
    const int slot = d + 4 - nd;
    nc_inq_dim(f->id, dimids[d], L->dim[slot], &L->len[slot]);
  }
  if (nd == 3) L->len[0] = 1;
  for (int d = 0; d < 4; ++d) snprintf(L->coord[d], sizeof L->coord[d], "%s", L->dim[d]);
  if (L->cm1) {
    snprintf(L->coord[1], sizeof L->coord[1], "zh");
    snprintf(L->coord[2], sizeof L->coord[2], "yh");
    snprintf(L->coord[3], sizeof L->coord[3], "xh");
  }
  /* The reader takes the dimensions by position, (time,) z, y, x; where the coordinates say which
   * axis they are, they must agree, or a (time, z, x, y) variable on a square grid would be read
   * with x and y swapped without a word. */
  for (int slot = 4 - nd; slot < 4 && !L->cm1; ++slot) {
    const char got = cf_axis_of(f, L->coord[slot]);
    if (got && got != "TZYX"[slot]) {
      char order[4 * (NC_MAX_NAME + 2)] = "";
      for (int d = 4 - nd; d < 4; ++d) {
        if (d > 4 - nd) strcat(order, ", ");
        strcat(order, L->dim[d]);
      }
      return sl_fail(err, SL_ERR_FORMAT,
                     "%s: '%s' has dimensions (%s): coordinate '%s' is the %c axis where the reader expects %c; "
                     "expected (time,) z, y, x",
                     f->path, L->ref, order, L->coord[slot], got, "TZYX"[slot]);
    }
  }
  for (int d = 0; d < 4; ++d)
    if (L->len[d] == 0 || L->len[d] > 100000)
      return sl_fail(err, SL_ERR_DATA, "%s: dimension '%s' has %s length %zu", f->path, L->dim[d],
                     L->len[d] == 0 ? "zero" : "an absurd", L->len[d]);
  int rc;
  if ((rc = axis_spacing(f, L->coord[3], L->len[3], 1, L->cm1, &L->x_to_m, &L->dx, &L->lat0, &L->flip[3], err)) ||
      (rc = axis_spacing(f, L->coord[2], L->len[2], 0, L->cm1, &L->y_to_m, &L->dy, &L->lat0, &L->flip[2], err)))
    return rc;
  if (L->x_to_m == 0.0) L->dx *= cos(L->lat0 * M_PI / 180.0);
  /* Vertical: a height (m or km, up); or, with heights by column read at load, pressure levels (a
   * geopotential on the same grid), hybrid height (a + b orog) or any levels with a 3-D altitude. */
  char zunits[64] = "", zstd[128] = "", positive[16] = "";
  coord_values(f, L->coord[1], L->len[1], NULL, zunits, sizeof zunits, zstd, sizeof zstd);
  if (L->cm1 && !zunits[0]) snprintf(zunits, sizeof zunits, "km");
  int zid;
  if (nc_inq_varid(f->id, L->coord[1], &zid) == NC_NOERR) sl_nc_attr_text(f, zid, "positive", positive, sizeof positive);
  L->z_to_m = length_scale(zunits);
  if (!L->cm1 && strcmp(zstd, "atmosphere_hybrid_height_coordinate") == 0) {
    /* formula_terms "a: VAR b: VAR orog: VAR" (CF appendix D) */
    char terms[512] = "";
    sl_nc_attr_text(f, zid, "formula_terms", terms, sizeof terms);
    static const char *const keys[3] = {"a:", "b:", "orog:"};
    for (int t = 0; t < 3; ++t) {
      const char *at = strstr(terms, keys[t]);
      /* a key starts the string or follows white space (not the tail of another word: "ta:") */
      while (at && at != terms && !isspace((unsigned char)at[-1])) at = strstr(at + 1, keys[t]);
      if (!at || sscanf(at + strlen(keys[t]), " %256s", L->terms[t]) != 1 || !sl_nc_has_var(f, L->terms[t]))
        return sl_fail(err, SL_ERR_FORMAT,
                       "%s: hybrid height coordinate '%s' needs formula_terms naming a, b and orog variables (has "
                       "'%s')",
                       f->path, L->coord[1], terms);
    }
    L->hybrid_height = 1;
  }
  double pa = 0.0, unused;
  if (!L->cm1 && cf_unit_factor(CF_PRESSURE, zunits, &pa, &unused) == 1) L->z_to_pa = pa;
  else if (!L->cm1 && strcmp(zstd, "air_pressure") == 0 && !zunits[0]) L->z_to_pa = 1.0;
  /* Model levels of any other kind (sigma, level numbers) are read where a 3-D altitude gives
   * their heights. */
  char alt[NC_MAX_NAME + 1];
  if (!L->hybrid_height && !(L->z_to_m > 0.0) && L->z_to_pa == 0.0 && !L->cm1 && find_var(f, 0, "", "altitude", alt))
    L->altitude_3d = 1;
  /* A length counted downward is a depth; pressure and model coordinates say "down" as they like. */
  if (L->z_to_m > 0.0 && !L->hybrid_height && strcasecmp(positive, "down") == 0)
    return sl_fail(err, SL_ERR_FORMAT,
                   "%s: vertical coordinate '%s' has positive = \"down\" (a depth): only heights, positive up, are read",
                   f->path, L->coord[1]);
  if (!(L->z_to_m > 0.0) && L->z_to_pa == 0.0 && !L->hybrid_height && !L->altitude_3d)
    return sl_fail(err, SL_ERR_FORMAT,
                   "%s: vertical coordinate '%s' (units '%s') is neither a height in m or km, a pressure nor a "
                   "hybrid height, and no variable has standard_name altitude: its heights are unknown",
                   f->path, L->coord[1], zunits);
  /* Levels listed from the top down (heights decreasing, pressures increasing) are read reversed:
   * judged by the heights themselves where the coordinate is not one (hybrid height: its a term;
   * other model levels: the first column's altitude; sigma and ECMWF's level numbers count down). */
  double ends[2];
  const char *judge = L->hybrid_height ? L->terms[0] : L->altitude_3d ? alt : L->coord[1];
  if (L->len[1] > 1 && level_ends(f, judge, L->dim[1], L->len[1], ends))
    L->flip[1] = L->z_to_pa > 0.0 ? ends[1] > ends[0] : ends[1] < ends[0];
  return SL_OK;
}

/* CF grid_mapping to WRF's MAP_PROJ codes (the georeferencing speaks WRF). */
static int cf_projection(const sl_nc *f, const cf_layout *L, sl_storm_info *info, sl_error *err)
{
  int varid, gid;
  char gm[NC_MAX_NAME + 1] = "", name[128] = "";
  nc_inq_varid(f->id, L->ref, &varid);
  info->truelat1 = info->truelat2 = info->stand_lon = NAN;
  if (!sl_nc_attr_text(f, varid, "grid_mapping", gm, sizeof gm) || !gm[0]) {
    info->map_proj = L->x_to_m == 0.0 ? 6 : 0;
    return SL_OK;
  }
  if (nc_inq_varid(f->id, gm, &gid) != NC_NOERR)
    return sl_fail(err, SL_ERR_FORMAT, "%s: grid_mapping variable '%s' is missing", f->path, gm);
  sl_nc_attr_text(f, gid, "grid_mapping_name", name, sizeof name);
  if (strcmp(name, "lambert_conformal_conic") == 0) info->map_proj = 1;
  else if (strcmp(name, "polar_stereographic") == 0) info->map_proj = 2;
  else if (strcmp(name, "mercator") == 0) info->map_proj = 3;
  else if (strcmp(name, "latitude_longitude") == 0 || strcmp(name, "rotated_latitude_longitude") == 0) info->map_proj = 6;
  else
    return sl_fail(err, SL_ERR_FORMAT,
                   "%s: unsupported projection grid_mapping_name '%s' (supported: lambert_conformal_conic, "
                   "polar_stereographic, mercator, latitude_longitude, rotated_latitude_longitude)",
                   f->path, name);
  double par[2] = {NAN, NAN};
  size_t n = 0;
  if (nc_inq_attlen(f->id, gid, "standard_parallel", &n) == NC_NOERR && n >= 1 && n <= 2) {
    nc_get_att_double(f->id, gid, "standard_parallel", par);
    info->truelat1 = par[0];
    info->truelat2 = n == 2 ? par[1] : par[0];
  }
  info->stand_lon = sl_nc_attr_double(
      f, gid, "longitude_of_central_meridian",
      sl_nc_attr_double(f, gid, "straight_vertical_longitude_from_pole",
                        sl_nc_attr_double(f, gid, "longitude_of_projection_origin", NAN)));
  /* Mercator's true latitude may be given as its scale at the equator instead (k0 = cos phi_ts). */
  if (info->map_proj == 3 && !isfinite(info->truelat1)) {
    const double k0 = sl_nc_attr_double(f, gid, "scale_factor_at_projection_origin", 1.0);
    info->truelat1 = info->truelat2 = k0 > 0.0 && k0 <= 1.0 ? acos(k0) * 180.0 / M_PI : NAN;
  }
  return SL_OK;
}

/* The latitude and longitude of a projected CF grid's centre column, from its grid_mapping's
 * origin (latitude_of_projection_origin, the central longitude, false_easting/northing: CF's x
 * and y are the projection's plane coordinates from that origin, false easting and northing
 * included, all in the coordinates' units).
 * Leaves NaN where the file gives no grid_mapping or no origin. On WRF's sphere, as every
 * projection here; the centre places the sun and the air mass, for which a sphere serves. */
/* The coordinate value (in the file's units) at the middle of `coord`'s n read points, from first
 * every stride-th: grid position (n - 1) / 2, between two points when n is even (the grid's
 * centre, as the volume and the WRF reader place it; a reversed axis has the same middle). 0 when
 * the coordinate cannot be read there. */
static int cf_middle_coord(const sl_nc *f, const char *coord, size_t first, size_t n, size_t stride, double *value)
{
  const size_t lo = first + (n - 1) / 2 * stride, hi = first + n / 2 * stride;
  double a, b;
  int id;
  if (nc_inq_varid(f->id, coord, &id) != NC_NOERR || !sl_nc_var_is_1d(f, id, hi + 1, NULL) ||
      nc_get_var1_double(f->id, id, &lo, &a) != NC_NOERR || nc_get_var1_double(f->id, id, &hi, &b) != NC_NOERR)
    return 0;
  *value = 0.5 * (a + b);
  return 1;
}

/* The x and y coordinate values of the subset's centre; 0 when they cannot be read. */
static int cf_centre_coords(const sl_nc *f, const cf_layout *L, const sl_subset *s, double *x, double *y)
{
  return cf_middle_coord(f, L->coord[3], (size_t)s->i0, (size_t)s->nx, (size_t)s->stride, x) &&
         cf_middle_coord(f, L->coord[2], (size_t)s->j0, (size_t)s->ny, (size_t)s->stride, y);
}

static void cf_projected_centre(const sl_nc *f, const cf_layout *L, const sl_storm_info *info, const sl_subset *s,
                                sl_storm_frame *frame)
{
  int varid, gid;
  char gm[NC_MAX_NAME + 1] = "";
  if (info->map_proj != 1 && info->map_proj != 2 && info->map_proj != 3) return;
  if (nc_inq_varid(f->id, L->ref, &varid) != NC_NOERR || !sl_nc_attr_text(f, varid, "grid_mapping", gm, sizeof gm) ||
      nc_inq_varid(f->id, gm, &gid) != NC_NOERR)
    return;
  const double lat0 = sl_nc_attr_double(f, gid, "latitude_of_projection_origin", info->map_proj == 3 ? 0.0 : NAN);
  const double fe = sl_nc_attr_double(f, gid, "false_easting", 0.0), fn = sl_nc_attr_double(f, gid, "false_northing", 0.0);
  sl_projection p;
  char why[200];
  double x, y, x0, y0, lat, lon;
  if (!isfinite(lat0) || !isfinite(info->stand_lon) ||
      sl_projection_init(&p, info->map_proj, info->truelat1, info->truelat2, info->stand_lon, 90.0, 0.0, why,
                         sizeof why) ||
      !cf_centre_coords(f, L, s, &x, &y))
    return;
  sl_projection_forward(&p, lat0, info->stand_lon, &x0, &y0);
  sl_projection_reverse(&p, x0 + (x - fe) * L->x_to_m, y0 + (y - fn) * L->y_to_m, &lat, &lon);
  if (fabs(lat) <= 90.0 && isfinite(lon)) frame->center_lat = lat, frame->center_lon = lon - 360.0 * floor((lon + 180.0) / 360.0);
}

/* Times from a CF time coordinate "<unit> since <date>" in its calendar (CF 4.4.1; climate
 * models count in noleap or 360_day years, and read as Gregorian their dates drift by weeks);
 * CM1's bare "seconds" stays index-only, and so does a calendar this reader does not know (the
 * render then asks for a date). So do "months" and "years since": UDUNITS makes them mean
 * months and years (30.44 and 365.24 days), whose multiples land at arbitrary hours, and the
 * sun cannot be placed from a monthly or yearly time anyway. */
static void cf_times(const sl_nc *f, const cf_layout *L, sl_storm_info *info)
{
  int id;
  char units[128] = "", calendar[64] = "";
  if (!L->dim[0][0] || nc_inq_varid(f->id, L->dim[0], &id) != NC_NOERR ||
      !sl_nc_var_is_1d(f, id, (size_t)info->ntimes, NULL))
    return;
  sl_nc_attr_text(f, id, "units", units, sizeof units);
  sl_nc_attr_text(f, id, "calendar", calendar, sizeof calendar);
  snprintf(info->calendar, sizeof info->calendar, "%s", calendar[0] ? calendar : "standard");
  const sl_calendar cal = sl_calendar_named(calendar);
  const char *since = strstr(units, " since ");
  double per = 0;
  if (strncmp(units, "second", 6) == 0) per = 1;
  else if (strncmp(units, "minute", 6) == 0) per = 60;
  else if (strncmp(units, "hour", 4) == 0) per = 3600;
  else if (strncmp(units, "day", 3) == 0) per = 86400;
  int base[6] = {0};
  if (!since && per > 0) {
    /* Elapsed time without a date (CM1): kept as seconds, for the series' order and --date. */
    double *v = malloc((size_t)info->ntimes * sizeof(double));
    size_t start = 0, count = (size_t)info->ntimes;
    if (v && nc_get_vara_double(f->id, id, &start, &count, v) == NC_NOERR) {
      info->has_elapsed = 1;
      for (int t = 0; t < info->ntimes; ++t) {
        info->elapsed_s[t] = v[t] * per;
        if (!isfinite(info->elapsed_s[t])) info->has_elapsed = 0;
      }
    }
    free(v);
    return;
  }
  if (!since || per == 0 || cal == SL_CAL_UNKNOWN ||
      sscanf(since + 7, "%d-%d-%d%*[ _T]%d:%d:%d", &base[0], &base[1], &base[2], &base[3], &base[4], &base[5]) < 3 ||
      !sl_calendar_valid(cal, base))
    return;
  double *v = malloc((size_t)info->ntimes * sizeof(double));
  size_t start = 0, count = (size_t)info->ntimes;
  if (v && nc_get_vara_double(f->id, id, &start, &count, v) == NC_NOERR) {
    int ok = 1;
    for (int t = 0; t < info->ntimes && ok; ++t) {
      int at[6], sun[6];
      ok = sl_calendar_add_seconds(cal, base, v[t] * per, at);
      if (!ok) break;
      sl_calendar_sun_date(cal, at, sun);
      sl_calendar_format(at, info->times[t]);
      sl_calendar_format(sun, info->sun_times[t]);
    }
    info->has_times = ok; /* absurd offsets: index-only times, as without a time coordinate */
  }
  free(v);
}

/* What `info` says of the vertical: height levels, hybrid height, model levels with an altitude,
 * or pressure levels and the variable that gives their heights. */
static void cf_vertical_words(const sl_nc *f, const cf_layout *L, sl_storm_info *info)
{
  char alt[NC_MAX_NAME + 1] = "";
  if (L->hybrid_height) {
    snprintf(info->vertical, sizeof info->vertical, "hybrid height '%.48s' = %.48s + %.48s * %.48s", L->coord[1],
             L->terms[0], L->terms[1], L->terms[2]);
    return;
  }
  if (L->altitude_3d && find_var(f, 0, "", "altitude", alt)) {
    snprintf(info->vertical, sizeof info->vertical, "model levels '%.64s', heights from altitude '%.64s'", L->coord[1],
             alt);
    return;
  }
  if (L->z_to_pa == 0.0) {
    snprintf(info->vertical, sizeof info->vertical, "height levels '%.64s'%s", L->coord[1],
             L->cm1 && !L->flip[1] && sl_nc_has_var(f, "zf") ? " (interfaces zf)" : "");
    return;
  }
  double ends[2] = {NAN, NAN};
  level_ends(f, L->coord[1], L->dim[1], L->len[1], ends);
  char name[NC_MAX_NAME + 1] = "";
  const char *source = find_var(f, 0, "", "geopotential_height", name) ? "geopotential_height"
                       : find_var(f, 0, "", "geopotential", name)      ? "geopotential"
                                                                         : NULL;
  snprintf(info->vertical, sizeof info->vertical, "pressure levels '%.64s', %g to %g hPa; heights from %s%s%.64s%s",
           L->coord[1], fmax(ends[0], ends[1]) * L->z_to_pa / 100.0, fmin(ends[0], ends[1]) * L->z_to_pa / 100.0,
           source ? source : "nothing (no geopotential: the load fails)", source ? " '" : "", name,
           source ? "'" : "");
}

int sl_cf_read_info(const sl_nc *f, sl_storm_info *info, sl_error *err)
{
  cf_layout L;
  int rc = cf_layout_of(f, &L, info, err);
  if (rc) return rc;
  info->kind = L.cm1 ? SL_STORM_CM1 : SL_STORM_CF;
  if (L.cm1)
    sl_species_cm1_scheme(f, info);
  else
    snprintf(info->scheme, sizeof info->scheme, "CF (hydrometeors by standard_name or ECMWF short name)");
  info->nx = (int)L.len[3], info->ny = (int)L.len[2], info->nz = (int)L.len[1];
  info->ntimes = (int)L.len[0];
  if (info->ntimes > SL_MAX_TIMES)
    return sl_fail(err, SL_ERR_FORMAT, "%s: %d times, more than this reader handles (%d)", f->path, info->ntimes,
                   SL_MAX_TIMES);
  info->dx = L.dx, info->dy = L.dy;
  /* The same bounds as WRF's DX/DY: a grid step beyond 1000 km (or a NaN from corrupt
   * coordinates) would place the storm off the earth. */
  if (!(info->dx > 0.0 && info->dx < 1e6) || !(info->dy > 0.0 && info->dy < 1e6))
    return sl_fail(err, SL_ERR_DATA, "%s: horizontal grid spacing %g x %g m is not plausible (0 to 1000 km)", f->path,
                   info->dx, info->dy);
  if ((rc = cf_projection(f, &L, info, err))) return rc;
  cf_times(f, &L, info);
  cf_vertical_words(f, &L, info);
  return SL_OK;
}

/* The level reader for CF and CM1: 1-D heights, density from the thermodynamic variables. */
typedef struct cf_levels {
  const sl_nc *f;
  const cf_layout *L;
  const sl_subset *s;
  int t;
  size_t n2;
  double *z_iface;      /* interfaces of the whole column, m (height levels) */
  double *z_cols;       /* heights by column (cf_column_levels): the subset's interfaces, [k][y][x], m */
  double *p_level;      /* pressure levels: each subset level's pressure, Pa, from the bottom */
  int *kb;              /* heights by column: per column the first level above the ground (levels
                           below it may be missing: no air, no cloud), counted from the file's bottom */
  int raw;              /* cf_block leaves missing values NaN */
  sl_nc_var rho, p, temp, theta, qv;
  int have_rho, have_temp, have_theta, have_qv, qv_specific;
  const sl_species *species; /* the load's species: which variables are numbers */
  int nspecies;
  sl_var_cache cache;
} cf_levels;


/* Folds v's units into its unpacking (value = packed * scale + offset), so that reads give the SI
 * unit the reader computes in: kg/kg for mixing ratios and mass fractions, Pa, K, kg m-3. A CF
 * file in g/kg, hPa or degrees Celsius read as SI would render a cloud 1000x too dense, air 100x
 * too thin or 24x too dense, without a word. No units attribute reads as SI (older CM1 and
 * hand-made files omit it); units not known here are an error naming the variable. */
static int cf_apply_units(const sl_nc *f, sl_nc_var *v, cf_quantity q, sl_error *err)
{
  static const char *const si[] = {"kg kg-1", "Pa", "K", "kg m-3", "m", "kg-1 (a number per kg of air)"};
  char units[128] = "";
  double scale, offset;
  if (!sl_nc_attr_text(f, v->varid, "units", units, sizeof units)) return SL_OK;
  const int known = cf_unit_factor(q, units, &scale, &offset);
  if (known < 0) return SL_OK;
  if (!known)
    return sl_fail(err, SL_ERR_FORMAT, "%s: variable '%s' has units '%s', which this reader cannot convert to %s",
                   f->path, v->name, units, si[q]);
  v->offset = v->offset * scale + offset;
  v->scale *= scale;
  return SL_OK;
}

static int cf_var(cf_levels *c, const char *name, cf_quantity q, sl_nc_var *v, sl_error *err)
{
  const char *const dims[3] = {c->L->dim[1], c->L->dim[2], c->L->dim[3]};
  const size_t lens[3] = {c->L->len[1], c->L->len[2], c->L->len[3]};
  const int rc = sl_nc_var_open(c->f, name, 3, dims, lens, v, err);
  return rc ? rc : cf_apply_units(c->f, v, q, err);
}

/* The subset's levels of a 3-D variable, each axis whose coordinate decreases reversed so that
 * x, y and z increase with the index as the remap expects (a reversed z reads the file's levels
 * that the subset's levels, counted from the bottom, are). */
static int cf_block(cf_levels *c, const sl_nc_var *v, float *out, sl_error *err)
{
  const sl_subset *s = c->s;
  const int *flip = c->L->flip;
  const int k0 = flip[1] ? (int)c->L->len[1] - s->k0 - s->nz : s->k0;
  const int rc = c->raw || c->kb ? sl_nc_read_block_raw(c->f, v, c->t, k0, s->nz, s, out, err)
                                  : sl_nc_read_block(c->f, v, c->t, k0, s->nz, s, out, err);
  if (rc) return rc;
  const size_t nx = (size_t)s->nx, ny = (size_t)s->ny, nz = (size_t)s->nz, plane = nx * ny;
  float t;
  for (size_t k = 0; flip[3] && k < nz; ++k)
    for (size_t j = 0; j < ny; ++j) {
      float *row = out + k * plane + j * nx;
      for (size_t i = 0; i < nx / 2; ++i) t = row[i], row[i] = row[nx - 1 - i], row[nx - 1 - i] = t;
    }
  for (size_t k = 0; flip[2] && k < nz; ++k)
    for (size_t j = 0; j < ny / 2; ++j) {
      float *a = out + k * plane + j * nx, *b = out + k * plane + (ny - 1 - j) * nx;
      for (size_t i = 0; i < nx; ++i) t = a[i], a[i] = b[i], b[i] = t;
    }
  for (size_t k = 0; flip[1] && k < nz / 2; ++k) {
    float *a = out + k * plane, *b = out + (nz - 1 - k) * plane;
    for (size_t i = 0; i < plane; ++i) t = a[i], a[i] = b[i], b[i] = t;
  }
  /* Below a column's ground (heights by column) a missing value is no air and no cloud; above it,
   * an error. */
  for (size_t k = 0; c->kb && k < nz; ++k)
    for (size_t i = 0; i < plane; ++i)
      if (!isfinite(out[k * plane + i])) {
        if (s->k0 + (int)k >= c->kb[i]) return sl_nc_fail_missing(c->f, v->name, c->t, err);
        out[k * plane + i] = 0.0f;
      }
  return SL_OK;
}

static int cf_interfaces(void *ctx, int k0, int nk, double *z, sl_error *err)
{
  (void)err;
  cf_levels *c = ctx;
  for (int k = 0; k < nk; ++k)
    for (size_t i = 0; i < c->n2; ++i)
      z[(size_t)k * c->n2 + i] =
          c->z_cols ? c->z_cols[(size_t)(k0 + k) * c->n2 + i] : c->z_iface[c->s->k0 + k0 + k];
  return SL_OK;
}

static int cf_air(void *ctx, float *rho_dry, float *rho_moist, unsigned char *frozen, sl_error *err)
{
  cf_levels *c = ctx;
  const size_t n = (size_t)c->s->nz * c->n2;
  float *qv = calloc(n, sizeof(float)), *a = malloc(n * sizeof(float)), *temp = malloc(n * sizeof(float));
  int rc = qv && a && temp ? SL_OK : sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", c->f->path);
  if (!rc && c->have_qv) rc = cf_block(c, &c->qv, qv, err);
  /* Temperature where the file has it (or potential temperature and pressure); without any, no
   * cell is below freezing (only split species need it, and those are refused without one). */
  if (!rc && (c->have_temp || c->have_theta)) rc = cf_block(c, c->have_temp ? &c->temp : &c->theta, temp, err);
  if (!rc && !c->have_rho && !c->p_level) rc = cf_block(c, &c->p, a, err);
  for (size_t i = 0; !rc && !c->have_rho && c->p_level && i < n; ++i) a[i] = (float)c->p_level[i / c->n2];
  if (!rc && c->have_rho) rc = cf_block(c, &c->rho, a, err);
  for (size_t i = 0; !rc && i < n; ++i) {
    if (c->kb && c->s->k0 + (int)(i / c->n2) < c->kb[i % c->n2]) { /* below the ground: no air */
      rho_dry[i] = 0.0f, frozen[i] = 0;
      if (rho_moist) rho_moist[i] = 0.0f;
      continue;
    }
    /* Small negative vapour is advection noise (clamped, as the hydrometeors are); beyond that,
     * or past 0.1 kg/kg (air holds at most a few hundredths), it is not a humidity at all. */
    if (!(qv[i] >= -0.01 && qv[i] <= 0.1)) {
      rc = sl_fail(err, SL_ERR_DATA, "%s: water vapour %g kg/kg at time %d is not physical (are its units right?)",
                   c->f->path, qv[i], c->t);
      break;
    }
    /* Specific humidity q_s is per kg of moist air: mixing ratio q_s / (1 - q_s). */
    const double q = fmax(qv[i], 0.0), r = c->qv_specific ? q / (1.0 - q) : q;
    double t = c->have_temp || c->have_theta ? temp[i] : INFINITY, rho;
    if (!(t > 0.0)) {
      rc = sl_fail(err, SL_ERR_DATA, "%s: non-positive %s temperature %g K at time %d", c->f->path,
                   c->have_temp ? "air" : "potential", t, c->t);
      break;
    }
    if (c->have_rho) {
      rho = a[i] / (1.0 + r);
    } else {
      const double p = a[i];
      if (!(p > 0.0)) {
        rc = sl_fail(err, SL_ERR_DATA, "%s: non-positive pressure at time %d", c->f->path, c->t);
        break;
      }
      if (!c->have_temp) t = sl_temperature_from_theta(t, p);
      rho = sl_dry_air_density(p, t, r);
    }
    frozen[i] = t < SL_FREEZING_K;
    rho_dry[i] = (float)rho;
    if (rho_moist) rho_moist[i] = (float)(rho * (1.0 + r));
  }
  free(qv);
  free(a);
  free(temp);
  return rc;
}

static int cf_field(void *ctx, const char *name, float *out, sl_error *err)
{
  cf_levels *c = ctx;
  const char *const dims[3] = {c->L->dim[1], c->L->dim[2], c->L->dim[3]};
  const size_t lens[3] = {c->L->len[1], c->L->len[2], c->L->len[3]};
  const sl_nc_var *cached;
  int rc = sl_var_cache_get(&c->cache, c->f, name, dims, lens, &cached, err);
  if (rc) return rc;
  sl_nc_var v = *cached;
  cf_quantity q = CF_MASS_FRACTION;
  for (int i = 0; i < c->nspecies; ++i)
    if (strcmp(c->species[i].number_variable, name) == 0) q = CF_NUMBER_PER_MASS;
  return (rc = cf_apply_units(c->f, &v, q, err)) ? rc : cf_block(c, &v, out, err);
}

/* A variable by CM1 name or by CF standard_name. */
static int find_var(const sl_nc *f, int cm1, const char *cm1_name, const char *standard_name, char *out)
{
  if (cm1) {
    snprintf(out, NC_MAX_NAME + 1, "%s", cm1_name);
    return sl_nc_has_var(f, cm1_name);
  }
  int nvars;
  nc_inq_nvars(f->id, &nvars);
  for (int id = 0; id < nvars; ++id) {
    char s[256];
    if (sl_nc_attr_text(f, id, "standard_name", s, sizeof s) && strcmp(s, standard_name) == 0) {
      nc_inq_varname(f->id, id, out);
      return 1;
    }
  }
  return 0;
}

/* Reads a 1-D variable of n values along the vertical, reversed with the levels. 0 when absent. */
static int cf_levels_1d(const sl_nc *f, const cf_layout *L, const char *name, size_t n, double *v)
{
  int id;
  size_t start = 0;
  if (nc_inq_varid(f->id, name, &id) != NC_NOERR || !sl_nc_var_is_1d(f, id, n, NULL) ||
      nc_get_vara_double(f->id, id, &start, &n, v) != NC_NOERR)
    return 0;
  for (size_t k = 0; L->flip[1] && k < n / 2; ++k) {
    const double t = v[k];
    v[k] = v[n - 1 - k], v[n - 1 - k] = t;
  }
  return 1;
}

/* Interfaces zi[0..n] of n level heights zh (from the bottom): midpoints between levels, the outer
 * interfaces half a layer beyond the outer levels; a single level stands for the layer from the
 * ground (0) to twice its height. */
static void level_interfaces(const double *zh, size_t n, double *zi)
{
  for (size_t k = 1; k < n; ++k) zi[k] = 0.5 * (zh[k - 1] + zh[k]);
  zi[0] = n > 1 ? zh[0] - (zi[1] - zh[0]) : 0.0;
  zi[n] = n > 1 ? zh[n - 1] + (zh[n - 1] - zi[n - 1]) : 2.0 * zh[0];
}

/* Interfaces of the 1-D height levels: zf when the file has it (CM1), else midpoints between
 * levels, the outer interfaces half a layer beyond the outer levels. */
static int cf_heights(const sl_nc *f, const cf_layout *L, double *zi, sl_error *err)
{
  const size_t n = L->len[1];
  double *zh = malloc(n * sizeof(double));
  if (!zh) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", f->path);
  if (!cf_levels_1d(f, L, L->coord[1], n, zh)) {
    free(zh);
    return sl_fail(err, SL_ERR_FORMAT, "%s: no 1-D coordinate variable '%s' for the heights", f->path, L->coord[1]);
  }
  int zf;
  size_t zn = 0;
  int nd = 0, dimid;
  if (L->cm1 && !L->flip[1] && nc_inq_varid(f->id, "zf", &zf) == NC_NOERR && nc_inq_varndims(f->id, zf, &nd) == NC_NOERR && nd == 1 &&
      nc_inq_vardimid(f->id, zf, &dimid) == NC_NOERR && nc_inq_dimlen(f->id, dimid, &zn) == NC_NOERR && zn == n + 1) {
    size_t start = 0;
    if (nc_get_vara_double(f->id, zf, &start, &zn, zi) != NC_NOERR) {
      free(zh);
      return sl_fail(err, SL_ERR_FORMAT, "%s: cannot read the interface heights 'zf'", f->path);
    }
  } else {
    level_interfaces(zh, n, zi);
  }
  for (size_t k = 0; k <= n; ++k) zi[k] *= L->z_to_m;
  free(zh);
  for (size_t k = 0; k < n; ++k)
    if (!(zi[k + 1] > zi[k])) return sl_fail(err, SL_ERR_DATA, "%s: heights '%s' do not increase", f->path, L->coord[1]);
  /* Weather lies below the stratopause; a grid reaching past 100 km (or 10 km below the sea) is
   * metres labelled km, or not heights at all (the horizontal spacing has its own bound). */
  if (!(zi[n] <= 1e5) || !(zi[0] >= -1e4))
    return sl_fail(err, SL_ERR_DATA, "%s: heights '%s' span %g to %g m, not an atmosphere (are its units right?)",
                   f->path, L->coord[1], zi[0], zi[n]);
  return SL_OK;
}

/* Hybrid height (CF appendix D, atmosphere_hybrid_height_coordinate; the Met Office UM's levels):
 * z(k, j, i) = a(k) + b(k) orog(j, i), in the units of a. Fills z[k][y][x] for all levels. */
static int cf_hybrid_heights(cf_levels *c, float *z, char *what, sl_error *err)
{
  const sl_nc *f = c->f;
  const cf_layout *L = c->L;
  const size_t n = L->len[1], n2 = c->n2;
  double *a = malloc(n * sizeof(double)), *b = malloc(n * sizeof(double)), *orog = malloc(n2 * sizeof(double));
  int rc = a && b && orog ? SL_OK : sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", f->path);
  snprintf(what, NC_MAX_NAME + 1, "%s", L->coord[1]);
  if (!rc && (!cf_levels_1d(f, L, L->terms[0], n, a) || !cf_levels_1d(f, L, L->terms[1], n, b)))
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: hybrid height terms '%s' and '%s' must be 1-D along '%s'", f->path,
                 L->terms[0], L->terms[1], L->dim[1]);
  double scale = 1.0, offset = 0.0;
  char units[64] = "";
  int id;
  if (!rc && nc_inq_varid(f->id, L->terms[0], &id) == NC_NOERR && sl_nc_attr_text(f, id, "units", units, sizeof units) &&
      cf_unit_factor(CF_HEIGHT, units, &scale, &offset) == 0)
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: hybrid height term '%s' has units '%s', not a height", f->path, L->terms[0],
                 units);
  sl_nc_var ov;
  const char *const dims[2] = {L->dim[2], L->dim[3]};
  const size_t lens[2] = {L->len[2], L->len[3]};
  if (!rc) rc = sl_nc_var_open(f, L->terms[2], 2, dims, lens, &ov, err);
  if (!rc) rc = cf_apply_units(f, &ov, CF_HEIGHT, err);
  if (!rc) rc = sl_nc_read_slab(f, &ov, c->t, -1, c->s, orog, err);
  if (!rc) rc = sl_all_finite(f, L->terms[2], c->t, orog, n2, err);
  const size_t nx = (size_t)c->s->nx, ny = (size_t)c->s->ny;
  for (size_t k = 0; !rc && k < n; ++k)
    for (size_t j = 0; j < ny; ++j)
      for (size_t i = 0; i < nx; ++i) {
        /* the orography in the file's order; the grid's x and y as reversed for the fields */
        const size_t src = (L->flip[2] ? ny - 1 - j : j) * nx + (L->flip[3] ? nx - 1 - i : i);
        z[k * n2 + j * nx + i] = (float)(a[k] * scale + offset + b[k] * orog[src]); /* orog already in m */
      }
  free(a);
  free(b);
  free(orog);
  return rc;
}

/* Levels whose heights vary by column: pressure levels (heights from a geopotential or
 * geopotential height on the same grid, pressures from the coordinate), hybrid height (a + b orog)
 * and any levels with a 3-D altitude. Each column's interfaces lie halfway between its levels and
 * the outer ones half a layer beyond, as for 1-D heights. A column whose heights do not rise is
 * refused, naming it. Sets the subset's lowest interface above a ground and its highest. */
static int cf_column_levels(cf_levels *c, double *ground, double *top, sl_error *err)
{
  const sl_nc *f = c->f;
  const cf_layout *L = c->L;
  const size_t n = L->len[1], n2 = c->n2, nz = (size_t)c->s->nz;
  const int pressure = L->z_to_pa > 0.0;
  char name[NC_MAX_NAME + 1] = "";
  int height = 0;
  if (pressure && !(height = find_var(f, 0, "", "geopotential_height", name)) &&
      !find_var(f, 0, "", "geopotential", name))
    return sl_fail(err, SL_ERR_FORMAT,
                   "%s: vertical coordinate '%s' is pressure: its heights need a variable with standard_name "
                   "geopotential_height or geopotential on the same grid",
                   f->path, L->coord[1]);
  if (L->altitude_3d) height = find_var(f, 0, "", "altitude", name);
  if (n < 2)
    return sl_fail(err, SL_ERR_FORMAT, "%s: one %s level has no thickness: such a grid needs two or more", f->path,
                   pressure ? "pressure" : "model");
  double *p = malloc(n * sizeof(double)), *zh = malloc((2 * n + 1) * sizeof(double)), *zi = zh + n;
  float *z = malloc(n * n2 * sizeof(float));
  c->z_cols = malloc((nz + 1) * n2 * sizeof(double));
  c->p_level = pressure ? malloc(nz * sizeof(double)) : NULL;
  c->kb = malloc(n2 * sizeof(int));
  int rc = SL_OK;
  if (!p || !zh || !z || !c->z_cols || (pressure && !c->p_level) || !c->kb) {
    rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", f->path);
    goto done;
  }
  if (L->hybrid_height) {
    if ((rc = cf_hybrid_heights(c, z, name, err))) goto done;
  } else {
    /* All levels (the subset's outer interfaces lie halfway to the levels beyond it). */
    sl_subset all = *c->s;
    all.k0 = 0, all.nz = (int)n;
    cf_levels whole = *c;
    whole.s = &all, whole.raw = 1, whole.kb = NULL;
    sl_nc_var geo;
    if ((rc = cf_var(c, name, CF_HEIGHT, &geo, err))) goto done;
    char units[64] = "", squeezed[64];
    sl_nc_attr_text(f, geo.varid, "units", units, sizeof units);
    cf_units_squeezed(units, squeezed, sizeof squeezed);
    if (!height && !squeezed[0]) geo.scale /= 9.80665, geo.offset /= 9.80665; /* no units: SI, m2 s-2 */
    if ((rc = cf_block(&whole, &geo, z, err))) goto done;
  }
  if (pressure) {
    if (!cf_levels_1d(f, L, L->coord[1], n, p)) {
      rc = sl_fail(err, SL_ERR_FORMAT, "%s: no 1-D coordinate variable '%s' for the pressure levels", f->path,
                   L->coord[1]);
      goto done;
    }
    for (size_t k = 0; k < n; ++k) {
      p[k] *= L->z_to_pa;
      if (!(p[k] > 0.0 && p[k] < 2e5) || (k > 0 && !(p[k] < p[k - 1]))) {
        rc = sl_fail(err, SL_ERR_DATA, "%s: pressure levels '%s' are not distinct pressures between 0 and 2000 hPa",
                     f->path, L->coord[1]);
        goto done;
      }
    }
  }
  const int k0 = c->s->k0;
  for (size_t i = 0; i < n2; ++i) {
    /* Levels below the ground may be missing (CMIP masks them, xarray writes NaN there): the column
     * starts at its first level with a height, and every level above must have one. The missing
     * levels get heights (down the hypsometric equation at 288 K between pressure levels, else
     * the spacing above) so that the remap sees rising interfaces; they hold no air and no cloud. */
    size_t kb = 0;
    while (kb < n && !isfinite(z[kb * n2 + i])) ++kb;
    for (size_t k = kb; k < n; ++k)
      if (!isfinite(z[k * n2 + i])) {
        char where[64];
        if (pressure) snprintf(where, sizeof where, "%g Pa", p[k]);
        else snprintf(where, sizeof where, "level %zu", k);
        rc = sl_fail(err, SL_ERR_DATA, "%s: '%s' is missing at %s above the ground in column (%zu, %zu) at time %d",
                     f->path, name, where, i % (size_t)c->s->nx, i / (size_t)c->s->nx, c->t);
        goto done;
      }
    if (kb + 2 > n) {
      rc = sl_fail(err, SL_ERR_DATA, "%s: '%s' has %s in column (%zu, %zu) at time %d", f->path, name,
                   kb == n ? "no level above the ground" : "one level above the ground", i % (size_t)c->s->nx,
                   i / (size_t)c->s->nx, c->t);
      goto done;
    }
    c->kb[i] = (int)kb;
    for (size_t k = kb; k-- > 0;)
      z[k * n2 + i] = (float)(pressure ? z[(k + 1) * n2 + i] - CF_RD * 288.0 / 9.80665 * log(p[k] / p[k + 1])
                                       : 2.0 * z[(k + 1) * n2 + i] - z[(k + 2) * n2 + i]);
    for (size_t k = 1; k < n; ++k)
      if (!(z[k * n2 + i] > z[(k - 1) * n2 + i])) {
        rc = sl_fail(err, SL_ERR_DATA,
                     "%s: '%s' does not rise from level %zu to %zu in column (%zu, %zu) at time %d (%g to %g m)",
                     f->path, name, k - 1, k, i % (size_t)c->s->nx, i / (size_t)c->s->nx, c->t, z[(k - 1) * n2 + i],
                     z[k * n2 + i]);
        goto done;
      }
    for (size_t k = 0; k < n; ++k) zh[k] = z[k * n2 + i];
    level_interfaces(zh, n, zi); /* interface kk lies below level kk */
    for (size_t k = 0; k <= nz; ++k) c->z_cols[k * n2 + i] = zi[(size_t)k0 + k];
  }
  *ground = INFINITY, *top = -INFINITY;
  /* The grid starts at the lowest interface above the ground (the layers below hold nothing). */
  for (size_t i = 0; i < n2; ++i) {
    const int lowest = c->kb[i] > k0 ? (c->kb[i] - k0 < (int)nz ? c->kb[i] - k0 : (int)nz) : 0;
    *ground = fmin(*ground, c->z_cols[(size_t)lowest * n2 + i]);
    *top = fmax(*top, c->z_cols[nz * n2 + i]);
  }
  if (!(*top <= 1e5) || !(*ground >= -1e4)) {
    rc = sl_fail(err, SL_ERR_DATA, "%s: '%s' spans %g to %g m, not an atmosphere (are its units right?)", f->path,
                 name, *ground, *top);
    goto done;
  }
  for (size_t k = 0; pressure && k < nz; ++k) c->p_level[k] = p[(size_t)k0 + k];
done:
  free(p);
  free(zh);
  free(z);
  return rc;
}

int sl_cf_load(const sl_nc *f, const sl_storm_info *info, const sl_load_options *opt, const sl_species *species,
               int nspecies, sl_storm_frame *frame, sl_error *err)
{
  cf_layout L;
  sl_storm_info *scratch = malloc(sizeof *scratch);
  if (!scratch) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", f->path);
  int rc = cf_layout_of(f, &L, scratch, err);
  free(scratch);
  if (rc) return rc;
  if (opt && opt->has_region) return sl_fail(err, SL_ERR_ARG, "%s: --region needs a WRF file (XLAT/XLONG)", f->path);
  frame->memory_estimate = sl_storm_memory_estimate(info, opt);
  /* Heights by column (cf_column_levels): every level's height (float) and the interfaces (double). */
  if (L.z_to_pa > 0.0 || L.hybrid_height || L.altitude_3d)
    frame->memory_estimate += (double)info->nx * info->ny * (info->nz * sizeof(float) + (info->nz + 1) * sizeof(double));
  if ((rc = sl_check_memory(f->path, frame->memory_estimate, opt, err))) return rc;
  sl_subset s = {0, 0, opt && opt->stride > 1 ? opt->stride : 1, 0, 0, opt ? opt->level_first : 0, 0};
  s.nx = (info->nx - 1) / s.stride + 1, s.ny = (info->ny - 1) / s.stride + 1;
  s.nz = opt && opt->level_count > 0 ? opt->level_count : info->nz - s.k0;
  if (s.k0 < 0 || s.nz < 1 || s.k0 + s.nz > info->nz)
    return sl_fail(err, SL_ERR_ARG, "%s: --levels outside the file's %d levels", f->path, info->nz);
  cf_levels c = {.f = f, .L = &L, .s = &s, .t = opt ? opt->time_index : 0, .n2 = (size_t)s.nx * s.ny,
                 .species = species, .nspecies = nspecies};
  double ground = 0.0, top = 0.0;
  if (L.z_to_pa > 0.0 || L.hybrid_height || L.altitude_3d) {
    if ((rc = cf_column_levels(&c, &ground, &top, err))) goto done;
  } else {
    c.z_iface = malloc((L.len[1] + 1) * sizeof(double));
    if (!c.z_iface) {
      rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", f->path);
      goto done;
    }
    if ((rc = cf_heights(f, &L, c.z_iface, err))) goto done;
    ground = c.z_iface[s.k0], top = c.z_iface[s.k0 + s.nz];
  }
  /* Air: density itself, or pressure with temperature or potential temperature; vapour optional. */
  char name[NC_MAX_NAME + 1];
  if ((c.have_rho = find_var(f, 0, "", "air_density", name)) && (rc = cf_var(&c, name, CF_DENSITY, &c.rho, err))) goto done;
  if ((c.have_temp = find_var(f, 0, "", "air_temperature", name)) && (rc = cf_var(&c, name, CF_TEMPERATURE, &c.temp, err))) goto done;
  if (!c.have_temp && (c.have_theta = find_var(f, L.cm1, "th", "air_potential_temperature", name)) &&
      (rc = cf_var(&c, name, CF_TEMPERATURE, &c.theta, err)))
    goto done;
  if ((c.have_qv = find_var(f, L.cm1, "qv", "humidity_mixing_ratio", name))) {
    if ((rc = cf_var(&c, name, CF_MASS_FRACTION, &c.qv, err))) goto done;
  } else if ((c.have_qv = c.qv_specific = find_var(f, 0, "", "specific_humidity", name))) {
    if ((rc = cf_var(&c, name, CF_MASS_FRACTION, &c.qv, err))) goto done;
  }
  /* On pressure levels the pressure is the coordinate's. */
  const int have_p = c.p_level || find_var(f, L.cm1, "prs", "air_pressure", name);
  if (!c.have_rho && (!have_p || (!c.have_temp && !c.have_theta))) {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: no air density: needs %s", f->path,
                 L.cm1        ? "prs and th"
                 : c.p_level ? "air_density, or air_temperature or air_potential_temperature on the pressure levels"
                             : "air_density, or air_pressure with air_temperature or air_potential_temperature");
    goto done;
  }
  if (!c.have_rho && !c.p_level && (rc = cf_var(&c, name, CF_PRESSURE, &c.p, err))) goto done;
  for (int i = 0; i < nspecies; ++i)
    if (species[i].warm != species[i].cold && !c.have_temp && !c.have_theta) {
      rc = sl_fail(err, SL_ERR_FORMAT, "%s: splitting '%s' at 0 C needs a temperature", f->path, species[i].variable);
      goto done;
    }
  const double dz = opt && opt->dz > 0.0 ? opt->dz : (top - ground) / (2.0 * s.nz);
  sl_level_reader r = {&c, cf_interfaces, cf_air, cf_field};
  if ((rc = sl_remap_levels(f->path, &r, &s, species, nspecies, ground, top, dz,
                            (const double[2]){info->dx * s.stride, info->dy * s.stride}, NULL, NULL,
                            opt ? opt->max_fields : 0, frame, err)))
    goto done;
  /* CM1 and projected CF grids without a projection origin carry no position: NaN asks for the
   * sun's angles; latitude-longitude grids know their centre, projected ones find it through
   * their grid_mapping. */
  frame->center_lat = frame->center_lon = NAN;
  if (L.x_to_m != 0.0 && !L.cm1) cf_projected_centre(f, &L, info, &s, frame);
  double x, y;
  if (L.x_to_m == 0.0 && cf_centre_coords(f, &L, &s, &x, &y)) frame->center_lat = y, frame->center_lon = x;
  /* --origin says where a grid with no place (CM1's flat plane) stands: its centre, for the sun of
   * a date, as for WRF's idealized runs. */
  if (!isfinite(frame->center_lat) && opt && opt->has_origin)
    frame->center_lat = opt->origin_lat, frame->center_lon = opt->origin_lon;
  frame->terrain_min = frame->terrain_max = ground;
  frame->model_top = top;
  frame->time_index = c.t;
done:
  free(c.z_iface);
  free(c.z_cols);
  free(c.p_level);
  free(c.kb);
  return rc;
}
