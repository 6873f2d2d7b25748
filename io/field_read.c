/* A 3-D float variable of a NetCDF file as it stands (z, y, x): the extinction field of a
 * Monte Carlo reference medium (`stormlight reference`, docs/REFERENCE.md). */
#include <math.h>
#include <netcdf.h>
#include <stdlib.h>

#include "sl_storm.h"

int sl_read_field3d(const char *path, const char *variable, int n[3], float **out, sl_error *err)
{
  *out = NULL;
  int nc, id, ndims, dims[NC_MAX_VAR_DIMS];
  if (nc_open(path, NC_NOWRITE, &nc) != NC_NOERR) return sl_fail(err, SL_ERR_IO, "%s: cannot open as NetCDF", path);
  int rc = SL_OK;
  size_t len[3] = {0, 0, 0};
  if (nc_inq_varid(nc, variable, &id) != NC_NOERR) {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: no variable '%s'", path, variable);
  } else if (nc_inq_varndims(nc, id, &ndims) != NC_NOERR || ndims != 3 || nc_inq_vardimid(nc, id, dims) != NC_NOERR) {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: variable '%s' must have 3 dimensions (z, y, x)", path, variable);
  } else {
    for (int a = 0; a < 3 && !rc; ++a)
      if (nc_inq_dimlen(nc, dims[a], &len[a]) != NC_NOERR) rc = sl_fail(err, SL_ERR_FORMAT, "%s: unreadable dimensions", path);
    if (!rc && (!(len[0] > 0 && len[1] > 0 && len[2] > 0) || (double)len[0] * len[1] * len[2] > 1e9))
      rc = sl_fail(err, SL_ERR_FORMAT, "%s: variable '%s' has an empty or absurd shape %zux%zux%zu", path, variable,
                   len[0], len[1], len[2]);
  }
  float *v = NULL;
  const size_t count = len[0] * len[1] * len[2];
  if (!rc && !(v = malloc(count * sizeof *v))) rc = sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
  if (!rc && nc_get_var_float(nc, id, v) != NC_NOERR) rc = sl_fail(err, SL_ERR_IO, "%s: cannot read '%s'", path, variable);
  for (size_t i = 0; i < count && !rc; ++i)
    if (!(v[i] >= 0.0f) || !isfinite(v[i]))
      rc = sl_fail(err, SL_ERR_DATA, "%s: '%s' is negative or not finite at element %zu", path, variable, i);
  nc_close(nc);
  if (rc) {
    free(v);
    return rc;
  }
  n[0] = (int)len[2], n[1] = (int)len[1], n[2] = (int)len[0];
  *out = v;
  return SL_OK;
}
