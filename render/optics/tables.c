/* sl_optics_build: the plan step. For every requested particle type, load its tables from the
 * cache when a valid file exists, otherwise compute them and store them. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "optics_internal.h"
#include "sl_legendre.h"
#include "sl_volume.h"

const double SL_WAVELENGTHS_RGB[3] = {650.0, 515.0, 440.0};
const double SL_WAVELENGTHS_SPECTRAL16[16] = {380.0,        402.6666667, 425.3333333, 448.0, 470.6666667, 493.3333333,
                                              516.0,        538.6666667, 561.3333333, 584.0, 606.6666667, 629.3333333,
                                              652.0,        674.6666667, 697.3333333, 720.0};

struct sl_optics_tables {
  int n_wavelengths;
  double wavelengths_nm[SL_OPTICS_MAX_WAVELENGTHS];
  unsigned particles;
  sl_phase_table *table[SL_PARTICLE_COUNT]; /* n_wavelengths each, or NULL */
  int n_sizes;
  sl_optics_size sizes[SL_OPTICS_MAX_SIZES];
  sl_phase_table *sized[SL_OPTICS_MAX_SIZES]; /* n_wavelengths each */
  sl_optics_stats stats;
};

_Static_assert(SL_OPTICS_MAX_SIZES >= SL_VOLUME_MAX_FIELDS, "every field of a volume may be a size");

void sl_optics_request_fields(sl_optics_request *req, const sl_volume *v)
{
  req->particles = 0;
  req->n_sizes = 0;
  for (int k = 0; k < SL_VOLUME_SLOTS; ++k) {
    if (!v->eta[k]) continue;
    const sl_particle p = sl_volume_field_type(v, k);
    if (v->effective_radius_m[k] > 0.0)
      req->sizes[req->n_sizes++] = (sl_optics_size){p, v->effective_radius_m[k]};
    else
      req->particles |= 1u << p;
  }
}

void sl_optics_request_defaults(sl_optics_request *req)
{
  memset(req, 0, sizeof *req);
  req->particles = (1u << SL_PARTICLE_COUNT) - 1u;
  req->n_wavelengths = 3;
  memcpy(req->wavelengths_nm, SL_WAVELENGTHS_RGB, sizeof SL_WAVELENGTHS_RGB);
  req->angle_step_deg = 0.1;
  req->max_order = 0;
  req->isotropy_tolerance = 1e-4;
  req->n_moments = 0;
  req->truncation_deg = 0.5;
  /* 256: at 32 the quadrature's nodes lie 5.6 size-parameter units apart for cloud droplets,
   * coarser than the glory's ripple in x (its P at 176-178 degrees 10-16 % high), and the 1 mm drops'
   * unaveraged interference scattered rain's P by +-20 % between neighbouring angles inside the
   * primary bow, which a rendered rainbow showed as coloured arcs (docs/ACCURACY.md). */
  req->radius_samples = 256;
  req->ice_rays = 400000;
  req->seed = 20040612ULL;
  req->cache_dir = NULL;
  req->use_cache = 1;
}

int sl_optics_request_wavelengths(sl_optics_request *req, const char *name, sl_error *err)
{
  if (strcmp(name, "rgb") == 0) {
    req->n_wavelengths = 3;
    memcpy(req->wavelengths_nm, SL_WAVELENGTHS_RGB, sizeof SL_WAVELENGTHS_RGB);
  } else if (strcmp(name, "spectral16") == 0) {
    req->n_wavelengths = 16;
    memcpy(req->wavelengths_nm, SL_WAVELENGTHS_SPECTRAL16, sizeof SL_WAVELENGTHS_SPECTRAL16);
  } else {
    return sl_fail(err, SL_ERR_ARG, "optics: unknown wavelength set '%s' (rgb, spectral16)", name);
  }
  return SL_OK;
}

static int validate(const sl_optics_request *r, sl_error *err)
{
  if ((r->particles == 0 && r->n_sizes == 0) || r->particles >= (1u << SL_PARTICLE_COUNT))
    return sl_fail(err, SL_ERR_ARG, "optics: particle mask 0x%x names no known particle type", r->particles);
  if (r->n_sizes < 0 || r->n_sizes > SL_OPTICS_MAX_SIZES)
    return sl_fail(err, SL_ERR_ARG, "optics: %d sizes (0..%d)", r->n_sizes, SL_OPTICS_MAX_SIZES);
  for (int i = 0; i < r->n_sizes; ++i) {
    const sl_optics_size *z = &r->sizes[i];
    optics_lognormal d;
    if ((int)z->type < 0 || z->type >= SL_PARTICLE_COUNT || !optics_size_distribution_at(z->type, 0.0, &d))
      return sl_fail(err, SL_ERR_ARG, "optics: tables at other sizes exist for cloud and rain, not particle %d",
                     (int)z->type);
    if (!(z->effective_radius_m >= 0.5e-6 && z->effective_radius_m <= 0.05))
      return sl_fail(err, SL_ERR_ARG, "optics: effective radius %g m outside 0.5 um .. 5 cm", z->effective_radius_m);
  }
  if (r->n_wavelengths < 1 || r->n_wavelengths > SL_OPTICS_MAX_WAVELENGTHS)
    return sl_fail(err, SL_ERR_ARG, "optics: %d wavelengths (1..%d)", r->n_wavelengths, SL_OPTICS_MAX_WAVELENGTHS);
  for (int i = 0; i < r->n_wavelengths; ++i)
    if (!(r->wavelengths_nm[i] >= 300.0 && r->wavelengths_nm[i] <= 1000.0))
      return sl_fail(err, SL_ERR_ARG, "optics: wavelength %g nm outside 300..1000 nm", r->wavelengths_nm[i]);
  if (!(r->angle_step_deg >= 0.005 && r->angle_step_deg <= 5.0))
    return sl_fail(err, SL_ERR_ARG, "optics: angle step %g degrees outside 0.005..5", r->angle_step_deg);
  if (r->max_order < 0 || r->max_order > SL_OPTICS_MAX_ORDER)
    return sl_fail(err, SL_ERR_ARG, "optics: max_order %d outside 0..%d", r->max_order, SL_OPTICS_MAX_ORDER);
  if (r->max_order == 0 && !(r->isotropy_tolerance > 0.0 && r->isotropy_tolerance < 1.0))
    return sl_fail(err, SL_ERR_ARG, "optics: isotropy tolerance %g outside (0, 1)", r->isotropy_tolerance);
  if (r->n_moments < 0 || r->n_moments > 100000) return sl_fail(err, SL_ERR_ARG, "optics: n_moments %d", r->n_moments);
  if (!(r->truncation_deg >= 0.0 && r->truncation_deg <= 10.0))
    return sl_fail(err, SL_ERR_ARG, "optics: truncation angle %g degrees outside 0..10", r->truncation_deg);
  if (r->radius_samples < 1 || r->radius_samples > 10000)
    return sl_fail(err, SL_ERR_ARG, "optics: radius_samples %d outside 1..10000", r->radius_samples);
  if (r->ice_rays < 64 || r->ice_rays > 2000000000L)
    return sl_fail(err, SL_ERR_ARG, "optics: ice_rays %ld outside 64..2e9", r->ice_rays);
  return SL_OK;
}

/* Everything that changes a particle's tables goes into its cache key. */
static void cache_key(const sl_optics_request *r, sl_particle p, double r_eff_m, int n_moments, char *key, size_t size)
{
  int len = snprintf(key, size, "stormlight-optics v%d particle=%s step=%.9g trunc=%.9g moments=%d order=%d tol=%.9g",
                     SL_OPTICS_TABLE_VERSION, sl_particle_name(p), r->angle_step_deg, r->truncation_deg, n_moments,
                     r->max_order, r->max_order ? 0.0 : r->isotropy_tolerance);
  optics_lognormal d;
  if (optics_size_distribution_at(p, r_eff_m, &d))
    len += snprintf(key + len, size - (size_t)len, " lognormal=%.9g,%.9g radii=%d", d.median_radius_m, d.sigma_ln,
                    r->radius_samples);
  const optics_exponential *e = optics_rimed_distribution(p);
  if (e)
    len += snprintf(key + len, size - (size_t)len, " exponential=%.9g,%.9g xmie=%.9g band=%d radii=%d",
                    e->slope_per_m, e->density_kg_m3, SL_RIMED_X_MIE_MAX, SL_RIMED_BAND_SPHERES, r->radius_samples);
  if (p == SL_ICE) len += snprintf(key + len, size - (size_t)len, " rays=%ld seed=%llu", r->ice_rays, r->seed);
  const sl_particle_props *props = sl_particle_properties(p);
  len += snprintf(key + len, size - (size_t)len, " sigma=%.9g r=%.9g wl=", props->sigma_ext_m2, props->radius_m);
  for (int i = 0; i < r->n_wavelengths && (size_t)len < size; ++i)
    len += snprintf(key + len, size - (size_t)len, "%s%.9g", i ? "," : "", r->wavelengths_nm[i]);
}

static double now_seconds(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int build_particle(const sl_optics_request *r, sl_particle p, double r_eff_m, const optics_grid *g,
                          const optics_table_params *params, sl_phase_table *tables, double progress0,
                          double progress_span, sl_error *err)
{
  optics_raw_phase raw = {0};
  raw.p = malloc(sizeof(double) * (size_t)g->n_angles);
  if (!raw.p) return sl_fail(err, SL_ERR_NOMEM, "optics: out of memory");
  int status = SL_OK;
  optics_lognormal dist;
  const int lognormal = optics_size_distribution_at(p, r_eff_m, &dist);
  for (int w = 0; w < r->n_wavelengths && status == SL_OK; ++w) {
    const double nm = r->wavelengths_nm[w];
    switch (p) {
    case SL_CLOUD:
    case SL_RAIN:
      status = optics_mie_distribution(p, lognormal ? &dist : NULL, nm, g, r->radius_samples, &raw, err);
      break;
    case SL_ICE: status = optics_ice_crystals(nm, g, r->ice_rays, r->seed, &raw, err); break;
    case SL_SNOW: status = optics_snow(nm, g, &raw, err); break;
    case SL_GRAUPEL:
    case SL_HAIL: status = optics_rimed_ice(p, nm, g, r->radius_samples, &raw, err); break;
    default: status = sl_fail(err, SL_ERR_ARG, "optics: unknown particle %d", (int)p);
    }
    if (status == SL_OK) status = optics_table_from_raw(g, &raw, params, nm, &tables[w], err);
    if (r->progress) r->progress(r->progress_user, progress0 + progress_span * (w + 1) / r->n_wavelengths);
  }
  free(raw.p);
  return status;
}

sl_optics_tables *sl_optics_build(const sl_optics_request *r, sl_error *err)
{
  if (!r) {
    sl_fail(err, SL_ERR_ARG, "optics: no request");
    return NULL;
  }
  if (validate(r, err)) return NULL;
  sl_optics_tables *T = calloc(1, sizeof *T);
  if (!T) {
    sl_fail(err, SL_ERR_NOMEM, "optics: out of memory");
    return NULL;
  }
  T->n_wavelengths = r->n_wavelengths;
  memcpy(T->wavelengths_nm, r->wavelengths_nm, sizeof(double) * (size_t)r->n_wavelengths);
  T->particles = r->particles;
  /* A cache that cannot be located costs time, not correctness: build without it. */
  sl_error dir_err = {0};
  const int use_cache =
      r->use_cache && sl_optics_cache_dir(r, T->stats.cache_dir, (int)sizeof T->stats.cache_dir, &dir_err) == SL_OK;
  if (!use_cache) T->stats.cache_dir[0] = '\0';

  optics_grid g;
  if (optics_grid_init(&g, r->angle_step_deg, err)) {
    free(T);
    return NULL;
  }
  optics_table_params params;
  params.truncation_rad = (r->truncation_deg > 0.0 ? r->truncation_deg : r->angle_step_deg) * SL_PI / 180.0;
  params.n_moments = r->n_moments > 0 ? r->n_moments : 2 * (g.n_angles - 1);
  params.max_order = r->max_order;
  params.isotropy_tolerance = r->isotropy_tolerance;

  /* The types' own tables, then the further sizes. */
  int count = 0, done = 0;
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p) count += (r->particles >> p) & 1u;
  count += r->n_sizes;
  T->n_sizes = r->n_sizes;
  memcpy(T->sizes, r->sizes, sizeof r->sizes);
  int status = SL_OK;
  for (int e = 0; e < SL_PARTICLE_COUNT + r->n_sizes && status == SL_OK; ++e) {
    const int own = e < SL_PARTICLE_COUNT;
    if (own && !((r->particles >> e) & 1u)) continue;
    const sl_particle p = own ? (sl_particle)e : r->sizes[e - SL_PARTICLE_COUNT].type;
    const double r_eff = own ? 0.0 : r->sizes[e - SL_PARTICLE_COUNT].effective_radius_m;
    sl_phase_table *tables = calloc((size_t)r->n_wavelengths, sizeof(sl_phase_table));
    if (!tables) {
      status = sl_fail(err, SL_ERR_NOMEM, "optics: out of memory");
      break;
    }
    if (own)
      T->table[p] = tables;
    else
      T->sized[e - SL_PARTICLE_COUNT] = tables;
    char key[2048], path[1024];
    cache_key(r, p, r_eff, params.n_moments, key, sizeof key);
    const unsigned long long h = optics_fnv1a(key, strlen(key), 0xcbf29ce484222325ULL);
    snprintf(path, sizeof path, "%s/optics-%s-%016llx.bin", T->stats.cache_dir, sl_particle_name(p), h);
    double t0 = now_seconds();
    if (use_cache) {
      sl_error load_err = {0};
      const int loaded = optics_cache_load(path, key, tables, r->n_wavelengths, &load_err);
      if (loaded == SL_OK) {
        T->stats.tables_loaded++;
        T->stats.load_seconds += now_seconds() - t0;
        if (r->progress) r->progress(r->progress_user, (double)++done / count);
        continue;
      }
      if (loaded != SL_ERR_IO) T->stats.cache_rejected++; /* present but stale or corrupt */
    }
    /* A miss: take the entry's lock, then look again, since another process (a test run in
     * parallel, a time series' ranks) may have built it while this one waited. */
    const int lock = use_cache ? optics_cache_lock(path) : -1;
    if (lock >= 0) {
      sl_error load_err = {0};
      if (optics_cache_load(path, key, tables, r->n_wavelengths, &load_err) == SL_OK) {
        optics_cache_unlock(lock);
        T->stats.tables_loaded++;
        T->stats.load_seconds += now_seconds() - t0;
        if (r->progress) r->progress(r->progress_user, (double)++done / count);
        continue;
      }
    }
    t0 = now_seconds();
    status = build_particle(r, p, r_eff, &g, &params, tables, (double)done / count, 1.0 / count, err);
    T->stats.build_seconds += now_seconds() - t0;
    if (status == SL_OK) {
      T->stats.tables_built++;
      if (use_cache) {
        /* A cache that cannot be written costs time, not correctness: not an error. */
        sl_error store_err = {0};
        (void)optics_cache_store(path, key, tables, r->n_wavelengths, &store_err);
      }
    }
    optics_cache_unlock(lock);
    ++done;
  }
  optics_grid_free(&g);
  if (status != SL_OK) {
    sl_optics_free(T);
    return NULL;
  }
  return T;
}

void sl_optics_free(sl_optics_tables *T)
{
  if (!T) return;
  for (int e = 0; e < SL_PARTICLE_COUNT + SL_OPTICS_MAX_SIZES; ++e) {
    sl_phase_table *t = e < SL_PARTICLE_COUNT ? T->table[e] : T->sized[e - SL_PARTICLE_COUNT];
    if (!t) continue;
    for (int w = 0; w < T->n_wavelengths; ++w) optics_table_release(&t[w]);
    free(t);
  }
  free(T);
}

int sl_optics_wavelength_count(const sl_optics_tables *T) { return T ? T->n_wavelengths : 0; }

double sl_optics_wavelength(const sl_optics_tables *T, int i)
{
  return (T && i >= 0 && i < T->n_wavelengths) ? T->wavelengths_nm[i] : 0.0;
}

const sl_phase_table *sl_optics_table(const sl_optics_tables *T, sl_particle p, int w)
{
  if (!T || (int)p < 0 || p >= SL_PARTICLE_COUNT || !T->table[p] || w < 0 || w >= T->n_wavelengths) return NULL;
  return &T->table[p][w];
}

const sl_phase_table *sl_optics_table_sized(const sl_optics_tables *T, sl_particle p, double r_eff_m, int w)
{
  if (!(r_eff_m > 0.0)) return sl_optics_table(T, p, w);
  if (!T || w < 0 || w >= T->n_wavelengths) return NULL;
  for (int i = 0; i < T->n_sizes; ++i)
    if (T->sizes[i].type == p && fabs(T->sizes[i].effective_radius_m / r_eff_m - 1.0) < 1e-9 && T->sized[i])
      return &T->sized[i][w];
  return NULL;
}

void sl_optics_get_stats(const sl_optics_tables *T, sl_optics_stats *stats)
{
  if (T && stats) *stats = T->stats;
}
