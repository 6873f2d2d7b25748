/* The sunlight reaching a point of the content box through the air, tabulated over altitude once
 * per frame (sun_table.c), and its branch-free look-ups for the eye passes' batches. */
#ifndef SL_SUN_TABLE_H
#define SL_SUN_TABLE_H

#include <stddef.h>

#include "sl_renderer.h"
#include "sl_sky.h"

/* Sunlight reaching a point through the air (Riley eq. 12 with the view's air mass), tabulated
 * over the altitudes (sl_sky_altitude: above the plane z = 0, or above the sphere with
 * `--curvature drop`) the box spans, once per frame, so the eye pass only interpolates. */
#define SUN_TABLE_SIZE 257
typedef struct sun_table {
  int nwl;
  const sl_atmosphere *atm; /* whose ground the altitudes are above; NULL: no air, one value */
  double z0, dz;            /* altitude of row 0, altitude step */
  double rgb[SUN_TABLE_SIZE][SL_MAX_WAVELENGTHS];
} sun_table;

void sl__sun_table_init(sun_table *t, const sl_scene *sc, const sl_sky_view *view, const double lo[3],
                        const double hi[3]);
/* The sun table's row and the fraction past it at world point x's altitude, with no branch: round
 * (whether the ground is round, of radius R) and inv_dz (rows per metre, 0 for one row) are the
 * caller's invariants (sl__sun_table_lane), so that the eye pass's loop over a batch vectorises. */
typedef struct sl__sun_lane {
  int round;
  double R, inv_dz;
} sl__sun_lane;

static inline sl__sun_lane sl__sun_table_lane(const sun_table *t)
{
  sl__sun_lane s;
  s.round = t->atm && t->atm->ground_radius > 0.0;
  s.R = s.round ? t->atm->ground_radius : 0.0;
  s.inv_dz = t->dz > 0.0 ? 1.0 / t->dz : 0.0;
  return s;
}

static inline __attribute__((always_inline)) void sl__sun_row(const sun_table *t, const sl__sun_lane *s,
                                                              const double x[3], int *row, double *frac)
{
  const double z = s->round ? sl_sky_altitude_round(s->R, x) : x[2];
  double u = (z - t->z0) * s->inv_dz;
  u = u < 0.0 ? 0.0 : u > SUN_TABLE_SIZE - 1 ? SUN_TABLE_SIZE - 1 : u;
  int i = (int)u;
  i = i < SUN_TABLE_SIZE - 2 ? i : SUN_TABLE_SIZE - 2;
  *row = i, *frac = u - i;
}

/* The table's sunlight at wavelength c, a fraction frac past row (sl__sun_row); rgb is the table's
 * first value, flat (rows SL_MAX_WAVELENGTHS apart), so that a loop over samples gathers from it. */
static inline __attribute__((always_inline)) double sl__sun_lerp(const double *rgb, int row, double frac, int c)
{
  const ptrdiff_t i = (ptrdiff_t)row * SL_MAX_WAVELENGTHS + c;
  return rgb[i] + frac * (rgb[i + SL_MAX_WAVELENGTHS] - rgb[i]);
}

/* The sunlight at world point x: the table at x's altitude (s: sl__sun_table_lane(t)). */
static inline __attribute__((always_inline)) void sl__sun_at(const sun_table *t, const sl__sun_lane *s,
                                                             const double x[3], double *out)
{
  int i;
  double f;
  sl__sun_row(t, s, x, &i, &f);
  for (int c = 0; c < t->nwl; ++c) out[c] = sl__sun_lerp(&t->rgb[0][0], i, f, c);
}

#endif
