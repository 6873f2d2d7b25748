// The eye pass's light-buffer look-up (slicer.h, light_bilinear_texel: a part's channels four to a
// vector) against its peer, the form it replaced (a loop per channel over a batch of 32 parts,
// which gathers each float), on a 401x388 buffer (the 256^3 storm's at 512^2) with 3 and 16
// wavelengths, the parts' texels in 16x16-texel tiles as an eye tile's are. Prints nanoseconds a
// part (both ends, every channel), their ratio, and whether the values are bitwise the same.
// Usage: bench_light_lookup [rounds]
#include "slicer.h"

#include "bench_peer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { PARTS = 32, BATCHES = 4096 };

/* The peer: per channel, the scalar lerps over the batch, which the compiler vectorises as gathers. */
static inline __attribute__((always_inline)) void per_channel(const float *st, int di, int dj, int channels,
                                                              const int *t, const double *u, const double *v,
                                                              double (*out)[PARTS])
{
  for (int c = 0; c < channels; ++c) {
#pragma omp simd
    for (int s = 0; s < PARTS; ++s) {
      const float *p = st + c;
      const double r0 = p[t[s]] + u[s] * (p[t[s] + di] - p[t[s]]);
      const double r1 = p[t[s] + dj] + u[s] * (p[t[s] + dj + di] - p[t[s] + dj]);
      out[c][s] = r0 + v[s] * (r1 - r0);
    }
  }
}

static inline __attribute__((always_inline)) void per_part(const float *st, int di, int dj, int channels,
                                                           const int *t, const double *u, const double *v,
                                                           double (*out)[PARTS])
{
  for (int s = 0; s < PARTS; ++s) {
    double value[SL_MAX_WAVELENGTHS + 4];
    light_bilinear_texel(st, di, dj, t[s], u[s], v[s], channels, value);
    for (int c = 0; c < channels; ++c) out[c][s] = value[c];
  }
}

typedef void lookup_fn(const float *, int, int, int, const int *, const double *, const double *, double (*)[PARTS]);

/* Each form in the copy the eye pass runs: the AVX-512 one where the CPU has it, else the baseline. */
#define LOOKUP_COPY(name, body, target) \
  target __attribute__((noinline)) static void name(const float *st, int di, int dj, int channels, const int *t, \
                                                    const double *u, const double *v, double (*out)[PARTS]) \
  { \
    body(st, di, dj, channels, t, u, v, out); \
  }
LOOKUP_COPY(per_channel_base, per_channel, )
LOOKUP_COPY(per_part_base, per_part, )
#ifdef SL_WIDE_TARGET
LOOKUP_COPY(per_channel_wide, per_channel, SL_WIDE_TARGET)
LOOKUP_COPY(per_part_wide, per_part, SL_WIDE_TARGET)
#endif

int main(int argc, char **argv)
{
  const int rounds = argc > 1 ? atoi(argv[1]) : 5;
  const int w = 401, h = 388;
  lookup_fn *peer = per_channel_base, *ours = per_part_base;
  const char *copy = "baseline x86-64";
#ifdef SL_WIDE_TARGET
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512bw"))
    peer = per_channel_wide, ours = per_part_wide, copy = "AVX-512";
#endif
  printf("the %s copy\n", copy);
  srand(1);
  for (int nwl = 3; nwl <= 16; nwl += 13) {
    const int stride = nwl + 1, di = stride, dj = w * stride;
    float *st = malloc(((size_t)w * h * stride + LIGHT_STATE_PAD) * sizeof(float));
    int *t = malloc(sizeof(int) * BATCHES * PARTS);
    double *u = malloc(sizeof(double) * BATCHES * PARTS), *v = malloc(sizeof(double) * BATCHES * PARTS);
    double(*a)[PARTS] = malloc(sizeof(double) * (SL_MAX_WAVELENGTHS + 1) * PARTS);
    double(*b)[PARTS] = malloc(sizeof(double) * (SL_MAX_WAVELENGTHS + 1) * PARTS);
    if (!st || !t || !u || !v || !a || !b) return fprintf(stderr, "bench_light_lookup: out of memory\n"), 1;
    for (size_t i = 0; i < (size_t)w * h * stride + LIGHT_STATE_PAD; ++i) st[i] = -(float)(rand() % 4000) / 97.0f;
    for (int k = 0; k < BATCHES; ++k) {
      const int i0 = rand() % (w - 17), j0 = rand() % (h - 17);
      for (int s = 0; s < PARTS; ++s) {
        t[k * PARTS + s] = ((j0 + rand() % 16) * w + i0 + rand() % 16) * stride;
        u[k * PARTS + s] = rand() / (double)RAND_MAX, v[k * PARTS + s] = rand() / (double)RAND_MAX;
      }
    }
    int same = 1;
    for (int k = 0; k < BATCHES; ++k) {
      peer(st, di, dj, stride, t + k * PARTS, u + k * PARTS, v + k * PARTS, a);
      ours(st, di, dj, stride, t + k * PARTS, u + k * PARTS, v + k * PARTS, b);
      for (int c = 0; c < stride; ++c) same &= !memcmp(a[c], b[c], sizeof a[c]);
    }
    double best_peer = 1e30, best_new = 1e30, sink = 0.0;
    for (int r = 0; r < rounds; ++r) {
      /* alternated round by round, each round every batch twice (a part's two ends) */
      double t0 = bench_now();
      for (int k = 0; k < 2 * BATCHES; ++k)
        peer(st, di, dj, stride, t + (k % BATCHES) * PARTS, u + (k % BATCHES) * PARTS, v + (k % BATCHES) * PARTS, a),
            sink += a[0][k % PARTS];
      double t1 = bench_now();
      for (int k = 0; k < 2 * BATCHES; ++k)
        ours(st, di, dj, stride, t + (k % BATCHES) * PARTS, u + (k % BATCHES) * PARTS, v + (k % BATCHES) * PARTS, b),
            sink += b[0][k % PARTS];
      double t2 = bench_now();
      bench_keep_best(t0, t1, t2, &best_peer, &best_new);
    }
    const double per = 1e9 / ((double)BATCHES * PARTS);
    printf("%2d wl: per channel (peer) %.1f ns a part, per part %.1f ns, ratio peer / per part %.2f; bitwise %s "
           "(%g)\n",
           nwl, best_peer * per, best_new * per, best_peer / best_new, same ? "the same" : "DIFFERENT", sink);
    free(st), free(t), free(u), free(v), free(a), free(b);
  }
  return 0;
}
