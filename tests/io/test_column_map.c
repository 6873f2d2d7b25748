/* The column map (io/column_map.c) and the terrain's height between lattice points
 * (render/surface, sl_heightfield_height_at), against closed forms: on an affine latitude-longitude
 * lattice the bilinear map is the affine map, so Newton's inversion must return the solution of
 * its 2 x 2 linear system; on a planar terrain the triangles are that plane everywhere; at the
 * lattice points and on a cell's diagonal the height is the values there. */
#include <math.h>

#include "sl_georef.h"
#include "sl_terrain.h"
#include "sl_testing.h"

int main(void)
{
  enum { NX = 7, NY = 5 };
  double lat[NX * NY], lon[NX * NY];
  /* lon = 10 + 0.1 i + 0.02 j, lat = 40 + 0.01 i + 0.08 j: a rotated, sheared lattice. */
  for (int j = 0; j < NY; ++j)
    for (int i = 0; i < NX; ++i) lon[j * NX + i] = 10 + 0.1 * i + 0.02 * j, lat[j * NX + i] = 40 + 0.01 * i + 0.08 * j;
  const double origin[2] = {-3000, -2000}, spacing[2] = {1000, 1000};
  sl_column_map m;
  sl_column_map_init(&m, NX, NY, lat, lon, origin, spacing);
  const double points[][2] = {{2.3, 1.7}, {0.0, 0.0}, {6.0, 4.0}, {5.99, 0.01}, {3.5, 2.5}};
  for (size_t k = 0; k < sizeof points / sizeof points[0]; ++k) {
    const double fi = points[k][0], fj = points[k][1];
    const double plon = 10 + 0.1 * fi + 0.02 * fj, plat = 40 + 0.01 * fi + 0.08 * fj;
    double gi, gj;
    CHECK(sl_column_map_to_grid(&m, plat, plon, &gi, &gj));
    CHECK_CLOSE(gi, fi, 0, 1e-7);
    CHECK_CLOSE(gj, fj, 0, 1e-7);
  }
  double gi, gj;
  CHECK(!sl_column_map_to_grid(&m, 40 + 0.08 * 2, 10 - 0.3, &gi, &gj)); /* west of the lattice */
  double x, y;
  sl_column_map_world(&m, 2.5, 1.0, &x, &y);
  CHECK_CLOSE(x, -500, 0, 1e-9);
  CHECK_CLOSE(y, -1000, 0, 1e-9);
  double lon0, lon1, lat0, lat1;
  sl_column_map_range(&m, &lon0, &lon1, &lat0, &lat1);
  CHECK_CLOSE(lon0, 10, 0, 1e-12);
  CHECK_CLOSE(lon1, 10.68, 0, 1e-12);
  CHECK_CLOSE(lat1, 40.38, 0, 1e-12);

  /* A planar terrain h = 100 + 20 i - 7 j: every point of the triangles lies on it. */
  float h[NX * NY];
  for (int j = 0; j < NY; ++j)
    for (int i = 0; i < NX; ++i) h[j * NX + i] = (float)(100 + 20 * i - 7 * j);
  sl_heightfield hf;
  sl_heightfield_init(&hf, NX, NY, origin, spacing, h);
  for (size_t k = 0; k < sizeof points / sizeof points[0]; ++k)
    CHECK_CLOSE(sl_heightfield_height_at(&hf, points[k][0], points[k][1]), 100 + 20 * points[k][0] - 7 * points[k][1],
                1e-12, 1e-9);
  /* Outside the lattice: clamped to its edge. */
  CHECK_CLOSE(sl_heightfield_height_at(&hf, -1.0, 0.0), 100, 0, 1e-9);
  /* A bump at one point: its value there, the diagonal's mean where it crosses the cell. */
  h[2 * NX + 3] = 1000.0f;
  CHECK_CLOSE(sl_heightfield_height_at(&hf, 3.0, 2.0), 1000, 0, 1e-9);
  const double h22 = 100 + 40 - 14;
  CHECK_CLOSE(sl_heightfield_height_at(&hf, 2.5, 1.5), 0.5 * (100 + 20 * 2 - 7 * 1) + 0.5 * 1000, 1e-12, 1e-9);
  CHECK_CLOSE(sl_heightfield_height_at(&hf, 2.0, 2.0), h22, 1e-12, 1e-9);
  return sl_test_finish("test_column_map");
}
