// Shared by the C benchmarks that time a form against its peer in the same process: the clock, and
// each form's best round, the rounds alternated (the peer from t0 to t1, the new form from t1 to t2)
// so that a noisy machine slows both alike.
#ifndef SL_BENCH_PEER_H
#define SL_BENCH_PEER_H

#include <time.h>

static inline double bench_now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static inline void bench_keep_best(double t0, double t1, double t2, double *best_peer, double *best_new)
{
  if (t1 - t0 < *best_peer) *best_peer = t1 - t0;
  if (t2 - t1 < *best_new) *best_new = t2 - t1;
}

#endif
