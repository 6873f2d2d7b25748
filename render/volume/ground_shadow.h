/* The ground under the storm (ground_shadow.c): a flat Lambertian ground at sea level lit by the sun
 * through the storm's shadow and by the clear sky, as the background draws it where a pixel's ray
 * meets the ground. Built once per sun. */
#ifndef SL_GROUND_SHADOW_H
#define SL_GROUND_SHADOW_H

#include <stddef.h>

#include "sl_sky.h"
#include "sl_status.h"

struct sl_renderer;

typedef struct sl__ground {
  int on;                /* the scene's albedo is above 0, the air is there and the sun is up */
  int n[2];              /* the shadow map's cells along x and y */
  double origin[2];      /* the centre of cell (0, 0), world metres */
  double spacing[2];
  /* The storm's transparency toward the sun from each cell's centre on the ground, x fastest;
   * 1 off the map. */
  float *shadow;
  /* albedo / pi times the sun's irradiance on the horizontal ground and times the clear sky's
   * (sl_sky_ground_irradiance), per wavelength: the ground's radiance is sun S + sky. */
  double sun[SL_SKY_MAX_WAVELENGTHS], sky[SL_SKY_MAX_WAVELENGTHS];
} sl__ground;

int sl__ground_build(struct sl_renderer *r, sl_error *err);
void sl__ground_free(sl__ground *g);

/* The map's transparency at world (x, y), bilinear between cell centres, 1 off the map. */
static inline double sl__ground_shadow_at(const sl__ground *g, double x, double y)
{
  const double u = (x - g->origin[0]) / g->spacing[0], v = (y - g->origin[1]) / g->spacing[1];
  if (!(u >= 0.0 && v >= 0.0 && u <= g->n[0] - 1 && v <= g->n[1] - 1)) return 1.0;
  int i = (int)u, j = (int)v;
  if (i > g->n[0] - 2) i = g->n[0] - 2;
  if (j > g->n[1] - 2) j = g->n[1] - 2;
  const double fu = u - i, fv = v - j;
  const float *s = g->shadow + (size_t)j * g->n[0] + i;
  const size_t row = (size_t)g->n[0];
  return (1 - fv) * ((1 - fu) * s[0] + fu * s[1]) + fv * ((1 - fu) * s[row] + fu * s[row + 1]);
}

#endif
