/* Delta tracking (Woodcock et al. 1965) and ratio tracking (Novak, Selle & Jarosz 2014) through
 * a coarse majorant grid walked by a 3-D DDA (Amanatides & Woo 1987), the scheme of pbrt-v4's
 * grid media: a cell whose majorant is zero is crossed in one step, whatever its length. */
#include <math.h>

#include "reference_internal.h"

/* A path that keeps circling a periodic medium (a horizontal ray in an empty layer) would never
 * end; after this many crossings of a side it counts as having left through it. */
#define MAX_WRAPS 100000

/* Distance from x along d to the box's boundary and the axis of the face it leaves through. */
static double exit_distance(const sl_ref_medium *m, const double x[3], const double d[3], int *axis)
{
  double best = INFINITY;
  *axis = 2;
  for (int a = 0; a < 3; ++a) {
    double t;
    if (d[a] > 0.0) t = (m->hi[a] - x[a]) / d[a];
    else if (d[a] < 0.0) t = (m->lo[a] - x[a]) / d[a];
    else continue;
    if (t < best) {
      best = t;
      *axis = a;
    }
  }
  return best > 0.0 ? best : 0.0;
}

typedef struct dda {
  int b[3], step[3];
  double tmax[3], tdelta[3];
} dda;

static void dda_init(const sl_ref_medium *m, const double x[3], const double d[3], dda *s)
{
  for (int a = 0; a < 3; ++a) {
    int b = (int)floor((x[a] - m->lo[a]) / m->block_size[a]);
    b = b < 0 ? 0 : b > m->nb[a] - 1 ? m->nb[a] - 1 : b;
    s->b[a] = b;
    if (d[a] > 0.0) {
      s->step[a] = 1;
      s->tmax[a] = fmax(0.0, (m->lo[a] + (b + 1) * m->block_size[a] - x[a]) / d[a]);
      s->tdelta[a] = m->block_size[a] / d[a];
    } else if (d[a] < 0.0) {
      s->step[a] = -1;
      s->tmax[a] = fmax(0.0, (m->lo[a] + b * m->block_size[a] - x[a]) / d[a]);
      s->tdelta[a] = -m->block_size[a] / d[a];
    } else {
      s->step[a] = 0;
      s->tmax[a] = INFINITY;
      s->tdelta[a] = INFINITY;
    }
  }
}

static double dda_cell_end(const dda *s)
{
  return fmin(s->tmax[0], fmin(s->tmax[1], s->tmax[2]));
}

static float dda_majorant(const sl_ref_medium *m, int w, const dda *s)
{
  return m->majorant[w][((size_t)s->b[2] * m->nb[1] + s->b[1]) * m->nb[0] + s->b[0]];
}

/* Steps into the next cell; 0 when that leaves the majorant grid. */
static int dda_advance(dda *s, const int nb[3])
{
  const int a = s->tmax[0] < s->tmax[1] ? (s->tmax[0] < s->tmax[2] ? 0 : 2) : (s->tmax[1] < s->tmax[2] ? 1 : 2);
  s->b[a] += s->step[a];
  if (s->b[a] < 0 || s->b[a] >= nb[a]) return 0;
  s->tmax[a] += s->tdelta[a];
  return 1;
}

/* Moves x to the boundary point t_exit along d and, for a periodic side, to the opposite face.
 * Returns 1 when the path goes on inside the box. */
static int cross_boundary(const sl_ref_medium *m, double x[3], const double d[3], double t_exit, int axis)
{
  for (int a = 0; a < 3; ++a) x[a] += t_exit * d[a];
  if (axis == 2 || m->desc.lateral != SL_REF_PERIODIC) return 0;
  x[axis] = d[axis] > 0.0 ? m->lo[axis] : m->hi[axis];
  /* Rounding must not leave the other coordinates a hair outside the box. */
  for (int a = 0; a < 3; ++a) x[a] = x[a] < m->lo[a] ? m->lo[a] : x[a] > m->hi[a] ? m->hi[a] : x[a];
  return 1;
}

track_event ref_track(const sl_ref_medium *m, int w, double x[3], const double d[3], sl_ref_rng *rng,
                      double *travelled)
{
  double covered = 0.0;
  for (int wraps = 0; wraps < MAX_WRAPS; ++wraps) {
    int axis;
    const double t_exit = exit_distance(m, x, d, &axis);
    dda s;
    dda_init(m, x, d, &s);
    double t = 0.0;
    while (t < t_exit) {
      const double t_end = fmin(dda_cell_end(&s), t_exit);
      const double maj = dda_majorant(m, w, &s);
      if (maj > 0.0) {
        for (;;) {
          /* Free flight in the majorant medium; memoryless, so a cell boundary simply restarts it. */
          t -= log(1.0 - sl_ref_rng_uniform(rng)) / maj;
          if (t >= t_end) break;
          const double p[3] = {x[0] + t * d[0], x[1] + t * d[1], x[2] + t * d[2]};
          if (sl_ref_rng_uniform(rng) * maj < sl_ref_extinction(m, w, p)) {
            x[0] = p[0], x[1] = p[1], x[2] = p[2];
            if (travelled) *travelled = covered + t;
            return TRACK_COLLISION;
          }
        }
      }
      t = t_end;
      if (t >= t_exit || !dda_advance(&s, m->nb)) break;
    }
    covered += t_exit;
    if (cross_boundary(m, x, d, t_exit, axis)) continue;
    if (travelled) *travelled = covered;
    if (axis == 2) return d[2] > 0.0 ? TRACK_TOP : TRACK_BOTTOM;
    return TRACK_SIDE;
  }
  if (travelled) *travelled = covered;
  return TRACK_SIDE;
}

double ref_transmittance(const sl_ref_medium *m, int w, const double x_in[3], const double d[3], double length,
                         sl_ref_rng *rng)
{
  double x[3] = {x_in[0], x_in[1], x_in[2]};
  double transmittance = 1.0, remaining = length;
  for (int wraps = 0; wraps < MAX_WRAPS && remaining > 0.0; ++wraps) {
    int axis;
    double t_exit = exit_distance(m, x, d, &axis);
    int stops_inside = 0;
    if (remaining < t_exit) {
      t_exit = remaining;
      stops_inside = 1;
    }
    dda s;
    dda_init(m, x, d, &s);
    double t = 0.0;
    while (t < t_exit) {
      const double t_end = fmin(dda_cell_end(&s), t_exit);
      const double maj = dda_majorant(m, w, &s);
      if (maj > 0.0) {
        for (;;) {
          t -= log(1.0 - sl_ref_rng_uniform(rng)) / maj;
          if (t >= t_end) break;
          const double p[3] = {x[0] + t * d[0], x[1] + t * d[1], x[2] + t * d[2]};
          transmittance *= fmax(0.0, 1.0 - sl_ref_extinction(m, w, p) / maj);
          /* Russian roulette: a nearly opaque path costs as much as a clear one without it. */
          if (transmittance < 0.05) {
            if (sl_ref_rng_uniform(rng) < 0.5) return 0.0;
            transmittance *= 2.0;
          }
        }
      }
      t = t_end;
      if (t >= t_exit || !dda_advance(&s, m->nb)) break;
    }
    if (stops_inside) break;
    remaining -= t_exit;
    if (!cross_boundary(m, x, d, t_exit, axis)) break;
  }
  return transmittance;
}
