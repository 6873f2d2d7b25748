/* The ground under the storm: its shadow map toward the sun and the light on it (ground_shadow.h).
 * The map covers the content box's shadow on the plane z = 0 (the box's corners carried along the
 * sunlight), at the grid's horizontal spacing (coarser past 512 cells a side), each cell's
 * transparency by the midpoint rule through the total extinction at the finest spacing (a shadow
 * blurred by the map's cells anyway). On the round earth the ground's light is taken at the
 * tangent point for the whole map (within a few hundred km of it the sun's elevation changes by
 * a few degrees). */
#include "ground_shadow.h"

#include <math.h>
#include <stdlib.h>

#include "renderer_internal.h"

#define GROUND_MAP_MAX 512

void sl__ground_free(sl__ground *g)
{
  free(g->shadow);
  g->shadow = NULL;
  g->on = 0;
}

int sl__ground_build(sl_renderer *r, sl_error *err)
{
  sl__ground *g = &r->ground;
  sl__ground_free(g);
  const sl_scene *sc = &r->scene;
  const double *sun = sc->sun_direction;
  if (!(sc->ground_albedo > 0.0) || !sc->atmosphere || !(sun[2] > 0.0)) return SL_OK;
  double E_sky[SL_SKY_MAX_WAVELENGTHS], E_sun[SL_SKY_MAX_WAVELENGTHS];
  int night = 0;
  if (sl_sky_ground_irradiance(sc->atmosphere, sun, E_sky, E_sun, &night, err)) return err->code;
  if (night) return SL_OK;
  for (int c = 0; c < r->model.nwl; ++c)
    g->sun[c] = sc->ground_albedo / M_PI * E_sun[c], g->sky[c] = sc->ground_albedo / M_PI * E_sky[c];
  /* The content box's shadow on z = 0. */
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (int corner = 0; corner < 8; ++corner) {
    const double p[3] = {corner & 1 ? r->chi[0] : r->clo[0], corner & 2 ? r->chi[1] : r->clo[1],
                         corner & 4 ? r->chi[2] : r->clo[2]};
    const double t = p[2] / sun[2];
    for (int a = 0; a < 2; ++a) {
      const double x = p[a] - t * sun[a];
      lo[a] = fmin(lo[a], x), hi[a] = fmax(hi[a], x);
    }
  }
  for (int a = 0; a < 2; ++a) {
    double h = r->shape.spacing[a];
    if ((hi[a] - lo[a]) / h + 3 > GROUND_MAP_MAX) h = (hi[a] - lo[a]) / (GROUND_MAP_MAX - 3);
    g->spacing[a] = h;
    g->origin[a] = lo[a] - h;
    g->n[a] = (int)ceil((hi[a] - lo[a]) / h) + 3;
  }
  g->shadow = malloc((size_t)g->n[0] * g->n[1] * sizeof(float));
  if (!g->shadow) return sl_fail(err, SL_ERR_NOMEM, "ground: out of memory for its shadow map");
  const double step = fmin(r->shape.spacing[0], fmin(r->shape.spacing[1], r->shape.spacing[2]));
#pragma omp parallel for schedule(dynamic, 4)
  for (int j = 0; j < g->n[1]; ++j)
    for (int i = 0; i < g->n[0]; ++i) {
      const double p[3] = {g->origin[0] + i * g->spacing[0], g->origin[1] + j * g->spacing[1], 0.0};
      double t0, t1, tau = 0.0, unused;
      if (r->any_extinction && sl_ray_box(r->clo, r->chi, p, sun, &t0, &t1) && t1 > 0.0)
        tau = sl__optical_depth(r, p, sun, fmax(t0, 0.0), t1, step, INFINITY, &unused);
      g->shadow[(size_t)j * g->n[0] + i] = (float)exp(-tau);
    }
  g->on = 1;
  return SL_OK;
}
