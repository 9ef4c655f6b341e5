/* team.c: a small persistent team of POSIX threads for the loops of one
 * run (ps_team in ps_util.h). A job is split into a fixed number of parts
 * by its caller, independent of the team's size, so that every sum is
 * formed in the same order whatever the number of threads: a run gives the
 * same numbers on any number of threads. Workers spin briefly between
 * jobs (a CG iteration starts a few jobs 1-3 ms apart), then sleep on a
 * condition variable; the caller waits for them the same way. Both yield the CPU
 * while they spin, and sleep soon: when the other core is busy (another
 * run, make -j2), a thread that only spun would keep the one it waits for
 * from running. */
#define _GNU_SOURCE /* sched_getaffinity */
#include "ps_util.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>

/* spins of a waiting thread before it sleeps (a few hundred microseconds),
 * with sched_yield every PS_TEAM_YIELD of them */
#define PS_TEAM_SPINS 8192
#define PS_TEAM_YIELD 64

struct ps_team {
  int n_threads;
  pthread_t *thread;        /* [n_threads - 1] workers: members 1.. */
  pthread_mutex_t mutex;
  pthread_cond_t wake;      /* workers: a new job */
  pthread_cond_t finished;  /* the caller: the workers are done */
  int caller_waiting;       /* the caller waits on `finished` (under mutex) */
  atomic_uint generation;   /* bumped by each job (and by the end) */
  atomic_int done;          /* workers that finished the current job */
  int sleepers;             /* workers waiting on `wake` (under mutex) */
  int quit;
  /* the current job */
  void (*fn)(void *arg, int part);
  void *arg;
  int n_parts;
};

typedef struct {
  ps_team *team;
  int member;
} worker_arg;

static inline void cpu_relax(void) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

/* one spin of a waiting thread: 1 when it should now sleep */
static inline int spin(int *spins) {
  if (++*spins >= PS_TEAM_SPINS) return 1;
  if (*spins % PS_TEAM_YIELD == 0)
    sched_yield();
  else
    cpu_relax();
  return 0;
}

static void run_parts(ps_team *t, int member) {
  for (int p = member; p < t->n_parts; p += t->n_threads) t->fn(t->arg, p);
}

static void *worker(void *varg) {
  worker_arg *wa = varg;
  ps_team *t = wa->team;
  int member = wa->member;
  free(wa);
  unsigned seen = 0;
  for (;;) {
    unsigned g;
    int spins = 0;
    while ((g = atomic_load_explicit(&t->generation, memory_order_acquire)) == seen) {
      if (!spin(&spins)) continue;
      pthread_mutex_lock(&t->mutex);
      t->sleepers++;
      while (atomic_load_explicit(&t->generation, memory_order_acquire) == seen)
        pthread_cond_wait(&t->wake, &t->mutex);
      t->sleepers--;
      pthread_mutex_unlock(&t->mutex);
    }
    seen = g;
    if (t->quit) break;
    run_parts(t, member);
    atomic_fetch_add_explicit(&t->done, 1, memory_order_release);
    pthread_mutex_lock(&t->mutex); /* after the count: no lost wake-up */
    if (t->caller_waiting) pthread_cond_signal(&t->finished);
    pthread_mutex_unlock(&t->mutex);
  }
  return NULL;
}

/* wake the workers for a new generation (job or end) */
static void bump(ps_team *t) {
  pthread_mutex_lock(&t->mutex);
  atomic_fetch_add_explicit(&t->generation, 1, memory_order_release);
  if (t->sleepers) pthread_cond_broadcast(&t->wake);
  pthread_mutex_unlock(&t->mutex);
}

int ps_team_create(ps_team **team, int n_threads, ps_ctx *ctx) {
  *team = NULL;
  if (n_threads <= 1) return PS_OK;
  ps_team *t = ps_calloc(1, sizeof *t, ctx);
  if (!t) return PS_ERR_NOMEM;
  t->thread = ps_calloc((size_t)n_threads - 1, sizeof *t->thread, ctx);
  if (!t->thread) {
    free(t);
    return PS_ERR_NOMEM;
  }
  pthread_mutex_init(&t->mutex, NULL);
  pthread_cond_init(&t->wake, NULL);
  pthread_cond_init(&t->finished, NULL);
  atomic_init(&t->generation, 0u);
  atomic_init(&t->done, 0);
  t->n_threads = 1;
  for (int m = 1; m < n_threads; m++) {
    worker_arg *wa = ps_calloc(1, sizeof *wa, ctx);
    if (!wa) break;
    wa->team = t;
    wa->member = m;
    if (pthread_create(&t->thread[m - 1], NULL, worker, wa) != 0) {
      free(wa);
      break;
    }
    t->n_threads = m + 1; /* a thread that cannot be made: fewer members */
  }
  *team = t;
  return PS_OK;
}

void ps_team_free(ps_team *t) {
  if (!t) return;
  t->quit = 1;
  bump(t);
  for (int m = 1; m < t->n_threads; m++) pthread_join(t->thread[m - 1], NULL);
  pthread_mutex_destroy(&t->mutex);
  pthread_cond_destroy(&t->wake);
  pthread_cond_destroy(&t->finished);
  free(t->thread);
  free(t);
}

int ps_team_size(const ps_team *t) { return t ? t->n_threads : 1; }

void ps_team_run(ps_team *t, int n_parts, void (*fn)(void *arg, int part), void *arg) {
  if (!t || t->n_threads <= 1 || n_parts <= 1) {
    for (int p = 0; p < n_parts; p++) fn(arg, p);
    return;
  }
  t->fn = fn;
  t->arg = arg;
  t->n_parts = n_parts;
  atomic_store_explicit(&t->done, 0, memory_order_relaxed);
  bump(t);
  run_parts(t, 0);
  int spins = 0, workers = t->n_threads - 1;
  while (atomic_load_explicit(&t->done, memory_order_acquire) < workers) {
    if (!spin(&spins)) continue;
    pthread_mutex_lock(&t->mutex);
    t->caller_waiting = 1;
    while (atomic_load_explicit(&t->done, memory_order_acquire) < workers)
      pthread_cond_wait(&t->finished, &t->mutex);
    t->caller_waiting = 0;
    pthread_mutex_unlock(&t->mutex);
  }
}

int ps_cpu_count(void) {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0) {
    int n = CPU_COUNT(&set);
    if (n >= 1) return n;
  }
  return 1;
}
