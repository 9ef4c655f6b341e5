/* ps_fuzz.c: a mutation fuzzer for peristatic's inputs. It takes seed
 * files (case files and point clouds), mutates them with text-aware
 * operators (bytes, numbers swapped for extreme values, keys swapped,
 * lines deleted, duplicated or spliced from another seed, nesting), writes
 * each mutant into a scratch folder and runs `peristatic info` on it (a
 * tenth of the case files, when -r is given: `peristatic run` with a
 * small increment budget) in a child process with a time limit.
 *
 * Each input must end with an exit status of 0..3 (success, bad input,
 * solver failure, I/O error: doc/peristatic.md EXIT STATUS): a signal (a
 * crash), an exit status outside that set, a sanitizer report on stderr
 * ("runtime error", "AddressSanitizer", "LeakSanitizer") or running past
 * the time limit for `info` counts as a failure, and the input is kept in
 * the scratch folder as fail-N.yaml (and its cloud) to reproduce it. A
 * `run` past its time limit is counted but is no failure: a mutant may
 * legitimately ask for a million increments.
 *
 * Usage: ps_fuzz [-n N] [-s SEED] [-t S] [-T S] [-m GIB] [-r] [-d DIR] PERISTATIC SEED...
 * -t limits `info`, -T `run` (default 5 s).
 * -m passes --max-memory GIB to peristatic (default 2; 0: not passed), so
 * that a mutant asking for a huge model is refused by the size estimate
 * instead of running into the time limit.
 * Prints one line per failure and a closing "PASS:/FAIL:" line with the
 * counts; exit status 0 when no input failed. Deterministic for a given
 * seed list and -s (GSL's mt19937). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <gsl/gsl_rng.h>

#define MAX_SEEDS 256
#define MAX_TEXT (256 * 1024)

typedef struct seed {
  char path[1024];
  char *text;
  size_t len;
  int is_case;          /* YAML case file (else a point cloud) */
  char cloud[1024];     /* case: the cloud file it names (geometry.file), or "" */
} seed;

static const char *const extreme[] = {
    "0", "-1", "1", "1e300", "-1e300", "1e-300", "1e400", "nan", "inf", "-inf",
    "2147483647", "2147483648", "-2147483649", "9223372036854775807", "1e155",
    "0x10", "\" 5.1\"", "1.0e9", "4294967296", "0.5", "3", "1e-12", "100000", ""};
static const char *const keys[] = {
    "file", "counts", "alpha", "horizon_factor", "type", "model", "dim", "nu", "E",
    "spacing", "origin", "jitter", "n_xi", "n_eta", "per_zone", "k", "sizes",
    "yield_strain", "delta", "cracks", "holes", "displace", "traction", "select",
    "measure", "load_step", "max_load", "boundary", "plane", "lattice", "c"};

static char *read_all(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  char *buf = malloc(MAX_TEXT + 1);
  size_t n = buf ? fread(buf, 1, MAX_TEXT, f) : 0;
  fclose(f);
  if (!buf) return NULL;
  buf[n] = '\0';
  *len = n;
  return buf;
}

static int write_all(const char *path, const char *text, size_t len) {
  FILE *f = fopen(path, "wb");
  if (!f) return -1;
  size_t w = fwrite(text, 1, len, f);
  return fclose(f) == 0 && w == len ? 0 : -1;
}

/* the value of "file:" in a case text (its first occurrence), or "" */
static void cloud_of(const char *text, char *out, size_t size) {
  const char *p = strstr(text, "file:");
  out[0] = '\0';
  if (!p) return;
  p += 5;
  while (*p == ' ' || *p == '"' || *p == '\'') p++;
  size_t n = strcspn(p, " \"'\n,}#");
  if (n >= size) n = size - 1;
  memcpy(out, p, n);
  out[n] = '\0';
}

/* replace text[a, b) of buf (length *len) by rep; stays within MAX_TEXT */
static void splice(char *buf, size_t *len, size_t a, size_t b, const char *rep, size_t rl) {
  if (*len - (b - a) + rl > MAX_TEXT) return;
  memmove(buf + a + rl, buf + b, *len - b + 1);
  memcpy(buf + a, rep, rl);
  *len = *len - (b - a) + rl;
}

/* a random position of a token matching class `num` (1: number, 0: word) */
static int find_token(const char *buf, size_t len, int num, gsl_rng *r, size_t *a,
                      size_t *b) {
  for (int tries = 0; tries < 64; tries++) {
    size_t p = gsl_rng_uniform_int(r, len ? len : 1);
    while (p < len && !(num ? (buf[p] >= '0' && buf[p] <= '9')
                            : ((buf[p] >= 'a' && buf[p] <= 'z') || buf[p] == '_')))
      p++;
    if (p >= len) continue;
    size_t s = p, e = p;
    if (num) {
      while (s > 0 && strchr("0123456789.eE+-", buf[s - 1])) s--;
      while (e < len && strchr("0123456789.eE+-", buf[e])) e++;
    } else {
      while (s > 0 && ((buf[s - 1] >= 'a' && buf[s - 1] <= 'z') || buf[s - 1] == '_')) s--;
      while (e < len && ((buf[e] >= 'a' && buf[e] <= 'z') || buf[e] == '_')) e++;
    }
    *a = s;
    *b = e;
    return 1;
  }
  return 0;
}

/* the start of line k (0-based) or len */
static size_t line_start(const char *buf, size_t len, size_t k) {
  size_t p = 0;
  while (k > 0 && p < len) {
    if (buf[p++] == '\n') k--;
  }
  return p;
}

static size_t count_lines(const char *buf, size_t len) {
  size_t n = 1;
  for (size_t p = 0; p < len; p++) n += buf[p] == '\n';
  return n;
}

static void mutate_once(char *buf, size_t *len, const seed *seeds, int n_seeds, gsl_rng *r) {
  size_t a, b, nl = count_lines(buf, *len);
  switch (gsl_rng_uniform_int(r, 9)) {
  case 0: /* flip one byte */
    if (*len) buf[gsl_rng_uniform_int(r, *len)] = (char)gsl_rng_uniform_int(r, 256);
    break;
  case 1: { /* insert a few random bytes */
    char ins[4];
    size_t k = 1 + gsl_rng_uniform_int(r, 4);
    for (size_t i = 0; i < k; i++) ins[i] = (char)gsl_rng_uniform_int(r, 256);
    a = gsl_rng_uniform_int(r, *len + 1);
    splice(buf, len, a, a, ins, k);
    break;
  }
  case 2: /* delete a span */
    if (*len) {
      a = gsl_rng_uniform_int(r, *len);
      b = a + 1 + gsl_rng_uniform_int(r, 16);
      if (b > *len) b = *len;
      splice(buf, len, a, b, "", 0);
    }
    break;
  case 3:
  case 4: /* a number becomes an extreme value */
    if (find_token(buf, *len, 1, r, &a, &b)) {
      const char *v = extreme[gsl_rng_uniform_int(r, sizeof extreme / sizeof *extreme)];
      splice(buf, len, a, b, v, strlen(v));
    }
    break;
  case 5: /* a key or word becomes another key */
    if (find_token(buf, *len, 0, r, &a, &b)) {
      const char *v = keys[gsl_rng_uniform_int(r, sizeof keys / sizeof *keys)];
      splice(buf, len, a, b, v, strlen(v));
    }
    break;
  case 6: { /* delete or duplicate a line */
    size_t k = gsl_rng_uniform_int(r, nl);
    a = line_start(buf, *len, k);
    b = line_start(buf, *len, k + 1);
    if (gsl_rng_uniform_int(r, 2)) {
      splice(buf, len, a, b, "", 0);
    } else if (b > a && b - a < 4096) {
      char line[4096];
      memcpy(line, buf + a, b - a);
      splice(buf, len, b, b, line, b - a);
    }
    break;
  }
  case 7: { /* splice a line of another seed of the same kind */
    const seed *o = &seeds[gsl_rng_uniform_int(r, (unsigned long)n_seeds)];
    size_t ol = count_lines(o->text, o->len), k = gsl_rng_uniform_int(r, ol);
    size_t s = line_start(o->text, o->len, k), e = line_start(o->text, o->len, k + 1);
    a = line_start(buf, *len, gsl_rng_uniform_int(r, nl + 1));
    if (e > s) splice(buf, len, a, a, o->text + s, e - s);
    break;
  }
  default: { /* nesting: wrap a value in brackets, a few levels deep */
    if (find_token(buf, *len, 1, r, &a, &b)) {
      size_t depth = 1 + gsl_rng_uniform_int(r, 40);
      char open[64], close[64];
      for (size_t i = 0; i < depth; i++) open[i] = gsl_rng_uniform_int(r, 2) ? '[' : '{';
      for (size_t i = 0; i < depth; i++) close[i] = open[depth - 1 - i] == '[' ? ']' : '}';
      splice(buf, len, b, b, close, depth);
      splice(buf, len, a, a, open, depth);
    }
    break;
  }
  }
}

/* Run argv with the time limit; returns the wait status, or -1 when it
 * ran past the limit (then it is killed). stderr goes to errpath. */
static int run_limited(char *const argv[], const char *errpath, double limit) {
  pid_t pid = fork();
  if (pid < 0) return -2;
  if (pid == 0) {
    int fd = open(errpath, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    int nul = open("/dev/null", O_WRONLY);
    if (fd >= 0) dup2(fd, 2);
    if (nul >= 0) dup2(nul, 1);
    setpgid(0, 0);
    execv(argv[0], argv);
    _exit(127);
  }
  struct timespec t0, t, nap = {0, 2000000};
  clock_gettime(CLOCK_MONOTONIC, &t0);
  for (;;) {
    int st;
    pid_t w = waitpid(pid, &st, WNOHANG);
    if (w == pid) return st;
    clock_gettime(CLOCK_MONOTONIC, &t);
    if ((double)(t.tv_sec - t0.tv_sec) + 1e-9 * (double)(t.tv_nsec - t0.tv_nsec) > limit) {
      kill(-pid, SIGKILL);
      kill(pid, SIGKILL);
      waitpid(pid, &st, 0);
      return -1;
    }
    nanosleep(&nap, NULL);
  }
}

/* 1 when the file holds a sanitizer report */
static int sanitizer_report(const char *path) {
  size_t len = 0;
  char *t = read_all(path, &len);
  int bad = t && (strstr(t, "runtime error") || strstr(t, "AddressSanitizer") ||
                  strstr(t, "LeakSanitizer") || strstr(t, "UndefinedBehaviorSanitizer"));
  free(t);
  return bad;
}

static int usage(void) {
  fprintf(stderr, "usage: ps_fuzz [-n N] [-s SEED] [-t S] [-T S] [-m GIB] [-r] [-d DIR] "
                  "PERISTATIC SEED...\n");
  return 2;
}

int main(int argc, char **argv) {
  long n_inputs = 300;
  unsigned long rseed = 1;
  double limit = 20.0, run_limit = 5.0;
  int with_runs = 0;
  const char *dir = "fuzz_tmp", *max_mem = "2";
  int i = 1;
  for (; i < argc && argv[i][0] == '-'; i++) {
    if (!strcmp(argv[i], "-r")) with_runs = 1;
    else if (i + 1 >= argc) return usage();
    else if (!strcmp(argv[i], "-n")) n_inputs = atol(argv[++i]);
    else if (!strcmp(argv[i], "-s")) rseed = strtoul(argv[++i], NULL, 10);
    else if (!strcmp(argv[i], "-t")) limit = atof(argv[++i]);
    else if (!strcmp(argv[i], "-T")) run_limit = atof(argv[++i]);
    else if (!strcmp(argv[i], "-d")) dir = argv[++i];
    else if (!strcmp(argv[i], "-m")) max_mem = argv[++i];
    else return usage();
  }
  if (argc - i < 2) return usage();
  const char *prog = argv[i++];
  static seed seeds[MAX_SEEDS];
  int n_seeds = 0;
  for (; i < argc && n_seeds < MAX_SEEDS; i++) {
    seed *s = &seeds[n_seeds];
    snprintf(s->path, sizeof s->path, "%s", argv[i]);
    if (!(s->text = read_all(argv[i], &s->len))) {
      fprintf(stderr, "ps_fuzz: cannot read %s\n", argv[i]);
      return 2;
    }
    size_t pl = strlen(argv[i]);
    s->is_case = (pl > 5 && !strcmp(argv[i] + pl - 5, ".yaml")) ||
                 (pl > 4 && !strcmp(argv[i] + pl - 4, ".yml"));
    if (s->is_case) cloud_of(s->text, s->cloud, sizeof s->cloud);
    n_seeds++;
  }
  mkdir(dir, 0777);
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, rseed);
  char *buf = malloc(MAX_TEXT + 1);
  long failed = 0, timeouts = 0, runs = 0, by_code[4] = {0, 0, 0, 0};
  for (long k = 0; k < n_inputs; k++) {
    const seed *s = &seeds[gsl_rng_uniform_int(r, (unsigned long)n_seeds)];
    char case_path[1200], cloud_path[1200], err_path[1200], out_path[1200];
    snprintf(case_path, sizeof case_path, "%s/input.yaml", dir);
    snprintf(err_path, sizeof err_path, "%s/stderr.txt", dir);
    snprintf(out_path, sizeof out_path, "%s/out", dir);
    size_t len;
    int mutate_cloud = 0;
    const seed *cs = s;
    if (!s->is_case) { /* a cloud: mutate it under a case that reads it */
      cs = NULL;
      for (int j = 0; j < n_seeds && !cs; j++) {
        const char *c = seeds[j].cloud, *base = strrchr(s->path, '/');
        base = base ? base + 1 : s->path;
        if (seeds[j].is_case && c[0] && !strcmp(c, base)) cs = &seeds[j];
      }
      if (!cs) continue;
      mutate_cloud = 1;
    }
    /* the case text, and its cloud (copied or mutated) beside it */
    memcpy(buf, cs->text, cs->len + 1);
    len = cs->len;
    if (cs->cloud[0]) {
      const seed *cl = NULL;
      for (int j = 0; j < n_seeds && !cl; j++) {
        const char *base = strrchr(seeds[j].path, '/');
        base = base ? base + 1 : seeds[j].path;
        if (!seeds[j].is_case && !strcmp(base, cs->cloud)) cl = &seeds[j];
      }
      snprintf(cloud_path, sizeof cloud_path, "%s/%s", dir, cs->cloud);
      if (cl) {
        char *cb = malloc(MAX_TEXT + 1);
        size_t cbl = cl->len;
        memcpy(cb, cl->text, cl->len + 1);
        if (mutate_cloud) {
          int m = 1 + (int)gsl_rng_uniform_int(r, 3);
          for (int j = 0; j < m; j++) mutate_once(cb, &cbl, cl, 1, r);
        }
        write_all(cloud_path, cb, cbl);
        free(cb);
      }
    }
    if (!mutate_cloud) {
      int m = 1 + (int)gsl_rng_uniform_int(r, 4);
      for (int j = 0; j < m; j++) mutate_once(buf, &len, seeds, n_seeds, r);
    }
    write_all(case_path, buf, len);
    int as_run = with_runs && gsl_rng_uniform_int(r, 10) == 0;
    char *args[16];
    int na = 0;
    args[na++] = (char *)prog;
    args[na++] = as_run ? "run" : "info";
    if (as_run) {
      char *more[] = {"-q", "-t", "1", "-o", out_path};
      for (int j = 0; j < 5; j++) args[na++] = more[j];
    }
    if (strcmp(max_mem, "0") != 0) {
      args[na++] = "--max-memory";
      args[na++] = (char *)max_mem;
    }
    args[na++] = case_path;
    args[na] = NULL;
    int st = run_limited(args, err_path, as_run ? run_limit : limit);
    runs += as_run;
    const char *why = NULL;
    char whybuf[64];
    if (st == -1) {
      timeouts++;
      if (!as_run) why = "time-out";
    } else if (st < 0) {
      why = "cannot fork";
    } else if (WIFSIGNALED(st)) {
      snprintf(whybuf, sizeof whybuf, "signal %d", WTERMSIG(st));
      why = whybuf;
    } else if (WEXITSTATUS(st) > 3) {
      snprintf(whybuf, sizeof whybuf, "exit status %d", WEXITSTATUS(st));
      why = whybuf;
    } else {
      by_code[WEXITSTATUS(st)]++;
    }
    if (!why && sanitizer_report(err_path)) why = "sanitizer report";
    if (why) {
      char keep[1300];
      failed++;
      snprintf(keep, sizeof keep, "%s/fail-%ld.yaml", dir, k);
      rename(case_path, keep);
      snprintf(keep, sizeof keep, "%s/fail-%ld.stderr", dir, k);
      rename(err_path, keep);
      printf("FAIL: input %ld (from %s, peristatic %s): %s; kept as %s/fail-%ld.yaml\n", k,
             s->path, as_run ? "run" : "info", why, dir, k);
    }
  }
  printf("%s: %ld mutated inputs (%ld as run): %ld failed; exit 0/1/2/3: %ld/%ld/%ld/%ld; "
         "%ld past the time limit\n",
         failed ? "FAIL" : "PASS", n_inputs, runs, failed, by_code[0], by_code[1],
         by_code[2], by_code[3], timeouts);
  free(buf);
  gsl_rng_free(r);
  for (int j = 0; j < n_seeds; j++) free(seeds[j].text);
  return failed ? 1 : 0;
}
