/* How far a clear ray of the light-volume march kept from any medium, so that the adaptive
 * refinement (pixel_refine.h) may fill a block of clear rays without marching the rays between
 * them, knowing those rays are clear too.
 *
 * The clearance C(x) of a point is its Chebyshev distance, in grid cells, to the nearest cell
 * holding medium (a cell with a non-zero corner; every trilinear sample outside such cells is
 * exactly zero). C is 1-Lipschitz in that distance, so along the ray o + t d it falls by at most
 * `rate` = max_a |d_a| / spacing_a per unit of t. The march knows a lower bound of C at
 * checkpoints: its steps in occupied bricks (from the clearance of their 2^3-cell block,
 * sl__clear_blocks_build) and where it jumps a cube of empty bricks (the distance to the cube's
 * faces, which also bounds C along the jump, as the distance to a convex cube's boundary is
 * concave along a chord). Between two checkpoints the larger of the two bounds carried from
 * either side holds; before the box's entry and after its exit, C is at least the distance to
 * the box (which holds every medium cell) along the axis of the face crossed.
 *
 * The tracker keeps the smallest of min C / t over each stretch, `ratio`: a ray d' within an
 * angle of `a` of d (|d' - d| <= a, unit vectors) lies within t a / spacing_min cells of it at
 * every t, so every point of it has clearance above ratio t - t a / spacing_min, and it meets no
 * medium cell where ratio > a / spacing_min. */
#ifndef SL_CLEAR_MARGIN_H
#define SL_CLEAR_MARGIN_H

#include <math.h>

typedef struct sl__clear_margin {
  double rate;         /* cells per unit of t along the ray (Chebyshev) */
  double t0, entry;    /* where the ray enters the box, and how fast it nears it before (cells per t) */
  double t, v, slope;  /* the last checkpoint: where, C's bound there, how fast that bound falls after it */
  double ratio;        /* the smallest bound of C / t so far; 0 once it cannot hold */
  int started;         /* a checkpoint is held */
} sl__clear_margin;

/* The least, over lo <= s <= hi, of the larger of a line falling from a at lo by `fall` per unit
 * and one rising to b at hi by `rise` per unit (fall, rise >= 0): where they cross, or an end. */
static inline double sl__clear_least_of_larger(double a, double fall, double b, double rise, double lo, double hi)
{
  const double left_at_hi = a - fall * (hi - lo), right_at_lo = b - rise * (hi - lo);
  if (left_at_hi >= b) return left_at_hi;
  if (right_at_lo >= a) return right_at_lo;
  const double s = (a - b + rise * (hi - lo)) / (fall + rise);
  return a - fall * s;
}

static inline void sl__clear_margin_begin(sl__clear_margin *m, double rate, double t0, double entry)
{
  m->rate = rate, m->t0 = t0, m->entry = entry;
  m->t = m->v = m->slope = 0.0;
  m->ratio = INFINITY;
  m->started = 0;
}

/* A checkpoint at t (after the last) where C >= v, from which the bound falls by `slope` per unit
 * of t (at most rate). */
static inline void sl__clear_margin_point(sl__clear_margin *m, double t, double v, double slope)
{
  if (!(m->ratio > 0.0)) return;
  if (!(v > 0.0 && t > 0.0)) {
    m->ratio = 0.0;
    return;
  }
  double least;
  if (!m->started) /* from the camera: the distance to the box before the entry, then this point's */
    least = sl__clear_least_of_larger(m->entry * m->t0, m->entry, v, m->rate, 0.0, t);
  else
    least = sl__clear_least_of_larger(m->v, m->slope, v, m->rate, m->t, t);
  const double r = least / t;
  m->ratio = r < m->ratio ? r : m->ratio;
  if (!(m->ratio > 0.0)) m->ratio = 0.0;
  m->t = t, m->v = v, m->slope = slope < m->rate ? slope : m->rate;
  m->started = 1;
}

/* The ray left the box at t1, moving away from it by `exit` cells per unit of t after; no ray of
 * the camera reaches the box past t_far. Returns the ray's ratio (0: no bound). */
static inline double sl__clear_margin_end(sl__clear_margin *m, double t1, double exit, double t_far)
{
  if (!m->started || !(m->ratio > 0.0) || !(t_far > m->t)) return 0.0;
  const double least = sl__clear_least_of_larger(m->v, m->slope, exit * (t_far - t1), exit, m->t, t_far);
  const double r = least / t_far;
  return r < m->ratio ? (r > 0.0 ? r : 0.0) : m->ratio;
}

/* How fast the ray o + t d nears the box [lo, hi] before it enters (along the axis whose face it
 * enters by) and leaves it after it exits, in cells per unit of t (inv_spacing: cells per unit
 * length along each axis). */
static inline void sl__clear_box_rates(const double lo[3], const double hi[3], const double o[3], const double d[3],
                                       const double inv_spacing[3], double *entry, double *exit)
{
  double t_in = -INFINITY, t_out = INFINITY;
  *entry = *exit = 0.0;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) continue;
    const double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    const double near = ta < tb ? ta : tb, far = ta < tb ? tb : ta;
    const double rate = fabs(d[a]) * inv_spacing[a];
    if (near > t_in) t_in = near, *entry = rate;
    if (far < t_out) t_out = far, *exit = rate;
  }
}

#endif
