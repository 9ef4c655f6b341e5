/* signals.c: SIGINT and SIGTERM end a run cleanly. The handler only
 * records the signal; the load path (run.c) and the sweep (griffith.c)
 * look at it between increments and stop with their outputs in order. */
#define _DEFAULT_SOURCE
#include "ps_app.h"

#include <signal.h>
#include <string.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

/* The one signal received, 0 if none. Process-wide because a signal
 * handler can reach nothing else: it is written only by the handler and
 * read through ps_signal_received. */
static volatile sig_atomic_t received = 0;

static void on_signal(int sig) {
  if (!received) received = sig;
}

/* flags 0 or SA_RESETHAND (the handler acts once; then the default
 * action, ending the process, takes the next signal of that kind) */
static void install(int flags) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  /* SA_RESTART: a read or write under way when the signal comes goes on
   * (stdio would otherwise report EINTR as a write error) */
  sa.sa_flags = SA_RESTART | flags;
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
}

void ps_signals_install(void) { install(SA_RESETHAND); }

int ps_signal_received(void) { return received; }

const char *ps_signal_name(int sig) {
  return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal";
}

int ps_signals_worker(long parent) {
#ifdef __linux__
  if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) return -1;
#endif
  if ((long)getppid() != parent) return -1; /* it died before prctl */
  install(0);
  return 0;
}
