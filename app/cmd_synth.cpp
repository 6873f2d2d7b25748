// stormlight synth: seeded synthetic storms written as WRF-style NetCDF.
#include <cmath>
#include <cstdio>
#include <vector>
#include <string>

#include "cli.h"
#include "commands.h"
#include "sl_synth.h"

int sl_cmd_synth(int argc, char **argv)
{
  sl::Options o("synth", "KIND --out FILE.nc [options]",
                "Writes a seeded synthetic storm as a WRF-style wrfout file (netCDF-4).\n"
                "KIND: cumulonimbus (rain shaft, mixed-phase tower, ice/snow anvil), cirrus (thin ice deck),\n"
                "stratocumulus (flat cellular liquid deck), cumulus (small, optically thin: validation scenes).");
  o.option("out", "FILE", "output NetCDF file");
  o.option("seed", "N", "random seed", "1");
  o.option("nx", "N", "grid points west-east (default per kind)");
  o.option("ny", "N", "grid points south-north (default per kind)");
  o.option("nz", "N", "mass levels (default per kind)");
  o.option("dx", "M", "horizontal grid spacing in metres (default per kind)");
  o.option("times", "N", "number of times (10 minutes apart)", "1");
  o.option("center", "LAT,LON", "the grid's centre, degrees north and east (default per kind)");
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (o.positional().size() != 1) return sl::fail("synth", "give exactly one KIND (cumulonimbus, cirrus, stratocumulus, cumulus)", 2);
  const int kind = sl_synth_kind_from_name(o.positional()[0].c_str());
  if (kind < 0) return sl::fail("synth", "unknown storm kind '" + o.positional()[0] + "'", 2);
  if (!o.has("out")) return sl::fail("synth", "missing --out FILE.nc", 2);
  sl_synth_options so;
  sl_synth_defaults((sl_synth_kind)kind, &so);
  long v;
  if (!o.integer("seed", &v, 0, 2147483647L)) return sl::fail("synth", o.error(), 2);
  so.seed = (uint64_t)v;
  if (!o.integer("times", &v, 1, 1000)) return sl::fail("synth", o.error(), 2);
  so.ntimes = (int)v;
  for (const char *name : {"nx", "ny", "nz"}) {
    if (!o.has(name)) continue;
    if (!o.integer(name, &v, 2, 2048)) return sl::fail("synth", o.error(), 2);
    (name[1] == 'x' ? so.nx : name[1] == 'y' ? so.ny : so.nz) = (int)v;
  }
  if (o.has("dx") && !o.number("dx", &so.dx)) return sl::fail("synth", o.error(), 2);
  if (o.has("center")) {
    std::vector<double> c;
    if (!o.list("center", &c) || c.size() != 2 || !(std::fabs(c[0]) < 80 && std::fabs(c[1]) <= 180))
      return sl::fail("synth", "--center needs LAT,LON with |LAT| < 80 and |LON| <= 180", 2);
    so.center_lat = c[0], so.center_lon = c[1];
  }
  sl_error err{};
  if (sl_synth_write(o.str("out").c_str(), &so, &err)) return sl::fail("synth", err.message);
  std::printf("wrote %s: %s, %dx%dx%d, dx %g m, %d time(s), seed %llu\n", o.str("out").c_str(),
              sl_synth_kind_name(so.kind), so.nx, so.ny, so.nz, so.dx, so.ntimes, (unsigned long long)so.seed);
  return 0;
}
