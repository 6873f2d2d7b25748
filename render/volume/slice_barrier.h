/* The barrier between the slicer's passes, which meets its threads twice a slice (hundreds of
 * times a frame). OpenMP's own barrier spins (libgomp: GOMP_SPINCOUNT, 300000 pauses, milliseconds)
 * before it sleeps, and its wait policy is fixed for the process when libgomp loads: a thread
 * spinning there keeps its core busy, so that a team thread descheduled by another process on the
 * other core (a second render, an MPI rank, a compile) is never moved to it, and the slice waits
 * for that process's time slice. This one spins for SLICE_BARRIER_SPIN seconds, about what the
 * threads' arrivals spread by when the machine is free, then sleeps, leaving its core free for the
 * thread it waits for. Arrivals are counted with atomics; the sleep is a condition variable. */
#ifndef SL_SLICE_BARRIER_H
#define SL_SLICE_BARRIER_H

#include <omp.h>
#include <pthread.h>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define SLICE_BARRIER_PAUSE() _mm_pause()
#else
#define SLICE_BARRIER_PAUSE() ((void)0)
#endif

#define SLICE_BARRIER_SPIN 50e-6 /* seconds */

typedef struct slice_barrier {
  int team;       /* threads that meet here (set inside the parallel region) */
  int arrived;    /* of this round */
  unsigned round; /* rounds completed: a waiter leaves when it changes */
  pthread_mutex_t lock;
  pthread_cond_t wake;
} slice_barrier;

#define SLICE_BARRIER_INIT {0, 0, 0, PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER}

/* Every thread of the team calls it; the last to arrive releases the others. The atomics order
 * every thread's writes before the barrier ahead of every thread's reads after it. */
static inline void slice_barrier_wait(slice_barrier *b)
{
  const unsigned round = __atomic_load_n(&b->round, __ATOMIC_ACQUIRE);
  if (__atomic_add_fetch(&b->arrived, 1, __ATOMIC_ACQ_REL) == b->team) {
    __atomic_store_n(&b->arrived, 0, __ATOMIC_RELAXED); /* no one arrives again before the round ends */
    pthread_mutex_lock(&b->lock);
    __atomic_store_n(&b->round, round + 1, __ATOMIC_RELEASE);
    pthread_cond_broadcast(&b->wake);
    pthread_mutex_unlock(&b->lock);
    return;
  }
  const double give_up = omp_get_wtime() + SLICE_BARRIER_SPIN;
  for (int i = 1;; ++i) {
    if (__atomic_load_n(&b->round, __ATOMIC_ACQUIRE) != round) return;
    SLICE_BARRIER_PAUSE();
    if (!(i & 63) && omp_get_wtime() > give_up) break;
  }
  pthread_mutex_lock(&b->lock);
  while (__atomic_load_n(&b->round, __ATOMIC_ACQUIRE) == round) pthread_cond_wait(&b->wake, &b->lock);
  pthread_mutex_unlock(&b->lock);
}

#endif
