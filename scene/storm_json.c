/* `stormlight info --json` (sl_storm_json.h): one storm file described as JSON through cJSON. */
#include "sl_storm_json.h"

#include <cjson/cJSON.h>
#include <stdlib.h>

const char *sl_projection_name(int map_proj)
{
  switch (map_proj) {
  case 1: return "Lambert conformal";
  case 2: return "polar stereographic";
  case 3: return "Mercator";
  case 6: return "latitude-longitude (cylindrical equidistant)";
  case 0: return "none (a flat grid)";
  default: return "unknown";
  }
}

const char *sl_netcdf_format_name(int format)
{
  switch (format) {
  case 1: return "netCDF-3 classic";
  case 2: return "netCDF-3 64-bit offset";
  case 3: return "netCDF-4";
  case 4: return "netCDF-4 classic model";
  case 5: return "netCDF-3 CDF5 (64-bit data)";
  default: return "unknown";
  }
}

const char *sl_storm_kind_name(sl_storm_format kind)
{
  return kind == SL_STORM_WRF ? "WRF" : kind == SL_STORM_CM1 ? "CM1" : "CF";
}

static void add_numbers(cJSON *parent, const char *name, const double *v, int n)
{
  cJSON *a = cJSON_AddArrayToObject(parent, name);
  for (int i = 0; i < n; ++i) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[i]));
}

/* The grid as the file holds it and as it loads: sizes, extent, the uniform grid, terrain. */
static void add_grid(cJSON *root, const sl_storm_info *info, const sl_storm_frame *frame)
{
  const sl_volume *v = &frame->volume;
  cJSON *grid = cJSON_AddObjectToObject(root, "grid");
  cJSON_AddNumberToObject(grid, "west_east", info->nx);
  cJSON_AddNumberToObject(grid, "south_north", info->ny);
  cJSON_AddNumberToObject(grid, "bottom_top", info->nz);
  cJSON_AddNumberToObject(grid, "dx_m", info->dx);
  cJSON_AddNumberToObject(grid, "dy_m", info->dy);
  cJSON *uni = cJSON_AddObjectToObject(root, "uniform_grid");
  cJSON_AddNumberToObject(uni, "nx", v->nx);
  cJSON_AddNumberToObject(uni, "ny", v->ny);
  cJSON_AddNumberToObject(uni, "nz", v->nz);
  cJSON_AddNumberToObject(uni, "dz_m", v->spacing[2]);
  cJSON *ext = cJSON_AddObjectToObject(root, "extent_m");
  cJSON_AddNumberToObject(ext, "east", v->nx * v->spacing[0]);
  cJSON_AddNumberToObject(ext, "north", v->ny * v->spacing[1]);
  cJSON_AddNumberToObject(ext, "up", frame->model_top - frame->terrain_min);
  cJSON_AddNumberToObject(root, "terrain_min_m", frame->terrain_min);
  cJSON_AddNumberToObject(root, "terrain_max_m", frame->terrain_max);
  cJSON_AddNumberToObject(root, "model_top_m", frame->model_top);
  cJSON_AddNumberToObject(root, "center_lat", frame->center_lat);
  cJSON_AddNumberToObject(root, "center_lon", frame->center_lon);
}

/* The projection, its check against XLAT/XLONG, the corners and the world frame. */
static void add_placement(cJSON *root, const sl_storm_info *info, const sl_storm_frame *frame)
{
  const sl_georef *g = &frame->georef;
  const sl_volume *v = &frame->volume;
  cJSON *proj = cJSON_AddObjectToObject(root, "projection");
  cJSON_AddNumberToObject(proj, "map_proj", info->map_proj);
  cJSON_AddStringToObject(proj, "name", sl_projection_name(info->map_proj));
  cJSON_AddNumberToObject(proj, "truelat1", info->truelat1);
  cJSON_AddNumberToObject(proj, "truelat2", info->truelat2);
  cJSON_AddNumberToObject(proj, "stand_lon", info->stand_lon);
  cJSON_AddNumberToObject(proj, "pole_lat", info->pole_lat);
  cJSON_AddNumberToObject(proj, "pole_lon", info->pole_lon);
  cJSON_AddBoolToObject(proj, "rotated_pole", g->projection.rotated);
  cJSON_AddNumberToObject(proj, "grid_north_deg", g->grid_north_deg);
  cJSON_AddNumberToObject(proj, "map_factor_min", g->map_factor_min);
  cJSON_AddNumberToObject(proj, "map_factor_max", g->map_factor_max);
  cJSON_AddNumberToObject(proj, "xlat_xlong_max_disagreement_deg", g->max_error_deg);
  cJSON_AddNumberToObject(proj, "xlat_xlong_max_disagreement_m", g->max_error_m);
  cJSON_AddStringToObject(proj, "placement_from", g->from_xlat ? "XLAT/XLONG" : "projection");
  cJSON_AddBoolToObject(proj, "placed", g->placed);
  cJSON *corners = cJSON_AddObjectToObject(root, "corners");
  static const char *const corner_names[4] = {"sw", "se", "ne", "nw"};
  for (int k = 0; k < 4 && g->placed; ++k) {
    cJSON *c = cJSON_AddObjectToObject(corners, corner_names[k]);
    cJSON_AddNumberToObject(c, "lat", g->corner_lat[k]);
    cJSON_AddNumberToObject(c, "lon", g->corner_lon[k]);
  }
  cJSON *enu = cJSON_AddObjectToObject(root, "enu_origin");
  cJSON_AddNumberToObject(enu, "lat", g->origin_lat);
  cJSON_AddNumberToObject(enu, "lon", g->origin_lon);
  cJSON *vol = cJSON_AddObjectToObject(root, "volume_m");
  cJSON_AddNumberToObject(vol, "x0", v->origin[0]);
  cJSON_AddNumberToObject(vol, "y0", v->origin[1]);
  cJSON_AddNumberToObject(vol, "z0", v->origin[2]);
  cJSON_AddNumberToObject(vol, "dx", v->spacing[0]);
  cJSON_AddNumberToObject(vol, "dy", v->spacing[1]);
  cJSON_AddNumberToObject(vol, "dz", v->spacing[2]);
}

/* One species: its variable, kind, types, clamped negatives, and where its sizes come from. */
static cJSON *species_json(const sl_species *sp, const sl_field_stats *st)
{
  cJSON *e = cJSON_CreateObject();
  cJSON_AddStringToObject(e, "variable", sp->variable);
  cJSON_AddStringToObject(e, "kind", sp->kind);
  cJSON_AddStringToObject(e, "type", sl_particle_name((sl_particle)sp->warm));
  if (sp->cold != sp->warm) cJSON_AddStringToObject(e, "type_below_0C", sl_particle_name((sl_particle)sp->cold));
  if (sp->number_variable[0]) cJSON_AddStringToObject(e, "number_variable", sp->number_variable);
  cJSON_AddNumberToObject(e, "negative_clamped", (double)st->negative_count);
  cJSON *sizes = cJSON_AddObjectToObject(e, "sizes");
  const int sized = sl_species_sized(sp);
  const int assumed = !sp->number_variable[0] && sp->sizes.fixed_number_m3 > 0.0;
  cJSON_AddStringToObject(sizes, "distribution", sized ? sp->sizes.source : "representative particle");
  cJSON_AddStringToObject(sizes, "number", sp->number_variable[0] ? "read" : assumed ? "assumed"
                                           : sized                ? "from intercept"
                                                                  : "none");
  if (sized && assumed) cJSON_AddNumberToObject(sizes, "assumed_number_m3", sp->sizes.fixed_number_m3);
  if (sized && !sp->number_variable[0] && !assumed)
    cJSON_AddNumberToObject(sizes, "intercept_m4", sp->sizes.fixed_intercept_m4);
  if (sized) cJSON_AddNumberToObject(sizes, "density_kg_m3", sp->sizes.density_kg_m3);
  if (st->r_eff_max > 0.0) {
    cJSON_AddNumberToObject(sizes, "r_eff_min_m", st->r_eff_min);
    cJSON_AddNumberToObject(sizes, "r_eff_max_m", st->r_eff_max);
  }
  cJSON_AddNumberToObject(sizes, "number_negative_clamped", (double)st->number_negative);
  cJSON_AddNumberToObject(sizes, "number_zero_beside_mass", (double)st->number_missing);
  return e;
}

/* The species, the optics tables sized cloud and rain take, and each field's statistics. */
static void add_species(cJSON *root, const sl_storm_frame *frame)
{
  cJSON *species = cJSON_AddArrayToObject(root, "species");
  for (int i = 0; i < frame->nspecies; ++i)
    cJSON_AddItemToArray(species, species_json(&frame->species[i], &frame->species_stats[i]));
  cJSON *tables = cJSON_AddArrayToObject(root, "size_tables");
  const sl_size_bins *b = &frame->sizes;
  for (int t = 0; t < SL_PARTICLE_COUNT; ++t) {
    if (!b->count[t]) continue;
    cJSON *e = cJSON_CreateObject();
    cJSON_AddStringToObject(e, "type", sl_particle_name((sl_particle)t));
    add_numbers(e, "effective_radii_m", b->radius_m[t], b->count[t]);
    cJSON_AddNumberToObject(e, "cells_r_eff_p01_m", b->range_lo_m[t]);
    cJSON_AddNumberToObject(e, "cells_r_eff_p99_m", b->range_hi_m[t]);
    cJSON_AddBoolToObject(e, "limited_by_fields", b->limited[t]);
    cJSON_AddItemToArray(tables, e);
  }
  cJSON *fields = cJSON_AddObjectToObject(root, "fields");
  for (int p = 0; p < frame->nspecies; ++p) {
    const sl_field_stats *s = &frame->species_stats[p];
    cJSON *f = cJSON_AddObjectToObject(fields, frame->species[p].variable);
    cJSON_AddNumberToObject(f, "min_kg_per_kg", s->q_min);
    cJSON_AddNumberToObject(f, "max_kg_per_kg", s->q_max);
    cJSON_AddNumberToObject(f, "mean_kg_per_kg", s->q_mean);
    cJSON_AddNumberToObject(f, "negative_clamped", (double)s->negative_count);
  }
}

char *sl_storm_info_json(const char *path, const sl_load_options *load, sl_error *err)
{
  sl_storm_info *info = malloc(sizeof *info);
  if (!info) {
    sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
    return NULL;
  }
  sl_storm_frame frame;
  if (sl_storm_read_info(path, info, err) || sl_storm_load(path, load, &frame, err)) {
    free(info);
    return NULL;
  }
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "file", path);
  add_grid(root, info, &frame);
  add_placement(root, info, &frame);
  cJSON_AddNumberToObject(root, "mp_physics", info->mp_physics);
  cJSON_AddStringToObject(root, "format", sl_storm_kind_name(info->kind));
  cJSON_AddStringToObject(root, "netcdf_format", sl_netcdf_format_name(info->format));
  cJSON_AddStringToObject(root, "scheme", info->scheme);
  cJSON_AddStringToObject(root, "vertical", info->vertical);
  add_species(root, &frame);
  cJSON *mem = cJSON_AddObjectToObject(root, "memory");
  cJSON_AddNumberToObject(mem, "estimate_bytes", frame.memory_estimate);
  cJSON_AddNumberToObject(mem, "available_bytes", sl_machine_memory());
  cJSON *times = cJSON_AddArrayToObject(root, "times");
  for (int i = 0; i < info->ntimes; ++i)
    cJSON_AddItemToArray(times, info->has_times ? cJSON_CreateString(info->times[i]) : cJSON_CreateNumber(i));
  if (!info->has_times && info->has_elapsed) add_numbers(root, "elapsed_seconds", info->elapsed_s, info->ntimes);
  cJSON_AddStringToObject(root, "calendar", info->calendar);
  cJSON_AddNumberToObject(root, "time_index", load->time_index);
  char *text = cJSON_PrintUnformatted(root);
  cJSON_Delete(root);
  sl_storm_frame_free(&frame);
  free(info);
  if (!text) sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
  return text;
}
