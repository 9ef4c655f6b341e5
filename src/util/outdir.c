/* outdir.c: output folders owned by peristatic: the marker and the
 * ownership rule (our marker or signature, and nothing but the names we
 * write), staging folders, the commit DIR.partial -> DIR (an atomic
 * exchange where the file system has one, else through DIR.old) with its
 * recovery after a kill, and the writer's lock DIR.lock. */
#define _GNU_SOURCE /* renameat2 and RENAME_EXCHANGE (glibc >= 2.28) */
#include "ps_util.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "config.h"

/* longest folder name we take: leaves room for ".partial", "/summary.txt" */
#define PS_DIR_MAX 1000

static int too_long(const char *path, ps_ctx *ctx) {
  return ps_error(ctx, PS_ERR_IO, "%.200s...: path too long (at most %d characters)", path,
                  PS_DIR_MAX);
}

/* 1 when the first line of dir/name starts with head */
static int file_starts(const char *dir, const char *name, const char *head) {
  char path[1200], line[64] = "";
  struct stat sb;
  snprintf(path, sizeof path, "%s/%s", dir, name);
  if (lstat(path, &sb) != 0 || !S_ISREG(sb.st_mode)) return 0;
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  int ok = fgets(line, sizeof line, f) && !strncmp(line, head, strlen(head));
  fclose(f);
  return ok;
}

static int dir_is_empty(const char *path) {
  DIR *d = opendir(path);
  struct dirent *e;
  int empty = 1;
  if (!d) return 0;
  while (empty && (e = readdir(d)))
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) empty = 0;
  closedir(d);
  return empty;
}

/* 1 when s is prefix, one or more digits, suffix */
static int numbered(const char *s, const char *prefix, const char *suffix) {
  size_t p = strlen(prefix), n = strlen(s), x = strlen(suffix), d = 0;
  if (n <= p + x || strncmp(s, prefix, p) || strcmp(s + n - x, suffix)) return 0;
  for (d = p; d < n - x && s[d] >= '0' && s[d] <= '9'; d++) continue;
  return d == n - x;
}

long ps_outdir_field_step(const char *name, int *listed) {
  const char *p = !strncmp(name, "particles_", 10) ? name + 10
                  : !strncmp(name, "arms_", 5)      ? name + 5
                                                    : NULL;
  char *end = NULL;
  if (listed) *listed = 0;
  if (!p || *p < '0' || *p > '9') return -1;
  long step = strtol(p, &end, 10);
  if (!strcmp(end, ".vtu") || !strcmp(end, ".pvtu")) {
    if (listed) *listed = 1;
    return step;
  }
  if (strncmp(end, "_p", 2) != 0 || end[2] < '0' || end[2] > '9') return -1;
  strtol(end + 2, &end, 10);
  return !strcmp(end, ".vtu") ? step : -1;
}

/* 1 when name is a file peristatic writes into an output folder (a run's
 * or a sweep's; with ".tmp" appended while it is being written) */
static int our_file(const char *name, int tmp_ok) {
  static const char *const fixed[] = {PS_OUTDIR_MARKER, "summary.txt",   "history.csv",
                                      "particles.csv",  "griffith.csv",  "griffith.gp",
                                      "griffith.png",   "griffith_fit.txt", "path.gp",
                                      "path.png",       "particles.pvd", "arms.pvd",
                                      "checkpoint.bin", NULL};
  /* NAME_N.SUFFIX; .vtk: the legacy field files of earlier versions;
   * checkpoint_pR.bin: a distributed run's process R's checkpoint (the
   * field files: ps_outdir_field_step) */
  static const char *const numbered_names[][2] = {{"particles_", ".vtk"},
                                                  {"arms_", ".vtk"},
                                                  {"job-", ".log"},
                                                  {"checkpoint_p", ".bin"}};
  size_t n = strlen(name);
  for (int i = 0; fixed[i]; i++)
    if (!strcmp(name, fixed[i])) return 1;
  for (size_t i = 0; i < sizeof numbered_names / sizeof numbered_names[0]; i++)
    if (numbered(name, numbered_names[i][0], numbered_names[i][1])) return 1;
  if (ps_outdir_field_step(name, NULL) >= 0) return 1;
  if (tmp_ok && n > 4 && !strcmp(name + n - 4, ".tmp")) {
    char base[256];
    if (n - 4 >= sizeof base) return 0;
    memcpy(base, name, n - 4);
    base[n - 4] = '\0';
    return our_file(base, 0);
  }
  return 0;
}

/* 1 when name is "delta_c" and c/delta as %.6g writes it, then `suffix`
 * ("" for a sweep's run folder, ".partial" or ".old" beside it, ".claim") */
static int sweep_entry(const char *name, const char *suffix) {
  size_t n = strlen(name), x = strlen(suffix);
  if (n <= 7 + x || strncmp(name, "delta_c", 7) || strcmp(name + n - x, suffix)) return 0;
  for (size_t i = 7; i < n - x; i++)
    if (!strchr("0123456789.e+-", name[i])) return 0;
  return 1;
}

/* The first (in byte order) few entries of a folder that peristatic did
 * not write. */
typedef struct foreign {
  char name[3][80];
  int n;     /* kept in name[] (at most 3) */
  long all;  /* found */
} foreign;

static void foreign_add(foreign *fo, const char *sub, const char *name) {
  char e[80];
  snprintf(e, sizeof e, "%s%s%s", sub, sub[0] ? "/" : "", name);
  fo->all++;
  int at = fo->n;
  while (at > 0 && strcmp(e, fo->name[at - 1]) < 0) at--;
  if (at >= 3) return;
  for (int k = (fo->n < 3 ? fo->n : 2); k > at; k--) memcpy(fo->name[k], fo->name[k - 1], 80);
  memcpy(fo->name[at], e, 80);
  if (fo->n < 3) fo->n++;
}

/* Every entry of dir (sub: its name inside the top folder, "" for the top)
 * that is not one peristatic writes goes to fo: files of ours, and at the
 * top the run folders of a sweep (delta_cNNNN, with .partial or .old
 * while one is staged or replaced; their files checked the same way) and
 * the claims of its runs. */
static void find_foreign(const char *dir, const char *sub, foreign *fo) {
  DIR *d = opendir(dir);
  struct dirent *e;
  char path[1400];
  struct stat sb;
  if (!d) {
    foreign_add(fo, "", sub[0] ? sub : "(its list of files cannot be read)");
    return;
  }
  while ((e = readdir(d))) {
    const char *n = e->d_name;
    if (!strcmp(n, ".") || !strcmp(n, "..")) continue;
    snprintf(path, sizeof path, "%s/%s", dir, n);
    if (lstat(path, &sb) != 0) continue; /* gone meanwhile */
    int top = !sub[0];
    if (S_ISREG(sb.st_mode) && (our_file(n, 1) || (top && sweep_entry(n, ".claim"))))
      continue;
    if (S_ISDIR(sb.st_mode) && top &&
        (sweep_entry(n, "") || sweep_entry(n, ".partial") || sweep_entry(n, ".old"))) {
      find_foreign(path, n, fo);
      continue;
    }
    foreign_add(fo, sub, n);
  }
  closedir(d);
}

int ps_outdir_owned(const char *path, char *why, size_t len) {
  struct stat sb;
  char marker[1200];
  if (lstat(path, &sb) != 0) {
    if (errno == ENOENT) return 0;
    snprintf(why, len, "cannot be examined (%s)", strerror(errno));
    return -1;
  }
  if (S_ISLNK(sb.st_mode)) {
    snprintf(why, len, "is a symbolic link");
    return -1;
  }
  if (!S_ISDIR(sb.st_mode)) {
    snprintf(why, len, "is a file, not a folder");
    return -1;
  }
  snprintf(marker, sizeof marker, "%s/%s", path, PS_OUTDIR_MARKER);
  if (!(lstat(marker, &sb) == 0 && S_ISREG(sb.st_mode)) &&
      !file_starts(path, "summary.txt", "case: ") &&
      !file_starts(path, "history.csv", "step,load_factor,") &&
      !file_starts(path, "griffith.csv", "delta_over_c,") && !dir_is_empty(path)) {
    snprintf(why, len, "is a folder peristatic did not write (no %s marker, no summary.txt "
                       "or griffith.csv of ours)", PS_OUTDIR_MARKER);
    return -1;
  }
  /* ours, if it holds nothing else: a case file or notes kept in an
   * output folder would go with it */
  foreign fo = {.n = 0, .all = 0};
  find_foreign(path, "", &fo);
  if (fo.all == 0) return 1;
  snprintf(why, len, "holds files peristatic did not write (%s%s%s%s%s%s)", fo.name[0],
           fo.n > 1 ? ", " : "", fo.n > 1 ? fo.name[1] : "", fo.n > 2 ? ", " : "",
           fo.n > 2 ? fo.name[2] : "", fo.all > 3 ? ", ..." : "");
  return -1;
}

/* PS_OK when nothing or a folder of ours is at path, else PS_ERR_IO with
 * the message that refuses it; *ours = 1 for a folder of ours */
static int check_ours(const char *path, int *ours, ps_ctx *ctx) {
  char why[512];
  int o = ps_outdir_owned(path, why, sizeof why);
  if (ours) *ours = o == 1;
  if (o >= 0) return PS_OK;
  if (!strncmp(why, "holds ", 6))
    return ps_error(ctx, PS_ERR_IO,
                    "%s %s: peristatic replaces or removes only a folder that holds nothing "
                    "but its own output, so it leaves this untouched and stops: move them out "
                    "or choose another output folder (-o)",
                    path, why);
  return ps_error(ctx, PS_ERR_IO,
                  "%s %s: peristatic replaces or removes only a folder it wrote itself "
                  "(holding its %s marker), so it leaves this untouched and stops: choose "
                  "another output folder (-o) or move %s away",
                  path, why, PS_OUTDIR_MARKER, path);
}

int ps_mkdir_p(const char *path, ps_ctx *ctx) {
  char buf[1200];
  if (strlen(path) >= sizeof buf) return too_long(path, ctx);
  strcpy(buf, path);
  for (char *p = buf + 1; *p; p++)
    if (*p == '/') {
      *p = '\0';
      if (mkdir(buf, 0777) != 0 && errno != EEXIST)
        return ps_error(ctx, PS_ERR_IO, "%s: cannot create directory: %s", buf,
                        strerror(errno));
      *p = '/';
    }
  if (mkdir(buf, 0777) != 0 && errno != EEXIST)
    return ps_error(ctx, PS_ERR_IO, "%s: cannot create directory: %s", buf,
                    strerror(errno));
  return PS_OK;
}

/* everything below the top folder but the top folder's marker */
static int rm_entry(const char *p, const struct stat *sb, int flag, struct FTW *f) {
  (void)sb;
  (void)flag;
  if (f->level == 0) return 0;
  if (f->level == 1 && !strcmp(p + f->base, PS_OUTDIR_MARKER)) return 0;
  return remove(p);
}

int ps_rm_rf(const char *path, ps_ctx *ctx) {
  struct stat sb;
  char marker[1200];
  if (lstat(path, &sb) != 0) return PS_OK; /* nothing there */
  if (!S_ISDIR(sb.st_mode)) { /* a file or a link: the entry itself only */
    if (remove(path) != 0)
      return ps_error(ctx, PS_ERR_IO, "%s: cannot remove: %s", path, strerror(errno));
    return PS_OK;
  }
  /* FTW_MOUNT: never into another file system mounted below */
  if (nftw(path, rm_entry, 32, FTW_DEPTH | FTW_PHYS | FTW_MOUNT) != 0)
    return ps_error(ctx, PS_ERR_IO, "%s: cannot remove: %s", path, strerror(errno));
  snprintf(marker, sizeof marker, "%s/%s", path, PS_OUTDIR_MARKER);
  if ((unlink(marker) != 0 && errno != ENOENT) || rmdir(path) != 0)
    return ps_error(ctx, PS_ERR_IO, "%s: cannot remove: %s", path, strerror(errno));
  return PS_OK;
}

/* write dir/.peristatic */
static int write_marker(const char *dir, ps_ctx *ctx) {
  char path[1200];
  snprintf(path, sizeof path, "%s/%s", dir, PS_OUTDIR_MARKER);
  FILE *f = fopen(path, "w");
  if (!f) return ps_error(ctx, PS_ERR_IO, "%s: cannot open for writing: %s", path, strerror(errno));
  int bad = fprintf(f, "peristatic output folder (version %s): peristatic replaces this "
                       "folder, and everything in it, when it writes here again\n",
                    PACKAGE_VERSION) < 0;
  if (fclose(f) != 0 || bad) return ps_error(ctx, PS_ERR_IO, "%s: write failed", path);
  return PS_OK;
}

/* 1 when dir/name is a regular file */
static int has_file(const char *dir, const char *name) {
  char path[1300];
  struct stat sb;
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return lstat(path, &sb) == 0 && S_ISREG(sb.st_mode);
}

int ps_outdir_prepare(const char *dir, ps_ctx *ctx) {
  char old[1200], partial[1200];
  int dir_ours, old_ours;
  if (strlen(dir) > PS_DIR_MAX) return too_long(dir, ctx);
  snprintf(old, sizeof old, "%s.old", dir);
  snprintf(partial, sizeof partial, "%s.partial", dir);
  PS_CHECK(check_ours(dir, &dir_ours, ctx));
  PS_CHECK(check_ours(old, &old_ours, ctx));
  PS_CHECK(check_ours(partial, NULL, ctx));
  if (!old_ours) return PS_OK;
  if (!dir_ours) { /* dir missing (check_ours let it pass) */
    if (rename(old, dir) != 0)
      return ps_error(ctx, PS_ERR_IO, "%s: cannot restore from %s: %s", dir, old,
                      strerror(errno));
    ps_log(ctx, 0, "peristatic: %s was missing and %s held its results (an earlier run was "
                   "stopped while replacing them): restored %s\n", dir, old, dir);
    return PS_OK;
  }
  /* an empty dir (not even our marker: e.g. a script's mkdir -p after a
   * kill between the renames) beside the only copy of the results */
  if (dir_is_empty(dir) && (has_file(old, "summary.txt") || has_file(old, "griffith.csv"))) {
    if (rmdir(dir) != 0 || rename(old, dir) != 0)
      return ps_error(ctx, PS_ERR_IO, "%s: cannot restore from %s: %s", dir, old,
                      strerror(errno));
    ps_log(ctx, 0, "peristatic: %s was an empty folder and %s held its results (an earlier "
                   "run was stopped while replacing them): restored %s\n", dir, old, dir);
    return PS_OK;
  }
  ps_log(ctx, 2, "# removing %s, left over from an earlier run\n", old);
  return ps_rm_rf(old, ctx);
}

int ps_outdir_fresh(const char *path, ps_ctx *ctx) {
  int ours;
  if (strlen(path) > PS_DIR_MAX + 16) return too_long(path, ctx);
  PS_CHECK(check_ours(path, &ours, ctx));
  if (ours) PS_CHECK(ps_rm_rf(path, ctx));
  PS_CHECK(ps_mkdir_p(path, ctx));
  return write_marker(path, ctx);
}

int ps_outdir_open(const char *dir, ps_ctx *ctx) {
  int ours;
  if (strlen(dir) > PS_DIR_MAX + 16) return too_long(dir, ctx);
  PS_CHECK(check_ours(dir, &ours, ctx));
  if (ours) return PS_OK;
  PS_CHECK(ps_mkdir_p(dir, ctx));
  return write_marker(dir, ctx);
}

/* staging in place of final. When final is there (ours), the two are
 * exchanged in one step (renameat2 RENAME_EXCHANGE: final is never
 * missing, whatever kills us when) and the earlier tree, now at staging,
 * is moved on to old; where the file system has no exchange, final goes
 * to old and staging to final (the window that ps_outdir_prepare repairs).
 * *leftover = the path of the earlier tree to remove, "" when none. */
static int swap_in(const char *staging, const char *final, const char *old, char *leftover,
                   size_t len, ps_ctx *ctx) {
  int final_ours, old_ours;
  leftover[0] = '\0';
  /* checked again: only a folder of ours may go */
  PS_CHECK(check_ours(final, &final_ours, ctx));
  PS_CHECK(check_ours(old, &old_ours, ctx));
  if (old_ours) PS_CHECK(ps_rm_rf(old, ctx));
  if (final_ours) {
#ifdef RENAME_EXCHANGE
    if (renameat2(AT_FDCWD, staging, AT_FDCWD, final, RENAME_EXCHANGE) == 0) {
      /* out of the way of a --resume that would continue in staging */
      snprintf(leftover, len, "%s", rename(staging, old) == 0 ? old : staging);
      return PS_OK;
    }
    if (errno != EINVAL && errno != ENOSYS)
      return ps_error(ctx, PS_ERR_IO, "%s: cannot exchange with %s: %s", final, staging,
                      strerror(errno));
#endif
    if (rename(final, old) != 0)
      return ps_error(ctx, PS_ERR_IO, "%s: cannot move aside: %s", final, strerror(errno));
    snprintf(leftover, len, "%s", old);
  }
  if (rename(staging, final) != 0) {
    int e = errno;
    if (leftover[0] && rename(old, final) == 0) leftover[0] = '\0';
    return ps_error(ctx, PS_ERR_IO, "%s: cannot rename from %s: %s", final, staging,
                    strerror(e));
  }
  return PS_OK;
}

int ps_dir_commit(const char *staging, const char *final, ps_ctx *ctx) {
  char old[1200], leftover[1200];
  sigset_t block, saved;
  if (strlen(final) > PS_DIR_MAX + 16) return too_long(final, ctx);
  snprintf(old, sizeof old, "%s.old", final);
  sigemptyset(&block);
  sigaddset(&block, SIGINT);
  sigaddset(&block, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &block, &saved);
  int status = swap_in(staging, final, old, leftover, sizeof leftover, ctx);
  pthread_sigmask(SIG_SETMASK, &saved, NULL); /* a signal held back arrives now */
  if (status < 0 || !leftover[0]) return status;
  /* the results are in final: a tree we cannot remove is only a warning
   * (the next run into final removes it) */
  if (ps_rm_rf(leftover, ctx) < 0)
    ps_log(ctx, 0, "peristatic: warning: %s (the results are in %s; the earlier ones left "
                   "in %s go at the next run)\n", ctx->msg, final, leftover);
  return PS_OK;
}

/* pid of the holder from the lock file, 0 when unknown */
static long lock_holder(int fd) {
  char buf[64] = "";
  long pid = 0;
  ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
  if (n > 0) buf[n] = '\0';
  if (sscanf(buf, "peristatic lock: pid %ld", &pid) != 1) pid = 0;
  return pid;
}

/* open and flock dir.lock; *busy = 1 when another process holds it.
 * Returns the fd (-1 on error, message in ctx) */
static int lock_open(const char *lock, const char *dir, int *busy, ps_ctx *ctx) {
  struct stat sb;
  *busy = 0;
  int fd = open(lock, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0 || fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
    ps_error(ctx, PS_ERR_IO, "%s: cannot open the lock file of %s: %s", lock, dir,
             fd < 0 ? strerror(errno) : "not a regular file");
    if (fd >= 0) close(fd);
    return -1;
  }
  if (flock(fd, LOCK_EX | LOCK_NB) == 0) return fd;
  if (errno == EWOULDBLOCK) {
    long pid = lock_holder(fd);
    char who[48] = "";
    if (pid > 0) snprintf(who, sizeof who, " (pid %ld)", pid);
    ps_error(ctx, PS_ERR_IO,
             "%s is being written by another peristatic process%s: wait for it to end, "
             "or write elsewhere with -o (lock %s)",
             dir, who, lock);
    *busy = 1;
  } else {
    ps_error(ctx, PS_ERR_IO, "%s: cannot lock: %s", lock, strerror(errno));
  }
  close(fd);
  return -1;
}

int ps_outdir_lock_take(ps_outdir_lock *lk, const char *dir, ps_ctx *ctx) {
  char parent[1200];
  struct stat a, b;
  lk->fd = -1;
  lk->pid = 0;
  if (strlen(dir) > PS_DIR_MAX + 16) return too_long(dir, ctx);
  snprintf(lk->path, sizeof lk->path, "%s.lock", dir);
  snprintf(parent, sizeof parent, "%s", dir);
  char *slash = strrchr(parent, '/');
  if (slash && slash != parent) {
    *slash = '\0';
    PS_CHECK(ps_mkdir_p(parent, ctx));
  }
  /* a holder removes the file before it lets go: a lock taken on a file
   * that is no longer at the path is no lock; try again */
  for (int attempt = 0; attempt < 20; attempt++) {
    int busy, fd = lock_open(lk->path, dir, &busy, ctx);
    if (fd < 0) return PS_ERR_IO;
    if (fstat(fd, &a) == 0 && lstat(lk->path, &b) == 0 && a.st_dev == b.st_dev &&
        a.st_ino == b.st_ino) {
      char buf[32] = "";
      ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
      if (n > 0 && strncmp(buf, "peristatic lock", 15) != 0) {
        close(fd);
        return ps_error(ctx, PS_ERR_IO,
                        "%s is not a peristatic lock file (it would lock %s): move it away "
                        "or write elsewhere with -o",
                        lk->path, dir);
      }
      char line[64];
      int len = snprintf(line, sizeof line, "peristatic lock: pid %ld\n", (long)getpid());
      if (ftruncate(fd, 0) != 0 || pwrite(fd, line, (size_t)len, 0) != len) {
        close(fd);
        return ps_error(ctx, PS_ERR_IO, "%s: write failed", lk->path);
      }
      lk->fd = fd;
      lk->pid = (long)getpid();
      return PS_OK;
    }
    close(fd);
  }
  return ps_error(ctx, PS_ERR_IO, "%s: cannot lock (the file keeps changing)", lk->path);
}

void ps_outdir_lock_release(ps_outdir_lock *lk) {
  if (lk->fd < 0) return;
  if (lk->pid == (long)getpid()) unlink(lk->path);
  close(lk->fd);
  lk->fd = -1;
}
