/* The ground under the storm as a CF file describes it (io/cf_load.c): surface_albedo, and land
 * or water from land_binary_mask, else land_area_fraction, in the volume's column order. The file
 * here stores latitudes north to south, so its first row is the volume's last; the expected
 * columns are the file's rows written out reversed by hand. Percent is a fraction; a land mask on
 * another grid is passed over and the load goes on. */
#include <stdio.h>
#include <stdlib.h>

#include "ncgen_file.h"
#include "sl_storm.h"
#include "sl_testing.h"

static char dir[] = "/tmp/sl_test_surface_XXXXXX";

/* A 3 x 2 lat-lon grid, one level, a little cloud, and the surface variables decl declares and
 * data fills. */
static const char *write_cf(const char *name, const char *decl, const char *data)
{
  static char nc[4][512];
  static int which;
  char cdl[4096];
  snprintf(cdl, sizeof cdl,
           "netcdf %s {\n dimensions: time = 1 ; z = 1 ; lat = 2 ; lon = 3 ; other = 4 ;\n variables:\n"
           " double time(time) ; time:units = \"hours since 2024-06-15 00:00:00\" ;\n"
           " float z(z) ; z:units = \"m\" ; z:positive = \"up\" ;\n"
           " float lat(lat) ; lat:units = \"degrees_north\" ; float lon(lon) ; lon:units = \"degrees_east\" ;\n"
           " float cl(time, z, lat, lon) ; cl:standard_name = \"mass_fraction_of_cloud_liquid_water_in_air\" ;\n"
           " float ta(time, z, lat, lon) ; ta:standard_name = \"air_temperature\" ;\n"
           " float pa(time, z, lat, lon) ; pa:standard_name = \"air_pressure\" ;\n%s"
           " data:\n time = 0 ; z = 500 ; lat = 30.1, 30.0 ; lon = -90.0, -89.9, -89.8 ;\n"
           " cl = 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4 ; ta = 290, 290, 290, 290, 290, 290 ;\n"
           " pa = 90000, 90000, 90000, 90000, 90000, 90000 ;\n%s}\n",
           name, decl, data);
  char *out = nc[which++ % 4];
  sl_test_ncgen(dir, name, cdl, out, sizeof nc[0]);
  return out;
}

static int load(const char *path, sl_storm_frame *f)
{
  sl_error err = {0};
  sl_load_options zero = {0};
  const int rc = sl_storm_load(path, &zero, f, &err);
  if (rc) fprintf(stderr, "%s\n", err.message);
  return rc;
}

static void check_columns(const float *got, const float *want, const char *what)
{
  if (!CHECK_MSG(got != NULL, what)) return;
  for (int c = 0; c < 6; ++c) CHECK_CLOSE(got[c], want[c], 0, 1e-6);
}

int main(void)
{
  if (!mkdtemp(dir)) return 1;
  sl_storm_frame f;
  /* File rows north (30.1) then south (30.0); the volume's columns south first. */
  const char *both = write_cf("both",
                              " float lsm(time, lat, lon) ; lsm:standard_name = \"land_binary_mask\" ;\n"
                              " float alb(lat, lon) ; alb:standard_name = \"surface_albedo\" ; alb:units = \"%\" ;\n",
                              " lsm = 1, 1, 0, 0, 0, 1 ;\n alb = 20, 21, 6, 7, 8, 19 ;\n");
  if (CHECK(load(both, &f) == SL_OK)) {
    CHECK(f.volume.nx == 3 && f.volume.ny == 2);
    check_columns(f.land_mask, (const float[]){0, 0, 1, 1, 1, 0}, "land_binary_mask");
    check_columns(f.surface_albedo, (const float[]){0.07f, 0.08f, 0.19f, 0.20f, 0.21f, 0.06f}, "surface_albedo in %");
    sl_storm_frame_free(&f);
  }
  const char *fraction = write_cf("fraction", " float laf(lat, lon) ; laf:standard_name = \"land_area_fraction\" ;\n",
                                  " laf = 0.5, 1, 0, 0.25, 0, 0 ;\n");
  if (CHECK(load(fraction, &f) == SL_OK)) {
    check_columns(f.land_mask, (const float[]){0.25f, 0, 0, 0.5f, 1, 0}, "land_area_fraction");
    CHECK(f.surface_albedo == NULL);
    sl_storm_frame_free(&f);
  }
  const char *other = write_cf("other", " float lsm(other) ; lsm:standard_name = \"land_binary_mask\" ;\n",
                               " lsm = 1, 0, 1, 0 ;\n");
  if (CHECK(load(other, &f) == SL_OK)) {
    CHECK_MSG(f.land_mask == NULL, "a land mask on another grid is passed over");
    sl_storm_frame_free(&f);
  }
  char cmd[700];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
  return sl_test_finish("test_reader_surface");
}
