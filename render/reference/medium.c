/* The medium: per-wavelength extinction grids with forward Dirac peaks scaled out, a coarse
 * majorant grid for delta and ratio tracking, and the counter-based random numbers. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sl_guards.h"
#include "reference_internal.h"
#include "sl_air.h"
#include "sl_legendre.h"

/* ---- random numbers ------------------------------------------------------------------------ */

/* SplitMix64's output function (Steele, Lea & Flood 2014) applied to key + counter * gamma is a
 * counter-based generator: the n-th number of a stream depends only on (key, n), never on which
 * thread draws it or what other streams did. Streams are keyed by hashing their coordinates. */
static unsigned long long mix64(unsigned long long z)
{
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

sl_ref_rng sl_ref_rng_make(unsigned long long seed, unsigned long long a, unsigned long long b, unsigned long long c)
{
  unsigned long long k = mix64(seed + 0x9E3779B97F4A7C15ull);
  k = mix64(k ^ (a + 0x632BE59BD9B4E019ull));
  k = mix64(k ^ (b + 0x8CB92BA72F3D8DD7ull));
  k = mix64(k ^ (c + 0xD1B54A32D192ED03ull));
  return (sl_ref_rng){k, 0};
}

double sl_ref_rng_uniform(sl_ref_rng *r)
{
  const unsigned long long z = mix64(r->key + (++r->counter) * 0x9E3779B97F4A7C15ull);
  return (double)(z >> 11) * 0x1.0p-53;
}

/* ---- geometry -------------------------------------------------------------------------------- */


void ref_rotate(const double d[3], double mu, double phi, double out[3])
{
  /* Orthonormal frame around d (Duff et al. 2017, branchless ONB). */
  const double s = copysign(1.0, d[2]);
  const double a = -1.0 / (s + d[2]);
  const double b = d[0] * d[1] * a;
  const double t1[3] = {1.0 + s * d[0] * d[0] * a, s * b, -s * d[0]};
  const double t2[3] = {b, s + d[1] * d[1] * a, -d[1]};
  const double sin_t = sl_safe_sqrt(1.0 - mu * mu);
  const double cp = cos(phi) * sin_t, sp = sin(phi) * sin_t;
  double n = 0.0;
  for (int k = 0; k < 3; ++k) {
    out[k] = mu * d[k] + cp * t1[k] + sp * t2[k];
    n += out[k] * out[k];
  }
  /* Renormalise: thousands of scatterings must not let the direction drift off the sphere. */
  n = 1.0 / sqrt(n);
  for (int k = 0; k < 3; ++k) out[k] *= n;
}

/* ---- phase functions ------------------------------------------------------------------------ */

static int phase_sampler_init(phase_sampler *ps, const sl_ref_phase *ph, sl_error *err)
{
  memset(ps, 0, sizeof *ps);
  ps->kind = ph->kind;
  ps->g = ph->g;
  if (ph->kind == SL_REF_PHASE_HG && !(fabs(ph->g) < 1.0))
    return sl_fail(err, SL_ERR_ARG, "reference: Henyey-Greenstein g = %g must lie in (-1, 1)", ph->g);
  if (ph->kind != SL_REF_PHASE_TABLE) return SL_OK;
  const sl_phase_table *t = ph->table;
  if (!t || t->n_angles < 2 || !t->ams) return sl_fail(err, SL_ERR_ARG, "reference: a tabulated phase function has no table");
  ps->table = t;
  ps->cdf = malloc((size_t)t->n_angles * sizeof(double));
  if (!ps->cdf) return sl_fail(err, SL_ERR_NOMEM, "reference: out of memory for a phase sampler");
  /* Cell j (theta_j..theta_j+1) of the hat interpolant y_j + (y_j+1 - y_j)(theta - theta_j)/h,
   * integrated against 2 pi sin(theta) in closed form:
   *   int sin = cos a - cos b,  int (theta - a) sin = sin b - sin a - h cos b. */
  const float *row = t->ams + (size_t)1 * t->n_angles;
  const double h = t->step_rad;
  double total = 0.0;
  ps->cdf[0] = 0.0;
  for (int j = 0; j + 1 < t->n_angles; ++j) {
    const double a = j * h, b = (j + 1 == t->n_angles - 1) ? SL_PI : (j + 1) * h;
    const double hb = b - a;
    const double i0 = cos(a) - cos(b), i1 = sin(b) - sin(a) - hb * cos(b);
    double cell = 2.0 * SL_PI * (row[j] * i0 + (row[j + 1] - row[j]) * i1 / hb);
    if (cell < 0.0) cell = 0.0;
    total += cell;
    ps->cdf[j + 1] = total;
  }
  if (!(total > 0.0)) return sl_fail(err, SL_ERR_DATA, "reference: tabulated phase function integrates to %g", total);
  for (int j = 0; j < t->n_angles; ++j) ps->cdf[j] /= total;
  ps->inv_total = 1.0 / total;
  return SL_OK;
}

static double phase_value(const phase_sampler *ps, double mu)
{
  switch (ps->kind) {
  case SL_REF_PHASE_ISOTROPIC: return 1.0 / (4.0 * SL_PI);
  case SL_REF_PHASE_HG: return sl_hg_phase(ps->g, mu);
  case SL_REF_PHASE_RAYLEIGH: return sl_rayleigh_phase(mu);
  case SL_REF_PHASE_TABLE: return sl_phase_table_ams(ps->table, 1, mu) * ps->inv_total;
  }
  return 0.0;
}

/* Samples mu = cos(theta); returns value / pdf of the sampled direction. */
static double phase_sample_mu(const phase_sampler *ps, sl_ref_rng *rng, double *mu)
{
  const double u = sl_ref_rng_uniform(rng);
  switch (ps->kind) {
  case SL_REF_PHASE_ISOTROPIC: *mu = 1.0 - 2.0 * u; return 1.0;
  case SL_REF_PHASE_HG: {
    const double g = ps->g;
    if (fabs(g) < 1e-6) {
      *mu = 1.0 - 2.0 * u;
      return 1.0;
    }
    /* Inverse CDF of HG in mu. */
    const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    double m = (1.0 + g * g - s * s) / (2.0 * g);
    *mu = sl_clamp_cosine(m);
    return 1.0;
  }
  case SL_REF_PHASE_RAYLEIGH: {
    /* Rejection from isotropic: P / P_iso = 3/4 (1 + mu^2) <= 3/2, acceptance (1 + mu^2) / 2. */
    double m = 1.0 - 2.0 * u;
    while (2.0 * sl_ref_rng_uniform(rng) > 1.0 + m * m) m = 1.0 - 2.0 * sl_ref_rng_uniform(rng);
    *mu = m;
    return 1.0;
  }
  case SL_REF_PHASE_TABLE: {
    /* The cell by its exact probability, then cos(theta) uniform within the cell: the weight
     * value/pdf differs from 1 only by the tabulation's curvature over 0.1 degree. */
    const sl_phase_table *t = ps->table;
    int lo = 0, hi = t->n_angles - 1;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      if (ps->cdf[mid] <= u) lo = mid;
      else hi = mid;
    }
    const double p_cell = ps->cdf[lo + 1] - ps->cdf[lo];
    const double a = lo * t->step_rad, b = (lo + 1 == t->n_angles - 1) ? SL_PI : (lo + 1) * t->step_rad;
    const double ca = cos(a), cb = cos(b);
    const double m = cb + (ca - cb) * sl_ref_rng_uniform(rng);
    *mu = m;
    const double pdf = p_cell / (2.0 * SL_PI * (ca - cb));
    return pdf > 0.0 ? phase_value(ps, m) / pdf : 0.0;
  }
  }
  *mu = 1.0;
  return 0.0;
}

double ref_phase_pdf(const sl_ref_medium *m, int c, int w, double mu)
{
  const phase_sampler *ps = &m->phase[c][w];
  if (ps->kind != SL_REF_PHASE_TABLE) return phase_value(ps, mu);
  /* The table's sampler: the cell's probability spread uniformly over its solid angle. */
  const sl_phase_table *t = ps->table;
  const double theta = acos(sl_clamp_cosine(mu));
  int j = (int)(theta * t->inv_step_rad);
  j = j < 0 ? 0 : j > t->n_angles - 2 ? t->n_angles - 2 : j;
  const double a = j * t->step_rad, b = (j + 1 == t->n_angles - 1) ? SL_PI : (j + 1) * t->step_rad;
  const double band = 2.0 * SL_PI * (cos(a) - cos(b));
  return band > 0.0 ? (ps->cdf[j + 1] - ps->cdf[j]) / band : 0.0;
}

double sl_ref_phase_eval(const sl_ref_medium *m, int c, int w, double cos_theta)
{
  return phase_value(&m->phase[c][w], cos_theta);
}

double sl_ref_phase_sample(const sl_ref_medium *m, int c, int w, const double in[3], sl_ref_rng *rng, double out[3])
{
  double mu;
  const double weight = phase_sample_mu(&m->phase[c][w], rng, &mu);
  ref_rotate(in, mu, 2.0 * SL_PI * sl_ref_rng_uniform(rng), out);
  return weight;
}

/* ---- the medium ------------------------------------------------------------------------------ */

void sl_ref_medium_desc_defaults(sl_ref_medium_desc *d)
{
  memset(d, 0, sizeof *d);
  d->n[0] = d->n[1] = d->n[2] = 1;
  d->spacing[0] = d->spacing[1] = d->spacing[2] = 1.0;
  d->n_wavelengths = 1;
  d->wavelength_nm[0] = 550.0;
  d->n_components = 1;
  d->component[0].sigma[0] = 1.0;
  d->component[0].albedo[0] = 1.0;
  d->interpolation = SL_REF_TRILINEAR;
}

static double sample_density(const sl_ref_medium *m, int c, const double x[3])
{
  if (!m->desc.component[c].density) return 1.0;
  const sl_grid_view *g = &m->density_view[c];
  if (m->desc.interpolation == SL_REF_TRILINEAR) return sl_grid_sample(g, x);
  size_t idx = 0, stride = 1;
  for (int a = 0; a < 3; ++a) {
    if (!(x[a] >= g->lo[a] && x[a] <= g->hi[a])) return 0.0;
    int i = (int)floor((x[a] - g->lo[a]) * g->inv_spacing[a]);
    i = i < 0 ? 0 : i >= g->n[a] ? g->n[a] - 1 : i;
    idx += (size_t)i * stride;
    stride *= (size_t)g->n[a];
  }
  return g->data[idx];
}

double sl_ref_extinction(const sl_ref_medium *m, int w, const double x[3])
{
  const sl_grid_view *g = &m->extinction_view[w];
  if (m->desc.interpolation == SL_REF_TRILINEAR) return sl_grid_sample(g, x);
  size_t idx = 0, stride = 1;
  for (int a = 0; a < 3; ++a) {
    if (!(x[a] >= g->lo[a] && x[a] <= g->hi[a])) return 0.0;
    int i = (int)floor((x[a] - g->lo[a]) * g->inv_spacing[a]);
    i = i < 0 ? 0 : i >= g->n[a] ? g->n[a] - 1 : i;
    idx += (size_t)i * stride;
    stride *= (size_t)g->n[a];
  }
  return g->data[idx];
}

int ref_choose_component(const sl_ref_medium *m, int w, const double x[3], sl_ref_rng *rng)
{
  if (m->nc == 1) return 0;
  double s[SL_REF_MAX_COMPONENTS], total = 0.0;
  for (int c = 0; c < m->nc; ++c) total += s[c] = m->sigma_eff[c][w] * sample_density(m, c, x);
  double u = sl_ref_rng_uniform(rng) * total;
  for (int c = 0; c < m->nc; ++c) {
    if (u < s[c]) return c;
    u -= s[c];
  }
  for (int c = m->nc - 1; c >= 0; --c)
    if (s[c] > 0.0) return c;
  return 0;
}

void sl_ref_medium_destroy(sl_ref_medium *m)
{
  if (!m) return;
  for (int w = 0; w < SL_REF_MAX_WAVELENGTHS; ++w) {
    free(m->extinction[w]);
    free(m->majorant[w]);
    for (int c = 0; c < SL_REF_MAX_COMPONENTS; ++c) free(m->phase[c][w].cdf);
  }
  free(m);
}

/* Majorant cells of `block` samples; a cell's bound is the largest sample that trilinear
 * interpolation anywhere inside it can reach (one sample beyond its faces), so it also bounds
 * the cell-constant interpolation. */
static int build_majorants(sl_ref_medium *m, const sl_ref_medium_desc *d, sl_error *err)
{
  m->block = d->majorant_block > 0 ? d->majorant_block : 8;
  for (int a = 0; a < 3; ++a) {
    m->nb[a] = (d->n[a] + m->block - 1) / m->block;
    m->block_size[a] = m->block * d->spacing[a];
  }
  const size_t nmaj = (size_t)m->nb[0] * m->nb[1] * m->nb[2];
  for (int w = 0; w < m->nw; ++w) {
    m->majorant[w] = calloc(nmaj, sizeof(float));
    if (!m->majorant[w]) return sl_fail(err, SL_ERR_NOMEM, "reference: out of memory for the majorant grid");
    for (int bk = 0; bk < m->nb[2]; ++bk)
      for (int bj = 0; bj < m->nb[1]; ++bj)
        for (int bi = 0; bi < m->nb[0]; ++bi) {
          const int b[3] = {bi, bj, bk};
          int lo[3], hi[3];
          for (int a = 0; a < 3; ++a) {
            lo[a] = b[a] * m->block - 1;
            hi[a] = (b[a] + 1) * m->block;
            lo[a] = lo[a] < 0 ? 0 : lo[a];
            hi[a] = hi[a] > d->n[a] - 1 ? d->n[a] - 1 : hi[a];
          }
          float mx = 0.0f;
          for (int k = lo[2]; k <= hi[2]; ++k)
            for (int j = lo[1]; j <= hi[1]; ++j)
              for (int i = lo[0]; i <= hi[0]; ++i) {
                const float v = m->extinction[w][((size_t)k * d->n[1] + j) * d->n[0] + i];
                if (v > mx) mx = v;
              }
          /* Interpolation in double of float samples can exceed the largest by an ulp. */
          m->majorant[w][((size_t)bk * m->nb[1] + bj) * m->nb[0] + bi] = mx * (1.0f + 1e-6f);
        }
  }
  return SL_OK;
}

/* The renderer's midplane anchor: the box around samples with extinction (first wavelength),
 * one cell of margin, as sl_renderer_content_bounds. */
static void content_box(sl_ref_medium *m, const sl_ref_medium_desc *d)
{
  int mn[3] = {d->n[0], d->n[1], d->n[2]}, mx[3] = {-1, -1, -1};
  for (int k = 0; k < d->n[2]; ++k)
    for (int j = 0; j < d->n[1]; ++j)
      for (int i = 0; i < d->n[0]; ++i) {
        if (!(m->extinction[0][((size_t)k * d->n[1] + j) * d->n[0] + i] > 0.0f)) continue;
        const int idx[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          if (idx[a] < mn[a]) mn[a] = idx[a];
          if (idx[a] > mx[a]) mx[a] = idx[a];
        }
      }
  for (int a = 0; a < 3; ++a) {
    double lo = m->lo[a], hi = m->hi[a];
    if (mx[0] >= 0) {
      lo = fmax(m->lo[a], d->origin[a] + (mn[a] - 1) * d->spacing[a]);
      hi = fmin(m->hi[a], d->origin[a] + (mx[a] + 1) * d->spacing[a]);
    }
    m->content_lo[a] = lo, m->content_hi[a] = hi;
    m->content_center[a] = 0.5 * (lo + hi);
  }
}

sl_ref_medium *sl_ref_medium_create(const sl_ref_medium_desc *d, sl_error *err)
{
  if (!d || d->n_wavelengths < 1 || d->n_wavelengths > SL_REF_MAX_WAVELENGTHS) {
    sl_fail(err, SL_ERR_ARG, "reference: %d wavelengths (1..%d)", d ? d->n_wavelengths : 0, SL_REF_MAX_WAVELENGTHS);
    return NULL;
  }
  if (d->n_components < 1 || d->n_components > SL_REF_MAX_COMPONENTS) {
    sl_fail(err, SL_ERR_ARG, "reference: %d medium components (1..%d)", d->n_components, SL_REF_MAX_COMPONENTS);
    return NULL;
  }
  sl_volume shape;
  if (sl_volume_init(&shape, d->n[0], d->n[1], d->n[2], d->origin, d->spacing, err)) return NULL;
  sl_ref_medium *m = calloc(1, sizeof *m);
  if (!m) {
    sl_fail(err, SL_ERR_NOMEM, "reference: out of memory");
    return NULL;
  }
  m->desc = *d;
  m->nw = d->n_wavelengths;
  m->nc = d->n_components;
  sl_volume_bounds(&shape, m->lo, m->hi);
  for (int a = 0; a < 3; ++a) m->size[a] = m->hi[a] - m->lo[a];
  const size_t n = sl_volume_count(&shape);

  for (int c = 0; c < m->nc; ++c) {
    const sl_ref_component *comp = &d->component[c];
    if (comp->density) sl_grid_view_init(&m->density_view[c], comp->density, &shape);
    for (int w = 0; w < m->nw; ++w) {
      const double sigma = comp->sigma[w], albedo = comp->albedo[w];
      if (!(sigma >= 0.0) || !isfinite(sigma) || !(albedo >= 0.0 && albedo <= 1.0)) {
        sl_fail(err, SL_ERR_ARG, "reference: component %d at %g nm: extinction %g or albedo %g out of range", c,
                d->wavelength_nm[w], sigma, albedo);
        sl_ref_medium_destroy(m);
        return NULL;
      }
      if (phase_sampler_init(&m->phase[c][w], &comp->phase[w], err)) {
        sl_ref_medium_destroy(m);
        return NULL;
      }
      /* Forward peaks (docs/REFERENCE.md): a Dirac of weight f in P is no interaction at all, so
       * the transport equation is exactly that of sigma (1 - albedo f), albedo (1 - f) / (1 - albedo f)
       * and the phase function's smooth part renormalised. This is what lets next-event
       * estimation see sunlight scattered into the peak. */
      double f = 0.0;
      if (comp->phase[w].kind == SL_REF_PHASE_TABLE) f = 1.0 - 1.0 / m->phase[c][w].inv_total;
      f = f < 0.0 ? 0.0 : f;
      const double keep = 1.0 - albedo * f;
      m->sigma_eff[c][w] = sigma * keep;
      m->albedo_eff[c][w] = keep > 0.0 ? albedo * (1.0 - f) / keep : 0.0;
    }
  }

  for (int w = 0; w < m->nw; ++w) {
    m->extinction[w] = calloc(n, sizeof(float));
    if (!m->extinction[w]) {
      sl_fail(err, SL_ERR_NOMEM, "reference: out of memory for a %dx%dx%d extinction grid", d->n[0], d->n[1], d->n[2]);
      sl_ref_medium_destroy(m);
      return NULL;
    }
    for (int c = 0; c < m->nc; ++c) {
      const float *rho = d->component[c].density;
      const double s = m->sigma_eff[c][w];
      for (size_t i = 0; i < n; ++i) {
        const double v = rho ? rho[i] : 1.0;
        if (!(v >= 0.0) || !isfinite(v)) {
          sl_fail(err, SL_ERR_DATA, "reference: component %d density is negative or not finite at sample %zu", c, i);
          sl_ref_medium_destroy(m);
          return NULL;
        }
        m->extinction[w][i] += (float)(v * s);
      }
    }
    sl_grid_view_init(&m->extinction_view[w], m->extinction[w], &shape);
  }

  if (build_majorants(m, d, err)) {
    sl_ref_medium_destroy(m);
    return NULL;
  }
  content_box(m, d);
  return m;
}

sl_ref_medium *sl_ref_medium_from_volume(const sl_volume *v, const sl_optics_tables *tables, sl_error *err)
{
  sl_ref_medium_desc d;
  sl_ref_medium_desc_defaults(&d);
  d.n[0] = v->nx, d.n[1] = v->ny, d.n[2] = v->nz;
  memcpy(d.origin, v->origin, sizeof d.origin);
  memcpy(d.spacing, v->spacing, sizeof d.spacing);
  d.n_wavelengths = sl_optics_wavelength_count(tables);
  if (d.n_wavelengths > SL_REF_MAX_WAVELENGTHS) {
    sl_fail(err, SL_ERR_ARG, "reference: %d wavelengths, at most %d", d.n_wavelengths, SL_REF_MAX_WAVELENGTHS);
    return NULL;
  }
  for (int w = 0; w < d.n_wavelengths; ++w) d.wavelength_nm[w] = sl_optics_wavelength(tables, w);
  d.n_components = 0;
  for (int k = 0; k < SL_VOLUME_SLOTS; ++k) {
    if (!v->eta[k]) continue;
    const sl_particle p = sl_volume_field_type(v, k);
    if (d.n_components == SL_REF_MAX_COMPONENTS) {
      sl_fail(err, SL_ERR_ARG, "reference: more than %d particle fields", SL_REF_MAX_COMPONENTS);
      return NULL;
    }
    sl_ref_component *c = &d.component[d.n_components++];
    c->density = v->eta[k];
    for (int w = 0; w < d.n_wavelengths; ++w) {
      const sl_phase_table *t = sl_optics_table_sized(tables, p, v->effective_radius_m[k], w);
      if (!t) {
        sl_fail(err, SL_ERR_ARG, "reference: no optics table for %s at %g nm", sl_particle_name(p),
                d.wavelength_nm[w]);
        return NULL;
      }
      c->sigma[w] = t->sigma_ext;
      c->albedo[w] = t->albedo;
      c->phase[w] = (sl_ref_phase){SL_REF_PHASE_TABLE, 0.0, t};
    }
  }
  if (d.n_components == 0) {
    /* An empty storm still renders (sky only): one component of zero density. */
    d.n_components = 1;
    for (int w = 0; w < d.n_wavelengths; ++w) {
      d.component[0].sigma[w] = 0.0;
      d.component[0].albedo[w] = 1.0;
      d.component[0].phase[w].kind = SL_REF_PHASE_ISOTROPIC;
    }
  }
  return sl_ref_medium_create(&d, err);
}

int sl_ref_medium_wavelength_count(const sl_ref_medium *m) { return m->nw; }
double sl_ref_medium_wavelength(const sl_ref_medium *m, int w) { return m->desc.wavelength_nm[w]; }
void sl_ref_medium_bounds(const sl_ref_medium *m, double lo[3], double hi[3])
{
  memcpy(lo, m->lo, 3 * sizeof(double));
  memcpy(hi, m->hi, 3 * sizeof(double));
}

void sl_ref_medium_content_bounds(const sl_ref_medium *m, double lo[3], double hi[3])
{
  memcpy(lo, m->content_lo, 3 * sizeof(double));
  memcpy(hi, m->content_hi, 3 * sizeof(double));
}
