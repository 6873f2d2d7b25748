/* The CF/CM1 level reader: the grid's heights (1-D levels, hybrid height, pressure levels with a
 * geopotential, 3-D altitudes), the air's density from the thermodynamic variables, and the
 * hydrometeor fields, streamed level by level through the remap (remap.c) by the layout that
 * cf_read.c found. */
#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cf_internal.h"
#include "sl_large_alloc.h"
#include "sl_geo.h"

/* The level reader for CF and CM1: 1-D heights, density from the thermodynamic variables. */
typedef struct cf_levels {
  const sl_nc *f;
  const cf_layout *L;
  const sl_subset *s;
  int t;
  size_t n2;
  double *z_iface;      /* interfaces of the whole column, m (height levels) */
  float *z_levels;      /* heights by column (cf_column_levels): every level of the file, from the bottom,
                           [k][y][x], m; the interfaces come from them (column_interface) */
  double *p_level;      /* pressure levels: each subset level's pressure, Pa, from the bottom */
  int *kb;              /* heights by column: per column the first level above the ground (levels
                           below it may be missing: no air, no cloud), counted from the file's bottom */
  int raw;              /* cf_block leaves missing values NaN */
  sl_nc_var rho, p, temp, theta, qv;
  int have_rho, have_temp, have_theta, have_qv, qv_specific;
  const sl_species *species; /* the load's species: which variables are numbers */
  int nspecies;
  sl_var_cache cache;
  float *scratch[3]; /* cf_air's arrays, kept from block to block (freed by the load): fresh pages
                        every block cost a fault each */
  size_t scratch_n;
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

/* Levels k_block .. k_block + nk - 1 of the subset of a 3-D variable, each axis whose coordinate
 * decreases reversed so that x, y and z increase with the index as the remap expects (a reversed z
 * reads the file's levels that the subset's levels, counted from the bottom, are). */
static int cf_block(cf_levels *c, const sl_nc_var *v, int k_block, int nk, float *out, sl_error *err)
{
  const sl_subset *s = c->s;
  const int *flip = c->L->flip;
  const int k0 = flip[1] ? (int)c->L->len[1] - s->k0 - k_block - nk : s->k0 + k_block;
  const int rc = c->raw || c->kb ? sl_nc_read_block_raw(c->f, v, c->t, k0, nk, s, out, err)
                                  : sl_nc_read_block(c->f, v, c->t, k0, nk, s, out, err);
  if (rc) return rc;
  const size_t nx = (size_t)s->nx, ny = (size_t)s->ny, nz = (size_t)nk, plane = nx * ny;
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
        if (s->k0 + k_block + (int)k >= c->kb[i]) return sl_nc_fail_missing(c->f, v->name, c->t, err);
        out[k * plane + i] = 0.0f;
      }
  return SL_OK;
}

/* Interface kk (below level kk, 0 .. n) of column i of n level heights z ([k][column], n2 columns,
 * n >= 2): level_interfaces' rule for one interface, in the same arithmetic, so that a block of the
 * remap needs no whole grid of interfaces. */
static double column_interface(const float *z, size_t n2, size_t n, size_t kk, size_t i)
{
  if (kk == 0) {
    const double z0 = z[i], above = 0.5 * (z0 + (double)z[n2 + i]);
    return z0 - (above - z0);
  }
  if (kk == n) {
    const double top = z[(n - 1) * n2 + i], below = 0.5 * ((double)z[(n - 2) * n2 + i] + top);
    return top + (top - below);
  }
  return 0.5 * ((double)z[(kk - 1) * n2 + i] + (double)z[kk * n2 + i]);
}

static int cf_interfaces(void *ctx, int k0, int nk, double *z, sl_error *err)
{
  (void)err;
  cf_levels *c = ctx;
  for (int k = 0; k < nk; ++k) {
    const size_t kk = (size_t)(c->s->k0 + k0 + k);
    for (size_t i = 0; i < c->n2; ++i)
      z[(size_t)k * c->n2 + i] =
          c->z_levels ? column_interface(c->z_levels, c->n2, c->L->len[1], kk, i) : c->z_iface[kk];
  }
  return SL_OK;
}

static int cf_air(void *ctx, int k_block, int nk, float *rho_dry, float *rho_moist, unsigned char *frozen,
                  sl_error *err)
{
  cf_levels *c = ctx;
  const size_t n = (size_t)nk * c->n2;
  if (n > c->scratch_n) {
    for (int i = 0; i < 3; ++i) free(c->scratch[i]), c->scratch[i] = sl__huge_alloc(n * sizeof(float));
    c->scratch_n = c->scratch[0] && c->scratch[1] && c->scratch[2] ? n : 0;
    if (!c->scratch_n) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", c->f->path);
  }
  float *qv = c->scratch[0], *a = c->scratch[1], *temp = c->scratch[2];
  int rc = SL_OK;
  if (c->have_qv) rc = cf_block(c, &c->qv, k_block, nk, qv, err);
  else memset(qv, 0, n * sizeof(float));
  /* Temperature where the file has it (or potential temperature and pressure); without any, no
   * cell is below freezing (only split species need it, and those are refused without one). */
  if (!rc && (c->have_temp || c->have_theta))
    rc = cf_block(c, c->have_temp ? &c->temp : &c->theta, k_block, nk, temp, err);
  if (!rc && !c->have_rho && !c->p_level) rc = cf_block(c, &c->p, k_block, nk, a, err);
  for (size_t i = 0; !rc && !c->have_rho && c->p_level && i < n; ++i)
    a[i] = (float)c->p_level[(size_t)k_block + i / c->n2];
  if (!rc && c->have_rho) rc = cf_block(c, &c->rho, k_block, nk, a, err);
  /* Cell by cell, so shared among the threads (the reads above stay on this one: netCDF's); the
   * first cell refused (the least index) is the one reported. */
  if (rc) return rc;
  size_t bad = n;
#pragma omp parallel for schedule(dynamic, SL_IO_CHUNK) reduction(min : bad) if (n > SL_IO_CHUNK)
  for (size_t i = 0; i < n; ++i) {
    if (c->kb && c->s->k0 + k_block + (int)(i / c->n2) < c->kb[i % c->n2]) { /* below the ground: no air */
      rho_dry[i] = 0.0f, frozen[i] = 0;
      if (rho_moist) rho_moist[i] = 0.0f;
      continue;
    }
    /* Small negative vapour is advection noise (clamped, as the hydrometeors are); beyond that,
     * or past 0.1 kg/kg (air holds at most a few hundredths), it is not a humidity at all. */
    const double q = fmax(qv[i], 0.0), r = c->qv_specific ? q / (1.0 - q) : q;
    double t = c->have_temp || c->have_theta ? temp[i] : INFINITY, rho;
    if (!(qv[i] >= -0.01 && qv[i] <= 0.1) || !(t > 0.0) || (!c->have_rho && !(a[i] > 0.0f))) {
      if (i < bad) bad = i;
      continue;
    }
    if (c->have_rho) {
      rho = a[i] / (1.0 + r);
    } else {
      const double p = a[i];
      if (!c->have_temp) t = sl_temperature_from_theta(t, p);
      rho = sl_dry_air_density(p, t, r);
    }
    frozen[i] = t < SL_FREEZING_K;
    rho_dry[i] = (float)rho;
    if (rho_moist) rho_moist[i] = (float)(rho * (1.0 + r));
  }
  if (bad < n) {
    if (!(qv[bad] >= -0.01 && qv[bad] <= 0.1))
      rc = sl_fail(err, SL_ERR_DATA, "%s: water vapour %g kg/kg at time %d is not physical (are its units right?)",
                   c->f->path, qv[bad], c->t);
    else if ((c->have_temp || c->have_theta) && !(temp[bad] > 0.0f))
      rc = sl_fail(err, SL_ERR_DATA, "%s: non-positive %s temperature %g K at time %d", c->f->path,
                   c->have_temp ? "air" : "potential", (double)temp[bad], c->t);
    else
      rc = sl_fail(err, SL_ERR_DATA, "%s: non-positive pressure at time %d", c->f->path, c->t);
  }
  return rc;
}

static int cf_field(void *ctx, const char *name, int k_block, int nk, float *out, sl_error *err)
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
  return (rc = cf_apply_units(c->f, &v, q, err)) ? rc : cf_block(c, &v, k_block, nk, out, err);
}

/* The remap's blocks follow the largest chunk layer of the variables it reads; with the levels
 * reversed, a layer of the file's chunks ends where the subset's block starts. */
static int cf_chunk_levels(cf_levels *c, int *levels, int *phase, sl_error *err)
{
  const char *const dims[3] = {c->L->dim[1], c->L->dim[2], c->L->dim[3]};
  const size_t lens[3] = {c->L->len[1], c->L->len[2], c->L->len[3]};
  const sl_nc_var *const air[] = {c->have_rho ? &c->rho : NULL, !c->have_rho && !c->p_level ? &c->p : NULL,
                                  c->have_temp ? &c->temp : NULL, c->have_theta ? &c->theta : NULL,
                                  c->have_qv ? &c->qv : NULL};
  *levels = 1;
  for (size_t i = 0; i < sizeof air / sizeof air[0]; ++i) {
    const int e = air[i] ? sl_nc_chunk_levels(c->f, air[i]) : 1;
    if (e > *levels) *levels = e;
  }
  *phase = c->L->flip[1] ? c->s->k0 - (int)c->L->len[1] : c->s->k0;
  return sl_species_chunk_levels(&c->cache, c->f, dims, lens, c->species, c->nspecies, levels, err);
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
  if (pressure && !(height = cf_find_var(f, 0, "", "geopotential_height", name)) &&
      !cf_find_var(f, 0, "", "geopotential", name))
    return sl_fail(err, SL_ERR_FORMAT,
                   "%s: vertical coordinate '%s' is pressure: its heights need a variable with standard_name "
                   "geopotential_height or geopotential on the same grid",
                   f->path, L->coord[1]);
  if (L->altitude_3d) height = cf_find_var(f, 0, "", "altitude", name);
  if (n < 2)
    return sl_fail(err, SL_ERR_FORMAT, "%s: one %s level has no thickness: such a grid needs two or more", f->path,
                   pressure ? "pressure" : "model");
  double *p = malloc(n * sizeof(double));
  float *z = c->z_levels = malloc(n * n2 * sizeof(float)); /* kept: the remap's interfaces come from it */
  c->p_level = pressure ? malloc(nz * sizeof(double)) : NULL;
  c->kb = malloc(n2 * sizeof(int));
  int rc = SL_OK;
  if (!p || !z || (pressure && !c->p_level) || !c->kb) {
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
    if ((rc = cf_block(&whole, &geo, 0, (int)n, z, err))) goto done;
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
  }
  *ground = INFINITY, *top = -INFINITY;
  /* The grid starts at the lowest interface above the ground (the layers below hold nothing). */
  for (size_t i = 0; i < n2; ++i) {
    const int lowest = c->kb[i] > k0 ? (c->kb[i] - k0 < (int)nz ? c->kb[i] - k0 : (int)nz) : 0;
    *ground = fmin(*ground, column_interface(z, n2, n, (size_t)(k0 + lowest), i));
    *top = fmax(*top, column_interface(z, n2, n, (size_t)k0 + nz, i));
  }
  if (!(*top <= 1e5) || !(*ground >= -1e4)) {
    rc = sl_fail(err, SL_ERR_DATA, "%s: '%s' spans %g to %g m, not an atmosphere (are its units right?)", f->path,
                 name, *ground, *top);
    goto done;
  }
  for (size_t k = 0; pressure && k < nz; ++k) c->p_level[k] = p[(size_t)k0 + k];
done:
  free(p);
  return rc;
}

/* A 2-D field on the grid's columns by standard_name (with or without time), into *out in the
 * volume's column order (axes reversed as cf_block does), as a fraction: units "%" or "percent"
 * divided by 100; missing values NaN. A variable of another shape is passed over (*out stays NULL):
 * it describes some other grid, and the ground under the storm is optional. */
static int cf_surface_field(const sl_nc *f, const cf_layout *L, const sl_subset *s, int t, const char *standard_name,
                            float **out, sl_error *err)
{
  char name[NC_MAX_NAME + 1];
  if (!cf_find_var(f, 0, "", standard_name, name)) return SL_OK;
  const char *const dims[2] = {L->dim[2], L->dim[3]};
  const size_t lens[2] = {L->len[2], L->len[3]};
  sl_nc_var v;
  sl_error other_shape = {0};
  if (sl_nc_var_open(f, name, 2, dims, lens, &v, &other_shape)) return SL_OK;
  char units[64] = "";
  sl_nc_attr_text(f, v.varid, "units", units, sizeof units);
  const double scale = strcmp(units, "%") == 0 || strcmp(units, "percent") == 0 ? 0.01 : 1.0;
  const size_t nx = (size_t)s->nx, ny = (size_t)s->ny;
  double *read = malloc(nx * ny * sizeof *read);
  *out = malloc(nx * ny * sizeof **out);
  if (!read || !*out) {
    free(read);
    return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", f->path);
  }
  const int rc = sl_nc_read_slab(f, &v, t, -1, s, read, err);
  for (size_t j = 0; !rc && j < ny; ++j)
    for (size_t i = 0; i < nx; ++i) {
      const size_t from = (L->flip[2] ? ny - 1 - j : j) * nx + (L->flip[3] ? nx - 1 - i : i);
      (*out)[j * nx + i] = (float)(read[from] * scale);
    }
  free(read);
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
  /* Heights by column (cf_column_levels): every level's height (float), held through the load. */
  if (L.z_to_pa > 0.0 || L.hybrid_height || L.altitude_3d)
    frame->memory_estimate += (double)info->nx * info->ny * info->nz * sizeof(float);
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
  if ((c.have_rho = cf_find_var(f, 0, "", "air_density", name)) && (rc = cf_var(&c, name, CF_DENSITY, &c.rho, err))) goto done;
  if ((c.have_temp = cf_find_var(f, 0, "", "air_temperature", name)) && (rc = cf_var(&c, name, CF_TEMPERATURE, &c.temp, err))) goto done;
  if (!c.have_temp && (c.have_theta = cf_find_var(f, L.cm1, "th", "air_potential_temperature", name)) &&
      (rc = cf_var(&c, name, CF_TEMPERATURE, &c.theta, err)))
    goto done;
  if ((c.have_qv = cf_find_var(f, L.cm1, "qv", "humidity_mixing_ratio", name))) {
    if ((rc = cf_var(&c, name, CF_MASS_FRACTION, &c.qv, err))) goto done;
  } else if ((c.have_qv = c.qv_specific = cf_find_var(f, 0, "", "specific_humidity", name))) {
    if ((rc = cf_var(&c, name, CF_MASS_FRACTION, &c.qv, err))) goto done;
  }
  /* On pressure levels the pressure is the coordinate's. */
  const int have_p = c.p_level || cf_find_var(f, L.cm1, "prs", "air_pressure", name);
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
  sl_level_reader r = {&c, cf_interfaces, cf_air, cf_field, 1, 0, opt ? opt->block_levels : 0};
  if ((rc = cf_chunk_levels(&c, &r.chunk_levels, &r.chunk_phase, err))) goto done;
  /* Now that the blocks are known: the output at this dz, a block's work arrays, heights by column. */
  const double nzo = ceil((top - ground) / dz), n2 = (double)c.n2;
  frame->memory_estimate = sl_load_bytes((size_t)s.nx, (size_t)s.ny, (size_t)sl_remap_block_levels(&r, s.nz, c.n2),
                                         nzo > 1 ? (size_t)fmin(nzo, 1e9) : 1, sl_species_type_count(species, nspecies)) +
                           (c.z_levels ? n2 * (double)L.len[1] * sizeof(float) : 0.0);
  if (nzo <= 4096 && (rc = sl_check_memory(f->path, frame->memory_estimate, opt, err))) goto done;
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
  /* The ground under the storm, where the file describes it (CF standard names): its albedo, and
   * land or water (a binary mask, else the land's area fraction). */
  if ((rc = cf_surface_field(f, &L, &s, c.t, "surface_albedo", &frame->surface_albedo, err))) goto done;
  if ((rc = cf_surface_field(f, &L, &s, c.t, "land_binary_mask", &frame->land_mask, err))) goto done;
  if (!frame->land_mask && (rc = cf_surface_field(f, &L, &s, c.t, "land_area_fraction", &frame->land_mask, err)))
    goto done;
done:
  for (int i = 0; i < 3; ++i) free(c.scratch[i]);
  free(c.z_iface);
  free(c.z_levels);
  free(c.p_level);
  free(c.kb);
  return rc;
}
