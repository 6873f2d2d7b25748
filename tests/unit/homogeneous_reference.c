#include "homogeneous_reference.h"

#include <math.h>

/* Chord of the ray through the box, t in [t0, t1] with t >= 0. */
static int chord(const box_medium *m, const double o[3], const double d[3], double *t0, double *t1)
{
  double a = 0.0, b = INFINITY;
  for (int i = 0; i < 3; ++i) {
    if (fabs(d[i]) < 1e-300) {
      if (o[i] < m->lo[i] || o[i] > m->hi[i]) return 0;
      continue;
    }
    const double u = (m->lo[i] - o[i]) / d[i], v = (m->hi[i] - o[i]) / d[i];
    a = fmax(a, fmin(u, v));
    b = fmin(b, fmax(u, v));
  }
  *t0 = a;
  *t1 = b;
  return b > a;
}

double reference_transparency(const box_medium *m, const double o[3], const double d[3])
{
  double t0, t1;
  if (!chord(m, o, d, &t0, &t1)) return 1.0;
  return exp(-m->beta * (t1 - t0));
}

double reference_radiance(const box_medium *m, const double o[3], const double d[3], const double sun[3],
                          double background, int steps)
{
  double t0, t1;
  if (!chord(m, o, d, &t0, &t1)) return background;
  /* Composite Simpson on t; the integrand is smooth inside the box except where the path to the
   * sun changes the face it leaves through (a kink), which the fine step resolves. */
  const int n = steps % 2 ? steps + 1 : steps;
  const double h = (t1 - t0) / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double t = t0 + i * h;
    const double x[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
    double s0, s1;
    double to_sun = 0.0;
    if (chord(m, x, sun, &s0, &s1)) to_sun = s1;
    const double f = m->beta * exp(-m->beta * (t - t0)) * exp(-m->beta * to_sun);
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * f;
  }
  return m->albedo * m->phase * sum * h / 3.0 + background * exp(-m->beta * (t1 - t0));
}

int make_box_volume(sl_volume *v, int nx, int ny, int nz, const double lo[3], const double hi[3], double beta)
{
  const int n[3] = {nx, ny, nz};
  double origin[3], spacing[3];
  for (int a = 0; a < 3; ++a) {
    spacing[a] = (hi[a] - lo[a]) / n[a];
    origin[a] = lo[a] + 0.5 * spacing[a];
  }
  sl_error err = {0};
  if (sl_volume_init(v, nx, ny, nz, origin, spacing, &err) || sl_volume_add_field(v, SL_CLOUD, &err)) return 1;
  const double eta = beta / sl_particle_properties(SL_CLOUD)->sigma_ext_m2;
  for (size_t i = 0; i < sl_volume_count(v); ++i) v->eta[SL_CLOUD][i] = (float)eta;
  return 0;
}

int render_frame(const sl_scene *scene, const sl_camera *cam, sl_image *out)
{
  sl_error err = {0};
  sl_renderer *r = sl_renderer_create(scene, &err);
  if (!r) return 1;
  sl_image layer, bg;
  if (sl_image_alloc(&layer, cam->width, cam->height, &err) || sl_image_alloc(&bg, cam->width, cam->height, &err) ||
      sl_image_alloc(out, cam->width, cam->height, &err))
    return 1;
  int rc = sl_renderer_render(r, cam, &layer, NULL, &err) || sl_renderer_background(r, cam, &bg, &err);
  if (!rc) sl_image_over(&layer, &bg, out);
  sl_image_free(&layer);
  sl_image_free(&bg);
  sl_renderer_destroy(r);
  return rc;
}
