/* Where a light texel's ray enters the medium (light_kink.h). */
#include "light_kink.h"

#include <math.h>

/* The total extinction at o + u d. */
static double ray_extinction(const sl_renderer *r, const double o[3], const double d[3], double u)
{
  const double x[3] = {o[0] + u * d[0], o[1] + u * d[1], o[2] + u * d[2]};
  return sl__total_extinction(r, x);
}

/* Where a light texel's ray o + u prop enters the medium: where its optical depth from `first`
 * (its first occupied brick; every sample before is zero) reaches SL__ENTRY_DEPTH; NaN when it
 * does not by `last`. Trapezoids one grid cell long, then the step that crosses in sixteen, then
 * within that sixteenth the extinction taken linear: a sixteenth of a cell is where a flat top
 * under a grazing sun is placed (Katrina's lid: 190 m along the ray, 14 m in height, against
 * texel rows 2.9 km apart along it). */
double sl__texel_entry(const sl_renderer *r, const double o[3], const double prop[3], double first, double last,
                          double step)
{
  double u = first, tau = 0.0;
  double beta_u = ray_extinction(r, o, prop, u);
  while (u < last) {
    const double u_next = u + step < last ? u + step : last;
    const double beta_next = ray_extinction(r, o, prop, u_next);
    const double dtau = 0.5 * (beta_u + beta_next) * (u_next - u);
    if (tau + dtau >= SL__ENTRY_DEPTH) {
      const double h = (u_next - u) / 16.0;
      double a = u, beta_a = beta_u;
      for (int i = 1; i <= 16; ++i) {
        const double b = i == 16 ? u_next : u + i * h;
        double beta_b = beta_next;
        if (i < 16) beta_b = ray_extinction(r, o, prop, b);
        const double d = 0.5 * (beta_a + beta_b) * (b - a);
        if (tau + d >= SL__ENTRY_DEPTH || i == 16) {
          /* tau + beta_a s + (beta_b - beta_a) s^2 / (2 (b - a)) = SL__ENTRY_DEPTH, the root in
           * [0, b - a] in the form without cancellation. */
          const double need = SL__ENTRY_DEPTH - tau, q = (beta_b - beta_a) / (2.0 * (b - a));
          const double disc = beta_a * beta_a + 4.0 * q * need;
          const double den = beta_a + sqrt(disc > 0.0 ? disc : 0.0);
          double s = den > 0.0 ? 2.0 * need / den : b - a;
          s = s < 0.0 ? 0.0 : s > b - a ? b - a : s;
          return a + s;
        }
        tau += d, a = b, beta_a = beta_b;
      }
    }
    tau += dtau, u = u_next, beta_u = beta_next;
  }
  return NAN;
}
