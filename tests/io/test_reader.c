/* The WRF reader on a synthetic storm with known construction, and on the real Katrina file. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sl_storm.h"
#include "sl_synth.h"
#include "sl_testing.h"

int main(void)
{
  sl_error err = {0};
  char path[] = "/tmp/sl_test_reader_XXXXXX.nc";
  close(mkstemps(path, 3));
  sl_synth_options o;
  sl_synth_defaults(SL_SYNTH_STRATOCUMULUS, &o);
  o.nx = 12, o.ny = 10, o.nz = 16, o.ntimes = 2;
  CHECK(sl_synth_write(path, &o, &err) == SL_OK);
  sl_storm_info *info = malloc(sizeof *info);
  CHECK(sl_storm_read_info(path, info, &err) == SL_OK);
  CHECK(info->nx == 12 && info->ny == 10 && info->nz == 16 && info->ntimes == 2);
  CHECK(info->has_times);
  CHECK(strcmp(info->times[1], "2024-07-01_19:10:00") == 0);
  CHECK_CLOSE(info->dx, 250.0, 0.0, 0.0);
  CHECK(info->map_proj == 1);
  sl_storm_frame f;
  sl_load_options lo = {.time_index = 1, .dz = 50.0};
  CHECK(sl_storm_load(path, &lo, &f, &err) == SL_OK);
  CHECK(f.volume.nx == 12 && f.volume.ny == 10);
  CHECK_CLOSE(f.volume.spacing[2], 50.0, 0.0, 0.0);
  /* The grid is centred on its own centre: x from -(nx-1)/2 times the ground spacing, which is
   * DX over the Lambert map factor (within 1 % of DX between the generator's true latitudes;
   * tests/io/test_projection.c checks it against PROJ). */
  CHECK_CLOSE(f.volume.origin[0], -5.5 * f.volume.spacing[0], 1e-12, 1e-9);
  CHECK_CLOSE(f.volume.spacing[0], 250.0, 0.01, 0.0);
  /* Model top 3000 m over a sea-level ocean: 60 levels of 50 m. */
  CHECK_CLOSE(f.model_top, 3000.0, 1e-4, 0.0);
  CHECK(f.volume.nz == 60);
  /* The generator centres the domain on its stated latitude and longitude. */
  CHECK_CLOSE(f.center_lat, o.center_lat, 0.0, 0.02);
  CHECK_CLOSE(f.center_lon, o.center_lon, 0.0, 0.02);
  /* The deck lies between about 600 and 1200 m: no cloud in the top and bottom levels. */
  double low = 0, deck = 0, high = 0;
  for (int k = 0; k < f.volume.nz; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 12; ++i) {
        const double z = f.volume.origin[2] + k * 50.0;
        const double e = f.volume.eta[SL_CLOUD][sl_volume_index(&f.volume, i, j, k)];
        if (z < 500) low += e;
        else if (z < 1300) deck += e;
        else high += e;
      }
  CHECK(deck > 0.0);
  CHECK_CLOSE(high, 0.0, 0.0, 0.0);
  CHECK(low < 1e-6 * deck);
  sl_storm_frame_free(&f);
  lo.time_index = 2;
  sl_error_clear(&err);
  CHECK(sl_storm_load(path, &lo, &f, &err) == SL_ERR_ARG);
  unlink(path);
  free(info);

  /* The real Katrina file: WSM3, negative QRAIN clamped and counted, ice split off QCLOUD. */
  const char *shared = getenv("SL_SHARED_DIR");
  char real[4096];
  snprintf(real, sizeof real, "%s/data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc", shared ? shared : "../shared");
  sl_load_options l0 = {.time_index = 0};
  sl_error_clear(&err);
  if (CHECK(sl_storm_load(real, &l0, &f, &err) == SL_OK)) {
    CHECK(f.stats[SL_RAIN].negative_count > 0);
    CHECK(f.stats[SL_RAIN].q_min < 0.0);
    CHECK(f.volume.eta[SL_ICE] != NULL && f.volume.eta[SL_SNOW] != NULL);
    CHECK(f.volume.nx == 48 && f.volume.ny == 48);
    /* A hurricane in the Gulf of Mexico. */
    CHECK(f.center_lat > 20 && f.center_lat < 30 && f.center_lon > -95 && f.center_lon < -80);
    sl_storm_frame_free(&f);
  } else {
    fprintf(stderr, "%s\n", err.message);
  }
  return sl_test_finish("test_reader");
}
