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

#include "cf_internal.h"
#include "sl_geo.h"


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


/* A units string without spaces, '*' and '^' (so "kg kg-1", "kg kg**-1" and "kg kg^-1" read alike). */
void cf_units_squeezed(const char *in, char *out, size_t cap)
{
  size_t n = 0;
  for (; *in && n + 1 < cap; ++in)
    if (*in != ' ' && *in != '*' && *in != '^') out[n++] = *in;
  out[n] = '\0';
}

/* SI value = value * scale + offset for quantity q in `units`: 1 when known, 0 when not, -1 for
 * an empty string (no units: read as SI). Geopotential (m2 s-2) reads as a height through WMO's
 * standard gravity: geopotential height, as WRF's (PH+PHB)/g. */
int cf_unit_factor(cf_quantity q, const char *units, double *scale, double *offset)
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

/* A CF hydrometeor's number concentration, as two-moment schemes write it: a variable that the
 * mass fraction's ancillary_variables attribute names (CF 3.4) whose units are a number per mass
 * of air (kg-1, #/kg, g-1); its cells then give the species' sizes (docs/DATA.md, "Sizes"). A
 * linked variable in other units (a quality flag, a number per volume) is left alone. */
static void cf_number_variable(const sl_nc *f, int id, sl_species *sp)
{
  char list[512];
  if (!sl_nc_attr_text(f, id, "ancillary_variables", list, sizeof list)) return;
  for (char *name = list; *name;) {
    while (*name == ' ' || *name == '\t') ++name;
    char *end = name;
    while (*end && *end != ' ' && *end != '\t') ++end;
    const char next = *end;
    *end = '\0';
    int nid;
    char units[64];
    double scale, offset;
    if (*name && nc_inq_varid(f->id, name, &nid) == NC_NOERR && sl_nc_attr_text(f, nid, "units", units, sizeof units) &&
        cf_unit_factor(CF_NUMBER_PER_MASS, units, &scale, &offset) == 1) {
      sl_species_set_number(sp, name);
      return;
    }
    if (!next) break;
    name = end + 1;
  }
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

int cf_layout_of(const sl_nc *f, cf_layout *L, sl_storm_info *info, sl_error *err)
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
    if (sl_species_cf_match(name, stdname, L->cm1, &info->species[info->nspecies])) {
      if (!L->cm1) cf_number_variable(f, id, &info->species[info->nspecies]);
      info->nspecies++;
    }
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
  if (!L->hybrid_height && !(L->z_to_m > 0.0) && L->z_to_pa == 0.0 && !L->cm1 && cf_find_var(f, 0, "", "altitude", alt))
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
int cf_centre_coords(const sl_nc *f, const cf_layout *L, const sl_subset *s, double *x, double *y)
{
  return cf_middle_coord(f, L->coord[3], (size_t)s->i0, (size_t)s->nx, (size_t)s->stride, x) &&
         cf_middle_coord(f, L->coord[2], (size_t)s->j0, (size_t)s->ny, (size_t)s->stride, y);
}

void cf_projected_centre(const sl_nc *f, const cf_layout *L, const sl_storm_info *info, const sl_subset *s,
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
  if (L->altitude_3d && cf_find_var(f, 0, "", "altitude", alt)) {
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
  const char *source = cf_find_var(f, 0, "", "geopotential_height", name) ? "geopotential_height"
                       : cf_find_var(f, 0, "", "geopotential", name)      ? "geopotential"
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

/* A variable by CM1 name or by CF standard_name. */
int cf_find_var(const sl_nc *f, int cm1, const char *cm1_name, const char *standard_name, char *out)
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
