#include <netcdf.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "sl_tempfile.h"
#include "sl_wrf_write.h"

#define NC_TRY(call)                                                                      \
  do {                                                                                    \
    int nc_status_ = (call);                                                              \
    if (nc_status_ != NC_NOERR) {                                                         \
      rc = sl_fail(err, SL_ERR_IO, "%s: cannot write: %s", path, nc_strerror(nc_status_)); \
      goto fail;                                                                          \
    }                                                                                     \
  } while (0)

typedef struct var_spec {
  const char *name, *units, *description, *stagger;
  const float *data;
  int staggered_z, two_d;
} var_spec;

int sl_wrf_write(const char *path, const sl_wrf_fields *f, sl_error *err)
{
  int rc = SL_OK, ncid = -1;
  char tmp[4096];
  if (sl_temp_name(path, tmp, sizeof tmp, err)) return err->code;
  NC_TRY(nc_create(tmp, NC_NETCDF4 | NC_CLOBBER, &ncid));
  int d_time, d_str, d_we, d_sn, d_bt, d_bts;
  NC_TRY(nc_def_dim(ncid, "Time", NC_UNLIMITED, &d_time));
  NC_TRY(nc_def_dim(ncid, "DateStrLen", 19, &d_str));
  NC_TRY(nc_def_dim(ncid, "west_east", (size_t)f->nx, &d_we));
  NC_TRY(nc_def_dim(ncid, "south_north", (size_t)f->ny, &d_sn));
  NC_TRY(nc_def_dim(ncid, "bottom_top", (size_t)f->nz, &d_bt));
  NC_TRY(nc_def_dim(ncid, "bottom_top_stag", (size_t)f->nz + 1, &d_bts));
  int v_times;
  const int times_dims[2] = {d_time, d_str};
  NC_TRY(nc_def_var(ncid, "Times", NC_CHAR, 2, times_dims, &v_times));

  const var_spec vars[] = {
      {"XLAT", "degree_north", "LATITUDE, SOUTH IS NEGATIVE", "", f->xlat, 0, 1},
      {"XLONG", "degree_east", "LONGITUDE, WEST IS NEGATIVE", "", f->xlong, 0, 1},
      {"HGT", "m", "Terrain Height", "", f->hgt, 0, 1},
      {"PH", "m2 s-2", "perturbation geopotential", "Z", f->ph, 1, 0},
      {"PHB", "m2 s-2", "base-state geopotential", "Z", f->phb, 1, 0},
      {"T", "K", "perturbation potential temperature (theta-t0)", "", f->t, 0, 0},
      {"P", "Pa", "perturbation pressure", "", f->p, 0, 0},
      {"PB", "Pa", "BASE STATE PRESSURE", "", f->pb, 0, 0},
      {"QVAPOR", "kg kg-1", "Water vapor mixing ratio", "", f->qvapor, 0, 0},
      {"QCLOUD", "kg kg-1", "Cloud water mixing ratio", "", f->qcloud, 0, 0},
      {"QRAIN", "kg kg-1", "Rain water mixing ratio", "", f->qrain, 0, 0},
      {"QICE", "kg kg-1", "Ice mixing ratio", "", f->qice, 0, 0},
      {"QSNOW", "kg kg-1", "Snow mixing ratio", "", f->qsnow, 0, 0},
  };
  enum { NVARS = sizeof vars / sizeof vars[0] };
  int ids[NVARS];
  for (int v = 0; v < NVARS; ++v) {
    ids[v] = -1;
    if (!vars[v].data) continue;
    int dims[4], nd;
    dims[0] = d_time;
    if (vars[v].two_d) {
      dims[1] = d_sn;
      dims[2] = d_we;
      nd = 3;
    } else {
      dims[1] = vars[v].staggered_z ? d_bts : d_bt;
      dims[2] = d_sn;
      dims[3] = d_we;
      nd = 4;
    }
    NC_TRY(nc_def_var(ncid, vars[v].name, NC_FLOAT, nd, dims, &ids[v]));
    NC_TRY(nc_def_var_deflate(ncid, ids[v], 1, 1, 4));
    NC_TRY(nc_put_att_text(ncid, ids[v], "units", strlen(vars[v].units), vars[v].units));
    NC_TRY(nc_put_att_text(ncid, ids[v], "description", strlen(vars[v].description), vars[v].description));
    NC_TRY(nc_put_att_text(ncid, ids[v], "stagger", strlen(vars[v].stagger), vars[v].stagger));
    const char *mo = vars[v].two_d ? "XY " : "XYZ";
    NC_TRY(nc_put_att_text(ncid, ids[v], "MemoryOrder", 3, mo));
  }
  const char *title = f->title ? f->title : " OUTPUT FROM STORMLIGHT SYNTH (WRF-STYLE)";
  NC_TRY(nc_put_att_text(ncid, NC_GLOBAL, "TITLE", strlen(title), title));
  NC_TRY(nc_put_att_text(ncid, NC_GLOBAL, "START_DATE", 19, f->times[0]));
  NC_TRY(nc_put_att_text(ncid, NC_GLOBAL, "SIMULATION_START_DATE", 19, f->times[0]));
  const int we = f->nx + 1, sn = f->ny + 1, bt = f->nz + 1;
  NC_TRY(nc_put_att_int(ncid, NC_GLOBAL, "WEST-EAST_GRID_DIMENSION", NC_INT, 1, &we));
  NC_TRY(nc_put_att_int(ncid, NC_GLOBAL, "SOUTH-NORTH_GRID_DIMENSION", NC_INT, 1, &sn));
  NC_TRY(nc_put_att_int(ncid, NC_GLOBAL, "BOTTOM-TOP_GRID_DIMENSION", NC_INT, 1, &bt));
  const float dx = (float)f->dx, dy = (float)f->dy;
  NC_TRY(nc_put_att_float(ncid, NC_GLOBAL, "DX", NC_FLOAT, 1, &dx));
  NC_TRY(nc_put_att_float(ncid, NC_GLOBAL, "DY", NC_FLOAT, 1, &dy));
  NC_TRY(nc_put_att_int(ncid, NC_GLOBAL, "MP_PHYSICS", NC_INT, 1, &f->mp_physics));
  NC_TRY(nc_put_att_int(ncid, NC_GLOBAL, "MAP_PROJ", NC_INT, 1, &f->map_proj));
  const struct {
    const char *name;
    double value;
  } angles[] = {{"CEN_LAT", f->cen_lat},     {"CEN_LON", f->cen_lon},     {"TRUELAT1", f->truelat1},
                {"TRUELAT2", f->truelat2},   {"MOAD_CEN_LAT", f->moad_cen_lat}, {"STAND_LON", f->stand_lon}};
  for (size_t a = 0; a < sizeof angles / sizeof angles[0]; ++a) {
    const float v = (float)angles[a].value;
    NC_TRY(nc_put_att_float(ncid, NC_GLOBAL, angles[a].name, NC_FLOAT, 1, &v));
  }
  const char *proj_char = f->map_proj == 1 ? "Lambert Conformal" : f->map_proj == 3 ? "Mercator" : "unknown";
  NC_TRY(nc_put_att_text(ncid, NC_GLOBAL, "MAP_PROJ_CHAR", strlen(proj_char), proj_char));
  NC_TRY(nc_enddef(ncid));

  for (int t = 0; t < f->ntimes; ++t) {
    const size_t start[2] = {(size_t)t, 0}, count[2] = {1, 19};
    NC_TRY(nc_put_vara_text(ncid, v_times, start, count, f->times[t]));
  }
  const size_t n2 = (size_t)f->nx * f->ny;
  for (int v = 0; v < NVARS; ++v) {
    if (ids[v] < 0) continue;
    const int nlev = vars[v].two_d ? 1 : f->nz + (vars[v].staggered_z ? 1 : 0);
    for (int t = 0; t < f->ntimes; ++t) {
      size_t start[4] = {(size_t)t, 0, 0, 0}, count[4] = {1, 0, 0, 0};
      if (vars[v].two_d) {
        count[1] = (size_t)f->ny;
        count[2] = (size_t)f->nx;
      } else {
        count[1] = (size_t)nlev;
        count[2] = (size_t)f->ny;
        count[3] = (size_t)f->nx;
      }
      NC_TRY(nc_put_vara_float(ncid, ids[v], start, count, vars[v].data + (size_t)t * nlev * n2));
    }
  }
  NC_TRY(nc_close(ncid));
  ncid = -1;
  return sl_temp_commit(tmp, path, err);
fail:
  if (ncid >= 0) nc_close(ncid);
  unlink(tmp);
  return rc;
}
