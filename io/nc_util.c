/* NetCDF helpers shared by the storm readers: opening by path or from memory, attributes, and
 * strided hyperslab reads of one horizontal level with unpacking (scale_factor/add_offset, any
 * sign) and fill values. */
#include <math.h>
#include <netcdf.h>
#include <netcdf_mem.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "storm_internal.h"

/* Bytes of one value of a netCDF-3 type. */
static double nc3_type_size(nc_type t)
{
  switch (t) {
  case NC_BYTE: case NC_CHAR: case NC_UBYTE: return 1;
  case NC_SHORT: case NC_USHORT: return 2;
  case NC_INT: case NC_FLOAT: case NC_UINT: return 4;
  default: return 8;
  }
}

static double pad4(double n) { return 4.0 * ceil(n / 4.0); }

/* The smallest size a netCDF-3 file (classic, 64-bit offset, CDF5) with this header can have: its
 * header encoded as the format specification lays it out, plus every variable's data (records
 * times the record count). netCDF-C reads past the end of a truncated netCDF-3 file as zeros, so
 * a file shorter than this has lost data silently. */
static double nc3_minimum_size(int ncid, int format)
{
  const double count = format == NC_FORMAT_CDF5 ? 8 : 4, begin = format == NC_FORMAT_CLASSIC ? 4 : 8;
  int ndims, nvars, ngatts, unlimited;
  nc_inq(ncid, &ndims, &nvars, &ngatts, &unlimited);
  size_t numrecs = 0;
  if (unlimited >= 0) nc_inq_dimlen(ncid, unlimited, &numrecs);
  char name[NC_MAX_NAME + 1];
  double size = 4 + count + 3 * (4 + count); /* magic, numrecs, three list headers */
  for (int d = 0; d < ndims; ++d) {
    nc_inq_dimname(ncid, d, name);
    size += count + pad4((double)strlen(name)) + count;
  }
  for (int v = -1; v < nvars; ++v) {
    int natts = ngatts;
    if (v >= 0) nc_inq_varnatts(ncid, v, &natts);
    for (int a = 0; a < natts; ++a) {
      nc_type t;
      size_t len;
      nc_inq_attname(ncid, v, a, name);
      nc_inq_att(ncid, v, name, &t, &len);
      size += count + pad4((double)strlen(name)) + 4 + count + pad4((double)len * nc3_type_size(t));
    }
  }
  double records = 0.0;
  int nrecvars = 0;
  for (int v = 0; v < nvars; ++v) {
    int nd, dims[NC_MAX_VAR_DIMS];
    nc_type t;
    nc_inq_var(ncid, v, name, &t, &nd, dims, NULL);
    size += count + pad4((double)strlen(name)) + count + nd * count + 4 + count + 4 + count + begin;
    double n = nc3_type_size(t);
    int record = 0;
    for (int d = 0; d < nd; ++d) {
      size_t len;
      if (dims[d] == unlimited) {
        record = 1;
        continue;
      }
      nc_inq_dimlen(ncid, dims[d], &len);
      n *= (double)len;
    }
    if (record) records += n, nrecvars++;
    else size += pad4(n);
  }
  /* Record slabs are padded to 4 bytes unless there is exactly one record variable. */
  if (nrecvars > 1) records = pad4(records);
  return size + records * (double)numrecs;
}

int sl_nc_open(const char *path, const void *data, size_t size, sl_nc *f, sl_error *err)
{
  f->path = path;
  f->id = -1;
  const int status = data ? nc_open_mem(path, NC_NOWRITE, size, (void *)data, &f->id)
                          : nc_open(path, NC_NOWRITE, &f->id);
  if (status == NC_NOERR) {
    int format = 0;
    nc_inq_format(f->id, &format);
    struct stat st;
    double actual = data ? (double)size : stat(path, &st) == 0 ? (double)st.st_size : INFINITY;
    if (format == NC_FORMAT_CLASSIC || format == NC_FORMAT_64BIT_OFFSET || format == NC_FORMAT_CDF5) {
      const double need = nc3_minimum_size(f->id, format);
      if (actual < need) {
        nc_close(f->id);
        f->id = -1;
        return sl_fail(err, SL_ERR_FORMAT, "%s: truncated: %.0f bytes where its header and data need at least %.0f",
                       path, actual, need);
      }
    }
    return SL_OK;
  }
  f->id = -1;
  struct stat st;
  if (!data && stat(path, &st) == 0 && S_ISDIR(st.st_mode))
    return sl_fail(err, SL_ERR_IO, "%s: is a directory, not a NetCDF file", path);
  if (status == NC_ENOTNC || status == NC_EHDFERR || status == NC_ENOTBUILT)
    return sl_fail(err, SL_ERR_FORMAT, "%s: not a NetCDF file (or truncated)", path);
  return sl_fail(err, SL_ERR_IO, "%s: cannot open: %s", path, nc_strerror(status));
}

double sl_nc_attr_double(const sl_nc *f, int varid, const char *name, double fallback)
{
  double v;
  size_t len;
  nc_type type;
  if (nc_inq_att(f->id, varid, name, &type, &len) != NC_NOERR || len != 1 || type == NC_CHAR || type == NC_STRING)
    return fallback;
  return nc_get_att_double(f->id, varid, name, &v) == NC_NOERR ? v : fallback;
}

int sl_nc_attr_text(const sl_nc *f, int varid, const char *name, char *out, size_t cap)
{
  size_t len;
  nc_type type;
  out[0] = '\0';
  if (nc_inq_att(f->id, varid, name, &type, &len) != NC_NOERR || type != NC_CHAR || len >= cap) return 0;
  if (nc_get_att_text(f->id, varid, name, out) != NC_NOERR) return 0;
  out[len] = '\0';
  return 1;
}

int sl_nc_has_var(const sl_nc *f, const char *name)
{
  int id;
  return nc_inq_varid(f->id, name, &id) == NC_NOERR;
}

int sl_nc_var_is_1d(const sl_nc *f, int varid, size_t min_len, size_t *len)
{
  int nd = 0, dimid;
  nc_type type;
  size_t n = 0;
  if (nc_inq_varndims(f->id, varid, &nd) != NC_NOERR || nd != 1 || nc_inq_vartype(f->id, varid, &type) != NC_NOERR ||
      type == NC_CHAR || type == NC_STRING || nc_inq_vardimid(f->id, varid, &dimid) != NC_NOERR ||
      nc_inq_dimlen(f->id, dimid, &n) != NC_NOERR || n < min_len)
    return 0;
  if (len) *len = n;
  return 1;
}

int sl_nc_var_open(const sl_nc *f, const char *name, int ndims, const char *const *dim_names, const size_t *lens,
                   sl_nc_var *v, sl_error *err)
{
  memset(v, 0, sizeof *v);
  snprintf(v->name, sizeof v->name, "%s", name);
  if (nc_inq_varid(f->id, name, &v->varid) != NC_NOERR)
    return sl_fail(err, SL_ERR_FORMAT, "%s: missing variable '%s'", f->path, name);
  /* No chunk cache: the loader reads a variable in blocks of whole layers of its chunks (remap.c),
   * so it inflates a chunk once, but for PH and PHB's next layer at each block's top, variables
   * chunked shallower than the deepest, and blocks set smaller than a layer (block_levels); a
   * cache of netCDF's default 16 MiB a variable holds one chunk of a large file's many in a layer,
   * and would only hold memory until the file closes (0.08 GB at a 1000 x 1000 deck's peak).
   * Classic files have none: the call then fails, which changes nothing. */
  (void)nc_set_var_chunk_cache(f->id, v->varid, 0, 0, 0.75f);
  int nd, dimids[NC_MAX_VAR_DIMS];
  nc_type type;
  nc_inq_varndims(f->id, v->varid, &nd);
  nc_inq_vartype(f->id, v->varid, &type);
  if (type == NC_CHAR || type == NC_STRING)
    return sl_fail(err, SL_ERR_FORMAT, "%s: variable '%s' is text, not numbers", f->path, name);
  /* Time-varying variables lead with time; some writers store static fields (HGT, XLAT, XLONG in
   * cropped or processed files) without it, which holds for every time. */
  v->has_time = nd == ndims + 1;
  if (!v->has_time && nd != ndims)
    return sl_fail(err, SL_ERR_FORMAT, "%s: variable '%s' has %d dimensions, expected %d", f->path, name, nd,
                   ndims + 1);
  v->ndims = nd;
  nc_inq_vardimid(f->id, v->varid, dimids);
  for (int d = 0; d < ndims; ++d) {
    char dname[NC_MAX_NAME + 1];
    size_t dlen;
    nc_inq_dim(f->id, dimids[d + v->has_time], dname, &dlen);
    if ((dim_names && strcmp(dname, dim_names[d]) != 0) || dlen != lens[d])
      return sl_fail(err, SL_ERR_FORMAT, "%s: variable '%s' dimension %d is %s=%zu, expected %s=%zu", f->path, name,
                     d + 1 + v->has_time, dname, dlen, dim_names ? dim_names[d] : "length", lens[d]);
  }
  v->fill = sl_nc_attr_double(f, v->varid, "_FillValue", NAN);
  v->missing = sl_nc_attr_double(f, v->varid, "missing_value", NAN);
  v->scale = sl_nc_attr_double(f, v->varid, "scale_factor", 1.0);
  v->offset = sl_nc_attr_double(f, v->varid, "add_offset", 0.0);
  return SL_OK;
}

/* Hyperslab of time t, levels k0 .. k0 + nk - 1 (3-D variables; ignored for 2-D ones) and the
 * subset's columns, as doubles or floats, unpacked; fill/missing values become NaN. */
static int read_hyperslab(const sl_nc *f, const sl_nc_var *v, int t, int k0, int nk, const sl_subset *s,
                          double *out_d, float *out_f, sl_error *err)
{
  size_t start[NC_MAX_VAR_DIMS] = {0}, count[NC_MAX_VAR_DIMS];
  ptrdiff_t stride[NC_MAX_VAR_DIMS];
  int d = 0;
  size_t levels = 1;
  if (v->has_time) start[d] = (size_t)t, count[d] = 1, stride[d] = 1, ++d;
  if (v->ndims - v->has_time == 3) start[d] = (size_t)k0, count[d] = levels = (size_t)nk, stride[d] = 1, ++d;
  start[d] = (size_t)s->j0, count[d] = (size_t)s->ny, stride[d] = s->stride, ++d;
  start[d] = (size_t)s->i0, count[d] = (size_t)s->nx, stride[d] = s->stride, ++d;
  const int status = out_d ? nc_get_vars_double(f->id, v->varid, start, count, stride, out_d)
                           : nc_get_vars_float(f->id, v->varid, start, count, stride, out_f);
  if (status != NC_NOERR)
    return sl_fail(err, SL_ERR_FORMAT, "%s: cannot read '%s' at time %d: %s", f->path, v->name, t,
                   nc_strerror(status));
  const size_t n = levels * (size_t)s->nx * s->ny;
  /* Fill values compare in the precision the values were read in. */
  const double fill = out_d ? v->fill : (double)(float)v->fill, missing = out_d ? v->missing : (double)(float)v->missing;
  /* Value by value, so shared among the threads (netCDF's read above is this thread's alone). */
  const double scale = v->scale, offset = v->offset;
  if (out_d) {
#pragma omp parallel for simd schedule(dynamic, SL_IO_CHUNK) if (n > SL_IO_CHUNK)
    for (size_t i = 0; i < n; ++i) {
      const double x = out_d[i];
      out_d[i] = (x == fill || x == missing ? NAN : x) * scale + offset;
    }
  } else {
#pragma omp parallel for simd schedule(dynamic, SL_IO_CHUNK) if (n > SL_IO_CHUNK)
    for (size_t i = 0; i < n; ++i) {
      const double x = (double)out_f[i];
      out_f[i] = (float)((x == fill || x == missing ? NAN : x) * scale + offset);
    }
  }
  return SL_OK;
}

int sl_nc_read_slab(const sl_nc *f, const sl_nc_var *v, int t, int k, const sl_subset *s, double *out,
                    sl_error *err)
{
  return read_hyperslab(f, v, t, k, 1, s, out, NULL, err);
}

int sl_nc_read_block(const sl_nc *f, const sl_nc_var *v, int t, int k0, int nk, const sl_subset *s, float *out,
                     sl_error *err)
{
  const int rc = read_hyperslab(f, v, t, k0, nk, s, NULL, out, err);
  if (rc) return rc;
  const size_t n = (size_t)(v->ndims - v->has_time == 3 ? nk : 1) * s->nx * s->ny;
  int bad = 0;
#pragma omp parallel for simd schedule(dynamic, SL_IO_CHUNK) reduction(| : bad) if (n > SL_IO_CHUNK)
  for (size_t i = 0; i < n; ++i) bad |= !isfinite(out[i]);
  return bad ? sl_nc_fail_missing(f, v->name, t, err) : SL_OK;
}

int sl_nc_read_block_raw(const sl_nc *f, const sl_nc_var *v, int t, int k0, int nk, const sl_subset *s, float *out,
                         sl_error *err)
{
  return read_hyperslab(f, v, t, k0, nk, s, NULL, out, err);
}

int sl_nc_chunk_levels(const sl_nc *f, const sl_nc_var *v)
{
  int storage = NC_CONTIGUOUS;
  size_t chunks[NC_MAX_VAR_DIMS] = {0};
  if (v->ndims - v->has_time != 3 || nc_inq_var_chunking(f->id, v->varid, &storage, chunks) != NC_NOERR ||
      storage != NC_CHUNKED)
    return 1;
  const size_t levels = chunks[v->has_time]; /* the dimension after time: the levels */
  return levels > 1 && levels < 100000 ? (int)levels : 1;
}

int sl_species_chunk_levels(sl_var_cache *cache, const sl_nc *f, const char *const dims[3], const size_t lens[3],
                            const sl_species *species, int nspecies, int *levels, sl_error *err)
{
  for (int i = 0; i < 2 * nspecies; ++i) {
    const char *name = i % 2 ? species[i / 2].number_variable : species[i / 2].variable;
    const sl_nc_var *v = NULL;
    int rc;
    if (!name[0]) continue;
    if ((rc = sl_var_cache_get(cache, f, name, dims, lens, &v, err))) return rc;
    const int e = sl_nc_chunk_levels(f, v);
    if (e > *levels) *levels = e;
  }
  return SL_OK;
}

int sl_nc_fail_missing(const sl_nc *f, const char *name, int t, sl_error *err)
{
  return sl_fail(err, SL_ERR_DATA, "%s: variable '%s' has NaN, Inf or missing values at time %d", f->path, name, t);
}

int sl_var_cache_get(sl_var_cache *cache, const sl_nc *f, const char *name, const char *const dims[3],
                     const size_t lens[3], const sl_nc_var **out, sl_error *err)
{
  int i = 0;
  while (i < cache->count && strcmp(cache->vars[i].name, name) != 0) ++i;
  if (i == cache->count) {
    if (i == (int)(sizeof cache->vars / sizeof cache->vars[0]))
      return sl_fail(err, SL_ERR_ARG, "%s: too many variables", f->path);
    const int rc = sl_nc_var_open(f, name, 3, dims, lens, &cache->vars[i], err);
    if (rc) return rc;
    cache->count++;
  }
  *out = &cache->vars[i];
  return SL_OK;
}

int sl_all_finite(const sl_nc *f, const char *name, int t, const double *v, size_t n, sl_error *err)
{
  for (size_t i = 0; i < n; ++i)
    if (!isfinite(v[i])) return sl_nc_fail_missing(f, name, t, err);
  return SL_OK;
}
