// stormlight info: what a storm file holds, as a meteorologist wants to see it.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "cli.h"
#include "commands.h"
#include "sl_storm.h"
#include "sl_storm_json.h"

namespace {

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
  sl::LoadOptions load;
  std::string load_error;
  if (!sl::parse_load_options(o, &load, &load_error)) return sl::fail("info", load_error, 2);
  load.load.time_index = (int)t;
  if (o.has("json")) {
    // The same description the Python package's Storm.info() returns (scene/sl_storm_json.h).
    char *text = sl_storm_info_json(path.c_str(), &load.load, &err);
    if (!text) return sl::fail("info", err.message);
    std::printf("%s\n", text);
    std::free(text);
    return 0;
  }
  std::unique_ptr<sl_storm_info> info(new sl_storm_info);
  if (sl_storm_read_info(path.c_str(), info.get(), &err)) return sl::fail("info", err.message);
  sl_storm_frame frame;
  if (sl_storm_load(path.c_str(), &load.load, &frame, &err)) return sl::fail("info", err.message);
  const sl_volume &v = frame.volume;
  const double extent[3] = {v.nx * v.spacing[0], v.ny * v.spacing[1], frame.model_top - frame.terrain_min};

  {
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
                  sl_projection_name(info->map_proj), info->map_proj, info->truelat1, info->truelat2, info->stand_lon,
                  frame.center_lat, frame.center_lon);
    else if (std::isfinite(frame.center_lat))
      std::printf("projection  %s; centre %.4f N %.4f E\n", sl_projection_name(info->map_proj), frame.center_lat,
                  frame.center_lon);
    else
      std::printf("projection  none: a flat Cartesian grid with no place on the earth (render places it with "
                  "--origin LAT,LON, the sun with --date or --sun-azimuth/--sun-elevation)\n");
    std::printf("format      %s, %s\n", sl_storm_kind_name(info->kind), sl_netcdf_format_name(info->format));
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
