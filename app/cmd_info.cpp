// stormlight info: what a storm file holds, as a meteorologist wants to see it.
#include <cjson/cJSON.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "cli.h"
#include "commands.h"
#include "sl_storm.h"

namespace {

const char *projection_name(int map_proj)
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

const char *netcdf_format_name(int format)
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

const char *storm_kind_name(sl_storm_format kind)
{
  return kind == SL_STORM_WRF ? "WRF" : kind == SL_STORM_CM1 ? "CM1" : "CF";
}

// "ice below 0 C, cloud above" for split species, else the type's name.
std::string species_types(const sl_species &sp)
{
  if (sp.warm == sp.cold) return sl_particle_name((sl_particle)sp.warm);
  return std::string(sl_particle_name((sl_particle)sp.warm)) + " at or above 0 C, " +
         sl_particle_name((sl_particle)sp.cold) + " below";
}

// Where a species' sizes come from, in words: the scheme's distribution and whether its number is
// read, the scheme's fixed number, or the representative particle.
std::string species_sizes(const sl_species &sp, const sl_field_stats &st)
{
  char text[512];
  const sl_gamma_distribution &d = sp.sizes;
  if (!(d.density_kg_m3 > 0.0)) {
    std::snprintf(text, sizeof text, "representative particle (%s)",
                  sl_particle_properties((sl_particle)sp.warm)->mass_source);
    return text;
  }
  std::string number = sp.number_variable[0] ? std::string("N read from ") + sp.number_variable
                       : d.fixed_number_m3 > 0.0 ? "N assumed " + std::to_string((int)std::lround(d.fixed_number_m3 * 1e-6)) + " cm^-3"
                       : d.fixed_intercept_m4 > 0.0 ? "N from the mass and the fixed intercept"
                                                    : "no N: representative particle";
  int len = std::snprintf(text, sizeof text, "%s; %s", d.source, number.c_str());
  if (st.r_eff_max > 0.0)
    len += std::snprintf(text + len, sizeof text - (size_t)len, "; r_eff %.3g..%.3g um where q > 1e-6",
                         st.r_eff_min * 1e6, st.r_eff_max * 1e6);
  if (st.number_negative || st.number_missing)
    std::snprintf(text + len, sizeof text - (size_t)len, "; N negative in %ld cells (clamped), zero beside q in %ld",
                  st.number_negative, st.number_missing);
  return text;
}

}  // namespace

int sl_cmd_info(int argc, char **argv)
{
  sl::Options o("info", "FILE [--time N] [--json]",
                "Describes a storm file: grid, extent in metres, hydrometeor fields with min/max/mean,\n"
                "negative values clamped, times and map projection.");
  o.option("time", "N", "time index for the field statistics and extent", "0");
  o.flag("json", "print one JSON object");
  sl::declare_load_options(o);
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (o.positional().size() != 1) return sl::fail("info", "give exactly one storm FILE", 2);
  const std::string path = o.positional()[0];
  long t;
  if (!o.integer("time", &t, 0, SL_MAX_TIMES - 1)) return sl::fail("info", o.error(), 2);
  sl_error err{};
  std::unique_ptr<sl_storm_info> info(new sl_storm_info);
  if (sl_storm_read_info(path.c_str(), info.get(), &err)) return sl::fail("info", err.message);
  sl::LoadOptions load;
  std::string load_error;
  if (!sl::parse_load_options(o, &load, &load_error)) return sl::fail("info", load_error, 2);
  load.load.time_index = (int)t;
  sl_storm_frame frame;
  if (sl_storm_load(path.c_str(), &load.load, &frame, &err)) return sl::fail("info", err.message);
  const sl_volume &v = frame.volume;
  const double extent[3] = {v.nx * v.spacing[0], v.ny * v.spacing[1], frame.model_top - frame.terrain_min};

  if (o.has("json")) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "file", path.c_str());
    cJSON *grid = cJSON_AddObjectToObject(root, "grid");
    cJSON_AddNumberToObject(grid, "west_east", info->nx);
    cJSON_AddNumberToObject(grid, "south_north", info->ny);
    cJSON_AddNumberToObject(grid, "bottom_top", info->nz);
    cJSON_AddNumberToObject(grid, "dx_m", info->dx);
    cJSON_AddNumberToObject(grid, "dy_m", info->dy);
    cJSON *uni = cJSON_AddObjectToObject(root, "uniform_grid");
    cJSON_AddNumberToObject(uni, "nx", v.nx);
    cJSON_AddNumberToObject(uni, "ny", v.ny);
    cJSON_AddNumberToObject(uni, "nz", v.nz);
    cJSON_AddNumberToObject(uni, "dz_m", v.spacing[2]);
    cJSON *ext = cJSON_AddObjectToObject(root, "extent_m");
    cJSON_AddNumberToObject(ext, "east", extent[0]);
    cJSON_AddNumberToObject(ext, "north", extent[1]);
    cJSON_AddNumberToObject(ext, "up", extent[2]);
    cJSON_AddNumberToObject(root, "terrain_min_m", frame.terrain_min);
    cJSON_AddNumberToObject(root, "terrain_max_m", frame.terrain_max);
    cJSON_AddNumberToObject(root, "model_top_m", frame.model_top);
    cJSON_AddNumberToObject(root, "center_lat", frame.center_lat);
    cJSON_AddNumberToObject(root, "center_lon", frame.center_lon);
    cJSON *proj = cJSON_AddObjectToObject(root, "projection");
    cJSON_AddNumberToObject(proj, "map_proj", info->map_proj);
    cJSON_AddStringToObject(proj, "name", projection_name(info->map_proj));
    cJSON_AddNumberToObject(proj, "truelat1", info->truelat1);
    cJSON_AddNumberToObject(proj, "truelat2", info->truelat2);
    cJSON_AddNumberToObject(proj, "stand_lon", info->stand_lon);
    const sl_georef &g = frame.georef;
    cJSON_AddNumberToObject(proj, "pole_lat", info->pole_lat);
    cJSON_AddNumberToObject(proj, "pole_lon", info->pole_lon);
    cJSON_AddBoolToObject(proj, "rotated_pole", g.projection.rotated);
    cJSON_AddNumberToObject(proj, "grid_north_deg", g.grid_north_deg);
    cJSON_AddNumberToObject(proj, "map_factor_min", g.map_factor_min);
    cJSON_AddNumberToObject(proj, "map_factor_max", g.map_factor_max);
    cJSON_AddNumberToObject(proj, "xlat_xlong_max_disagreement_deg", g.max_error_deg);
    cJSON_AddNumberToObject(proj, "xlat_xlong_max_disagreement_m", g.max_error_m);
    cJSON_AddStringToObject(proj, "placement_from", g.from_xlat ? "XLAT/XLONG" : "projection");
    cJSON_AddBoolToObject(proj, "placed", g.placed);
    cJSON *corners = cJSON_AddObjectToObject(root, "corners");
    const char *const corner_names[4] = {"sw", "se", "ne", "nw"};
    for (int k = 0; k < 4 && g.placed; ++k) {
      cJSON *c = cJSON_AddObjectToObject(corners, corner_names[k]);
      cJSON_AddNumberToObject(c, "lat", g.corner_lat[k]);
      cJSON_AddNumberToObject(c, "lon", g.corner_lon[k]);
    }
    cJSON *enu = cJSON_AddObjectToObject(root, "enu_origin");
    cJSON_AddNumberToObject(enu, "lat", g.origin_lat);
    cJSON_AddNumberToObject(enu, "lon", g.origin_lon);
    cJSON *vol = cJSON_AddObjectToObject(root, "volume_m");
    cJSON_AddNumberToObject(vol, "x0", v.origin[0]);
    cJSON_AddNumberToObject(vol, "y0", v.origin[1]);
    cJSON_AddNumberToObject(vol, "z0", v.origin[2]);
    cJSON_AddNumberToObject(vol, "dx", v.spacing[0]);
    cJSON_AddNumberToObject(vol, "dy", v.spacing[1]);
    cJSON_AddNumberToObject(vol, "dz", v.spacing[2]);
    cJSON_AddNumberToObject(root, "mp_physics", info->mp_physics);
    cJSON_AddStringToObject(root, "format", storm_kind_name(info->kind));
    cJSON_AddStringToObject(root, "netcdf_format", netcdf_format_name(info->format));
    cJSON_AddStringToObject(root, "scheme", info->scheme);
    cJSON_AddStringToObject(root, "vertical", info->vertical);
    cJSON *species = cJSON_AddArrayToObject(root, "species");
    for (int i = 0; i < frame.nspecies; ++i) {
      const sl_species &sp = frame.species[i];
      cJSON *e = cJSON_CreateObject();
      cJSON_AddStringToObject(e, "variable", sp.variable);
      cJSON_AddStringToObject(e, "kind", sp.kind);
      cJSON_AddStringToObject(e, "type", sl_particle_name((sl_particle)sp.warm));
      if (sp.cold != sp.warm) cJSON_AddStringToObject(e, "type_below_0C", sl_particle_name((sl_particle)sp.cold));
      if (sp.number_variable[0]) cJSON_AddStringToObject(e, "number_variable", sp.number_variable);
      cJSON_AddNumberToObject(e, "negative_clamped", (double)frame.species_stats[i].negative_count);
      const sl_field_stats &st = frame.species_stats[i];
      cJSON *sizes = cJSON_AddObjectToObject(e, "sizes");
      const bool sized = sl_species_sized(&sp);
      cJSON_AddStringToObject(sizes, "distribution", sized ? sp.sizes.source : "representative particle");
      cJSON_AddStringToObject(sizes, "number", sp.number_variable[0]           ? "read"
                                               : sp.sizes.fixed_number_m3 > 0.0 ? "assumed"
                                               : sized                          ? "from intercept"
                                                                                : "none");
      if (sized && !sp.number_variable[0] && sp.sizes.fixed_number_m3 > 0.0)
        cJSON_AddNumberToObject(sizes, "assumed_number_m3", sp.sizes.fixed_number_m3);
      if (sized && !sp.number_variable[0] && !(sp.sizes.fixed_number_m3 > 0.0))
        cJSON_AddNumberToObject(sizes, "intercept_m4", sp.sizes.fixed_intercept_m4);
      if (sized) cJSON_AddNumberToObject(sizes, "density_kg_m3", sp.sizes.density_kg_m3);
      if (st.r_eff_max > 0.0) {
        cJSON_AddNumberToObject(sizes, "r_eff_min_m", st.r_eff_min);
        cJSON_AddNumberToObject(sizes, "r_eff_max_m", st.r_eff_max);
      }
      cJSON_AddNumberToObject(sizes, "number_negative_clamped", (double)st.number_negative);
      cJSON_AddNumberToObject(sizes, "number_zero_beside_mass", (double)st.number_missing);
      cJSON_AddItemToArray(species, e);
    }
    cJSON *tables = cJSON_AddArrayToObject(root, "size_tables");
    for (int t = 0; t < SL_PARTICLE_COUNT; ++t) {
      const sl_size_bins &b = frame.sizes;
      if (!b.count[t]) continue;
      cJSON *e = cJSON_CreateObject();
      cJSON_AddStringToObject(e, "type", sl_particle_name((sl_particle)t));
      cJSON *radii = cJSON_AddArrayToObject(e, "effective_radii_m");
      for (int j = 0; j < b.count[t]; ++j) cJSON_AddItemToArray(radii, cJSON_CreateNumber(b.radius_m[t][j]));
      cJSON_AddNumberToObject(e, "cells_r_eff_p01_m", b.range_lo_m[t]);
      cJSON_AddNumberToObject(e, "cells_r_eff_p99_m", b.range_hi_m[t]);
      cJSON_AddBoolToObject(e, "limited_by_fields", b.limited[t]);
      cJSON_AddItemToArray(tables, e);
    }
    cJSON *mem = cJSON_AddObjectToObject(root, "memory");
    cJSON_AddNumberToObject(mem, "estimate_bytes", frame.memory_estimate);
    cJSON_AddNumberToObject(mem, "available_bytes", sl_machine_memory());
    cJSON *times = cJSON_AddArrayToObject(root, "times");
    for (int i = 0; i < info->ntimes; ++i)
      cJSON_AddItemToArray(times, info->has_times ? cJSON_CreateString(info->times[i]) : cJSON_CreateNumber(i));
    if (!info->has_times && info->has_elapsed) {
      cJSON *elapsed = cJSON_AddArrayToObject(root, "elapsed_seconds");
      for (int i = 0; i < info->ntimes; ++i) cJSON_AddItemToArray(elapsed, cJSON_CreateNumber(info->elapsed_s[i]));
    }
    cJSON_AddStringToObject(root, "calendar", info->calendar);
    cJSON_AddNumberToObject(root, "time_index", (double)t);
    cJSON *fields = cJSON_AddObjectToObject(root, "fields");
    for (int p = 0; p < frame.nspecies; ++p) {
      const sl_field_stats &s = frame.species_stats[p];
      cJSON *f = cJSON_AddObjectToObject(fields, frame.species[p].variable);
      cJSON_AddNumberToObject(f, "min_kg_per_kg", s.q_min);
      cJSON_AddNumberToObject(f, "max_kg_per_kg", s.q_max);
      cJSON_AddNumberToObject(f, "mean_kg_per_kg", s.q_mean);
      cJSON_AddNumberToObject(f, "negative_clamped", (double)s.negative_count);
    }
    char *text = cJSON_PrintUnformatted(root);
    std::printf("%s\n", text);
    std::free(text);
    cJSON_Delete(root);
  } else {
    std::printf("file        %s\n", path.c_str());
    std::printf("grid        %d x %d x %d mass points (west_east x south_north x bottom_top), dx %g m, dy %g m\n",
                info->nx, info->ny, info->nz, info->dx, info->dy);
    std::printf("extent      %.1f km east x %.1f km north x %.1f km up (terrain %.0f..%.0f m, top %.0f m)\n",
                extent[0] / 1e3, extent[1] / 1e3, extent[2] / 1e3, frame.terrain_min, frame.terrain_max,
                frame.model_top);
    std::printf("levels      %s\n", info->vertical);
    std::printf("uniform     %d x %d x %d samples, dz %.1f m\n", v.nx, v.ny, v.nz, v.spacing[2]);
    if (std::isfinite(frame.center_lat) && info->map_proj > 0)
      std::printf("projection  %s (MAP_PROJ %d), truelat %g/%g, stand_lon %g; centre %.4f N %.4f E\n",
                  projection_name(info->map_proj), info->map_proj, info->truelat1, info->truelat2, info->stand_lon,
                  frame.center_lat, frame.center_lon);
    else if (std::isfinite(frame.center_lat))
      std::printf("projection  %s; centre %.4f N %.4f E\n", projection_name(info->map_proj), frame.center_lat,
                  frame.center_lon);
    else
      std::printf("projection  none: a flat Cartesian grid with no place on the earth (render places it with "
                  "--origin LAT,LON, the sun with --date or --sun-azimuth/--sun-elevation)\n");
    std::printf("format      %s, %s\n", storm_kind_name(info->kind), netcdf_format_name(info->format));
    if (info->mp_physics >= 0) std::printf("physics     %s (MP_PHYSICS %d)\n", info->scheme, info->mp_physics);
    else std::printf("physics     %s\n", info->scheme);
    std::printf("memory      a load needs about %.1f MB (available %.1f GB)\n", frame.memory_estimate / 1e6,
                sl_machine_memory() / 1e9);
    const sl_georef &g = frame.georef;
    if (g.placed) {
      std::printf("placement   corners SW %.4f %.4f, SE %.4f %.4f, NE %.4f %.4f, NW %.4f %.4f (lat lon)\n",
                  g.corner_lat[0], g.corner_lon[0], g.corner_lat[1], g.corner_lon[1], g.corner_lat[2],
                  g.corner_lon[2], g.corner_lat[3], g.corner_lon[3]);
      if (std::isfinite(g.max_error_deg))
        std::printf("            grid north %.3f deg from true north, map factor %.4f..%.4f, XLAT/XLONG agree with "
                    "the projection to %.2g deg (%.2g m): placed by %s\n",
                    g.grid_north_deg, g.map_factor_min, g.map_factor_max, g.max_error_deg, g.max_error_m,
                    g.from_xlat ? "XLAT/XLONG" : "the projection");
      else
        std::printf("            grid north %.3f deg from true north, map factor %.4f..%.4f: placed by XLAT/XLONG "
                    "(the projection's attributes are not usable, see the note)\n",
                    g.grid_north_deg, g.map_factor_min, g.map_factor_max);
    } else {
      std::printf("placement   %s\n", std::isfinite(frame.center_lat)
                                         ? "by the centre above only (no projection fitted to the grid's columns)"
                                         : "none: the grid has no latitude and longitude");
    }
    if (g.note[0]) std::printf("note        %s\n", g.note);
    std::printf("times       %d", info->ntimes);
    if (std::strcmp(info->calendar, "standard") != 0) std::printf(" (calendar %s)", info->calendar);
    std::printf(":");
    for (int i = 0; i < info->ntimes && i < 8; ++i) {
      if (info->has_times) std::printf(" %s", info->times[i]);
      else if (info->has_elapsed) std::printf(" %g s", info->elapsed_s[i]);
      else std::printf(" (index only)");
    }
    if (!info->has_times && info->has_elapsed) std::printf(" since the run's start (no date: --date gives the start)");
    std::printf("%s\n", info->ntimes > 8 ? " ..." : "");
    std::printf("fields at time %ld (kg/kg):\n", t);
    for (int p = 0; p < frame.nspecies; ++p) {
      const sl_field_stats &s = frame.species_stats[p];
      const sl_species &sp = frame.species[p];
      std::printf("  %-9s min %11.4e  max %11.4e  mean %11.4e  negative clamped %ld  %s -> %s\n", sp.variable,
                  s.q_min, s.q_max, s.q_mean, s.negative_count, sp.kind, species_types(sp).c_str());
      std::printf("  %-9s sizes: %s\n", "", species_sizes(sp, s).c_str());
    }
    for (int t = 0; t < SL_PARTICLE_COUNT; ++t) {
      const sl_size_bins &b = frame.sizes;
      if (!b.count[t]) continue;
      const double um = t == SL_CLOUD ? 1e6 : 1e3;
      const char *unit = t == SL_CLOUD ? "um" : "mm";
      std::printf("optics      %s: ", sl_particle_name((sl_particle)t));
      const char *short_of_fields = "fewer tables than the range asks: no fields left (--max-fields, 8 at most)";
      if (b.count[t] == 1)
        std::printf("one table at r_eff %.3g %s (the cells span %.3g-%.3g %s, 1-99 %%; %s)\n", b.radius_m[t][0] * um,
                    unit, b.range_lo_m[t] * um, b.range_hi_m[t] * um, unit,
                    b.limited[t] ? short_of_fields : "within one step of it");
      else {
        std::printf("tables at r_eff");
        for (int j = 0; j < b.count[t]; ++j) std::printf("%s %.3g", j ? "," : "", b.radius_m[t][j] * um);
        std::printf(" %s, interpolated per cell in ln r_eff (cells %.3g-%.3g %s, 1-99 %%%s%s)\n", unit,
                    b.range_lo_m[t] * um, b.range_hi_m[t] * um, unit, b.limited[t] ? "; " : "",
                    b.limited[t] ? short_of_fields : "");
      }
    }
  }
  sl_storm_frame_free(&frame);
  return 0;
}
