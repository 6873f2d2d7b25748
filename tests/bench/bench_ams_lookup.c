// The eye pass's angular term (sl_sample_physics.h, sl_eye_phase_at: eq. 26's Ams at the orders
// around n + 1 and the angle rows around the scattering angle) over batches of 32 samples, as
// eye_batch_phases runs it, against its peer, the form it replaced (each Ams value read alone, so
// that the loop gathers every float by itself; now the two angle rows are one 8-byte read,
// SL_AMS_PAIR). Two fields (cloud and rain, as most of a storm's batches hold), tables of 41
// orders by 1801 angles (0.1 degrees), 3 and 16 wavelengths; a batch's samples see nearby angles,
// as an eye tile's pixels do. Prints nanoseconds a sample, their ratio, and whether the values are
// bitwise the same. Usage: bench_ams_lookup [rounds]
#include "bench_peer.h"
#include "renderer_internal.h"
#include "sl_sample_physics.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { SAMPLES = 32, BATCHES = 4096, FIELDS = 2, ORDERS = 41, ANGLES = 1801 };

/* The peer: sl_eye_phase_at with each of the four Ams values per field read by itself. */
static inline __attribute__((always_inline)) double ams_alone(const sl_light_model *m, int j, int c, int k, int i,
                                                               double w)
{
  const int N = m->max_order[j][c], kk = k > N ? N : k, na = m->table[j][c]->n_angles;
  const double a0 = m->table[j][c]->ams[kk * na + i], a1 = m->table[j][c]->ams[kk * na + i + 1];
  return a0 + w * (a1 - a0);
}

static inline __attribute__((always_inline)) void phase_alone(const sl_light_model *m, int nf, int nwl,
                                                              const float *beta, double n, int i, double w,
                                                              double *result)
{
  const double order = n + 1.0;
  const int k = (int)floor(order);
  const double f = order - k;
  for (int c = 0; c < nwl; ++c) {
    double sum = 0.0;
    for (int j = 0; j < nf; ++j) {
      const double a0 = ams_alone(m, j, c, k, i, w), a1 = ams_alone(m, j, c, k + 1, i, w);
      const double term = m->albedo[j][c] * beta[j] * ((1.0 - f) * a0 + f * a1 + m->xi);
      sum += beta[j] > 0.0 ? term : 0.0;
    }
    result[c] = sum;
  }
}

typedef void batch_fn(const sl_light_model *, float (*)[SL_MAX_FIELDS], const double *, const int *,
                      const double *, double (*)[SAMPLES]);

/* One batch as eye_batch_phases loops it, the wavelength count a constant. */
#define PHASE_BATCH(name, nwl, phase, target) \
  target __attribute__((noinline)) static void name(const sl_light_model *m, float (*fields)[SL_MAX_FIELDS], \
                                                    const double *n, const int *ai, const double *aw, \
                                                    double (*out)[SAMPLES]) \
  { \
    _Pragma("GCC ivdep") for (int s = 0; s < SAMPLES; ++s) \
    { \
      double result[SL_MAX_WAVELENGTHS]; \
      phase; \
      for (int c = 0; c < nwl; ++c) out[c][s] = result[c]; \
    } \
  }
#define OURS(nwl) sl_eye_phase_at(m, SL_LIGHTING_MULTIPLE, FIELDS, nwl, fields[s], n[s], ai[s], aw[s], result)
#define PEER(nwl) phase_alone(m, FIELDS, nwl, fields[s], n[s], ai[s], aw[s], result)
PHASE_BATCH(peer3_base, 3, PEER(3), )
PHASE_BATCH(ours3_base, 3, OURS(3), )
PHASE_BATCH(peer16_base, 16, PEER(16), )
PHASE_BATCH(ours16_base, 16, OURS(16), )
#ifdef SL_WIDE_TARGET
PHASE_BATCH(peer3_wide, 3, PEER(3), SL_WIDE_TARGET)
PHASE_BATCH(ours3_wide, 3, OURS(3), SL_WIDE_TARGET)
PHASE_BATCH(peer16_wide, 16, PEER(16), SL_WIDE_TARGET)
PHASE_BATCH(ours16_wide, 16, OURS(16), SL_WIDE_TARGET)
#endif

int main(int argc, char **argv)
{
  const int rounds = argc > 1 ? atoi(argv[1]) : 5;
  batch_fn *peer[2] = {peer3_base, peer16_base}, *ours[2] = {ours3_base, ours16_base};
  const char *copy = "baseline x86-64";
#ifdef SL_WIDE_TARGET
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512bw"))
    peer[0] = peer3_wide, peer[1] = peer16_wide, ours[0] = ours3_wide, ours[1] = ours16_wide, copy = "AVX-512";
#endif
  printf("the %s copy\n", copy);
  srand(1);
  static sl_phase_table tables[FIELDS][SL_MAX_WAVELENGTHS];
  float *ams = malloc(sizeof(float) * FIELDS * SL_MAX_WAVELENGTHS * ORDERS * ANGLES);
  float(*fields)[SL_MAX_FIELDS] = malloc(sizeof(float) * SL_MAX_FIELDS * BATCHES * SAMPLES);
  double *n = malloc(sizeof(double) * BATCHES * SAMPLES), *aw = malloc(sizeof(double) * BATCHES * SAMPLES);
  int *ai = malloc(sizeof(int) * BATCHES * SAMPLES);
  double(*a)[SAMPLES] = malloc(sizeof(double) * SL_MAX_WAVELENGTHS * SAMPLES);
  double(*b)[SAMPLES] = malloc(sizeof(double) * SL_MAX_WAVELENGTHS * SAMPLES);
  if (!ams || !fields || !n || !aw || !ai || !a || !b) return fprintf(stderr, "bench_ams_lookup: out of memory\n"), 1;
  for (size_t i = 0; i < (size_t)FIELDS * SL_MAX_WAVELENGTHS * ORDERS * ANGLES; ++i) ams[i] = rand() / (float)RAND_MAX;
  sl_light_model m;
  memset(&m, 0, sizeof m);
  m.mode = SL_LIGHTING_MULTIPLE, m.nf = FIELDS, m.xi = 0.01;
  for (int j = 0; j < FIELDS; ++j)
    for (int c = 0; c < SL_MAX_WAVELENGTHS; ++c) {
      tables[j][c].n_angles = ANGLES, tables[j][c].max_order = ORDERS - 1;
      tables[j][c].ams = ams + ((size_t)j * SL_MAX_WAVELENGTHS + c) * ORDERS * ANGLES;
      m.table[j][c] = &tables[j][c], m.max_order[j][c] = ORDERS - 1, m.albedo[j][c] = 0.99 - 0.01 * c;
    }
  for (int k = 0; k < BATCHES; ++k) {
    const int row = rand() % (ANGLES - 40);
    for (int s = 0; s < SAMPLES; ++s) {
      const size_t i = (size_t)k * SAMPLES + s;
      for (int j = 0; j < FIELDS; ++j) fields[i][j] = rand() % 4 ? rand() / (float)RAND_MAX * 0.02f : 0.0f;
      n[i] = rand() / (double)RAND_MAX * 50.0; /* past the tables' last order too */
      ai[i] = row + rand() % 32, aw[i] = rand() / (double)RAND_MAX;
    }
  }
  for (int wl = 0; wl < 2; ++wl) {
    const int nwl = wl ? 16 : 3;
    m.nwl = nwl;
    int same = 1;
    for (int k = 0; k < BATCHES; ++k) {
      const size_t o = (size_t)k * SAMPLES;
      peer[wl](&m, fields + o, n + o, ai + o, aw + o, a);
      ours[wl](&m, fields + o, n + o, ai + o, aw + o, b);
      for (int c = 0; c < nwl; ++c) same &= !memcmp(a[c], b[c], sizeof a[c]);
    }
    double best_peer = 1e30, best_new = 1e30, sink = 0.0;
    for (int r = 0; r < rounds; ++r) {
      /* alternated round by round */
      double t0 = bench_now();
      for (int k = 0; k < BATCHES; ++k) {
        const size_t o = (size_t)k * SAMPLES;
        peer[wl](&m, fields + o, n + o, ai + o, aw + o, a), sink += a[0][k % SAMPLES];
      }
      double t1 = bench_now();
      for (int k = 0; k < BATCHES; ++k) {
        const size_t o = (size_t)k * SAMPLES;
        ours[wl](&m, fields + o, n + o, ai + o, aw + o, b), sink += b[0][k % SAMPLES];
      }
      double t2 = bench_now();
      bench_keep_best(t0, t1, t2, &best_peer, &best_new);
    }
    const double per = 1e9 / ((double)BATCHES * SAMPLES);
    printf("%2d wl, %d fields: each Ams alone (peer) %.1f ns a sample, angle rows paired %.1f ns, ratio peer / "
           "paired %.2f; bitwise %s (%g)\n",
           nwl, FIELDS, best_peer * per, best_new * per, best_peer / best_new, same ? "the same" : "DIFFERENT", sink);
  }
  free(ams), free(fields), free(n), free(aw), free(ai), free(a), free(b);
  return 0;
}
