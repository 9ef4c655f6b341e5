/* checkpoint.c: checkpoint.bin written and read (the format: ps_checkpoint.h),
 * from and into the layers' lists of their state. */
#include "ps_checkpoint.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char ps_magic[8] = {'P', 'S', 'C', 'H', 'K', 'P', 'T', '\n'};
#define PS_BYTE_ORDER 0x01020304u


/* ---- writing ---- */

typedef struct writer {
  FILE *f;
  uint64_t h;
  int bad;
} writer;

static void put(writer *w, const void *data, size_t n) {
  if (!n || w->bad) return;
  ps_fnv1a(&w->h, data, n);
  if (fwrite(data, 1, n, w->f) != n) w->bad = 1;
}
static void put_u32(writer *w, uint32_t v) { put(w, &v, sizeof v); }
static void put_i32(writer *w, int32_t v) { put(w, &v, sizeof v); }
static void put_u64(writer *w, uint64_t v) { put(w, &v, sizeof v); }
static void put_i64(writer *w, int64_t v) { put(w, &v, sizeof v); }
static void put_f64(writer *w, double v) { put(w, &v, sizeof v); }

static void put_body(writer *w, const ps_checkpoint_head *hd, int which, const ps_csc *A,
                     const ps_state_list *l) {
  put(w, ps_magic, sizeof ps_magic);
  put_u32(w, PS_CHECKPOINT_FORMAT);
  put_u32(w, PS_BYTE_ORDER);
  put_u32(w, (uint32_t)hd->algorithm);
  put_u32(w, (uint32_t)hd->processes);
  put_u64(w, hd->fingerprint);
  for (int k = 0; k < PS_RESTART_PARTS; k++) put_u64(w, hd->parts[k]);
  put_f64(w, hd->delta);
  put_i64(w, hd->particles);
  put_i64(w, hd->arms);
  put_i64(w, hd->dofs);
  put_i64(w, hd->free_dofs);
  put_i64(w, hd->increment);
  put_f64(w, hd->wall);
  int64_t n = A ? A->n : 0, nz = A ? A->p[A->n] : 0;
  put_i32(w, A ? which : 0);
  put_i32(w, hd->rank);
  put_i64(w, n);
  put_i64(w, nz);
  if (A) {
    put(w, A->p, ((size_t)n + 1) * sizeof *A->p);
    put(w, A->i, (size_t)nz * sizeof *A->i);
    put(w, A->x, (size_t)nz * sizeof *A->x);
  }
  put_i64(w, l->n);
  for (int k = 0; k < l->n; k++) {
    const ps_state_item *it = &l->item[k];
    uint32_t len = (uint32_t)strlen(it->name);
    put_u32(w, len);
    put(w, it->name, len);
    put_u64(w, (uint64_t)it->bytes);
    put(w, it->data, it->bytes);
  }
}

/* fsync the folder dir (the rename into it durable); errors ignored:
 * some file systems refuse fsync on a folder */
static void sync_dir(const char *dir) {
  int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)fsync(fd);
  close(fd);
}

void ps_checkpoint_name(int processes, int rank, char *buf, size_t len) {
  if (processes > 0)
    snprintf(buf, len, "checkpoint_p%d.bin", rank);
  else
    snprintf(buf, len, "%s", PS_CHECKPOINT_FILE);
}

int ps_checkpoint_write(const char *dir, const ps_checkpoint_head *head, int which,
                        const ps_csc *A, const ps_state_list *l, ps_ctx *ctx) {
  char path[1200], name[64];
  ps_checkpoint_name(head->processes, head->rank, name, sizeof name);
  snprintf(path, sizeof path, "%s/%s", dir, name);
  ps_outfile o;
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  writer w = {o.f, PS_FNV_START, 0};
  put_body(&w, head, which, A, l);
  uint64_t h = w.h;
  /* the file's bytes on disk before the rename makes it the checkpoint */
  if (w.bad || fwrite(&h, sizeof h, 1, o.f) != 1 || fflush(o.f) != 0 ||
      fsync(fileno(o.f)) != 0) {
    int e = errno;
    ps_outfile_abort(&o);
    return ps_error(ctx, PS_ERR_IO, "%s: write failed: %s", o.tmp, strerror(e));
  }
  PS_CHECK(ps_outfile_commit(&o, ctx));
  sync_dir(dir);
  return PS_OK;
}

/* ---- reading ---- */

typedef struct reader {
  const unsigned char *d;
  size_t size, at;
  int short_read;
} reader;

static void get(reader *r, void *out, size_t n) {
  if (!n) return;
  if (r->short_read || n > r->size - r->at) {
    r->short_read = 1;
    memset(out, 0, n);
    return;
  }
  memcpy(out, r->d + r->at, n);
  r->at += n;
}
static uint32_t get_u32(reader *r) {
  uint32_t v;
  get(r, &v, sizeof v);
  return v;
}
static int32_t get_i32(reader *r) {
  int32_t v;
  get(r, &v, sizeof v);
  return v;
}
static uint64_t get_u64(reader *r) {
  uint64_t v;
  get(r, &v, sizeof v);
  return v;
}
static int64_t get_i64(reader *r) {
  int64_t v;
  get(r, &v, sizeof v);
  return v;
}
static double get_f64(reader *r) {
  double v;
  get(r, &v, sizeof v);
  return v;
}

void ps_checkpoint_free(ps_checkpoint *ck) {
  free(ck->data);
  free(ck->A.p);
  free(ck->A.i);
  free(ck->A.x);
  memset(ck, 0, sizeof *ck);
}

/* PS_ERR_INPUT: the file is damaged */
static int corrupt(const ps_checkpoint *ck, const char *what, ps_ctx *ctx) {
  return ps_error(ctx, PS_ERR_INPUT,
                  "%s is truncated or corrupt (%s): it cannot be restarted from; restart from "
                  "another checkpoint or run the case afresh",
                  ck->path, what);
}

/* the whole file into ck->data */
static int slurp(ps_checkpoint *ck, ps_ctx *ctx) {
  struct stat sb;
  FILE *f = fopen(ck->path, "rb");
  if (!f)
    return ps_error(ctx, errno == ENOENT ? PS_ERR_INPUT : PS_ERR_IO,
                    "%s: cannot read: %s (--restart needs the output folder of a run that "
                    "wrote a checkpoint)", ck->path, strerror(errno));
  if (fstat(fileno(f), &sb) != 0 || !S_ISREG(sb.st_mode)) {
    fclose(f);
    return ps_error(ctx, PS_ERR_IO, "%s: not a regular file", ck->path);
  }
  ck->size = (size_t)sb.st_size;
  ck->data = ps_calloc(ck->size ? ck->size : 1, 1, ctx);
  if (!ck->data) {
    fclose(f);
    return PS_ERR_NOMEM;
  }
  size_t got = fread(ck->data, 1, ck->size, f);
  int bad = ferror(f);
  fclose(f);
  if (bad || got != ck->size) return ps_error(ctx, PS_ERR_IO, "%s: read failed", ck->path);
  return PS_OK;
}

int ps_checkpoint_read(const char *path, ps_checkpoint *ck, ps_ctx *ctx) {
  memset(ck, 0, sizeof *ck);
  snprintf(ck->path, sizeof ck->path, "%s", path);
  int status = slurp(ck, ctx);
  if (status < 0) goto fail;
  reader r = {ck->data, ck->size, 0, 0};
  char magic[8];
  if (ck->size < sizeof magic) {
    status = corrupt(ck, ck->size ? "shorter than its header" : "empty", ctx);
    goto fail;
  }
  get(&r, magic, sizeof magic);
  if (r.short_read || memcmp(magic, ps_magic, sizeof magic) != 0) {
    status = ps_error(ctx, PS_ERR_INPUT, "%s is not a peristatic checkpoint", path);
    goto fail;
  }
  uint32_t format = get_u32(&r), order = get_u32(&r);
  if (r.short_read) {
    status = corrupt(ck, "it ends in its header", ctx);
    goto fail;
  }
  if (order != PS_BYTE_ORDER) {
    status = ps_error(ctx, PS_ERR_INPUT, "%s was written on a machine of another byte order",
                      path);
    goto fail;
  }
  if (format != PS_CHECKPOINT_FORMAT) {
    status = ps_error(ctx, PS_ERR_INPUT, "%s has checkpoint format %u, this peristatic reads "
                      "format %d: run the case afresh", path, format, PS_CHECKPOINT_FORMAT);
    goto fail;
  }
  if (ck->size < r.at + sizeof(uint64_t)) {
    status = corrupt(ck, "it ends in its header", ctx);
    goto fail;
  }
  uint64_t h = PS_FNV_START, stored;
  ps_fnv1a(&h, ck->data, ck->size - sizeof stored);
  memcpy(&stored, ck->data + ck->size - sizeof stored, sizeof stored);
  if (h != stored) {
    status = corrupt(ck, "its hash does not match its contents", ctx);
    goto fail;
  }
  r.size = ck->size - sizeof stored;
  ps_checkpoint_head *hd = &ck->head;
  hd->algorithm = (int)get_u32(&r);
  hd->processes = (int)get_u32(&r);
  hd->fingerprint = get_u64(&r);
  for (int k = 0; k < PS_RESTART_PARTS; k++) hd->parts[k] = get_u64(&r);
  hd->delta = get_f64(&r);
  hd->particles = get_i64(&r);
  hd->arms = get_i64(&r);
  hd->dofs = get_i64(&r);
  hd->free_dofs = get_i64(&r);
  hd->increment = get_i64(&r);
  hd->wall = get_f64(&r);
  ck->which = get_i32(&r);
  hd->rank = get_i32(&r);
  int64_t n = get_i64(&r), nz = get_i64(&r);
  size_t left = r.size - r.at;
  if (r.short_read || n < 0 || nz < 0 || (size_t)n >= left / 8 || (size_t)nz > left / 16) {
    status = corrupt(ck, "its factor's sizes do not fit the file", ctx);
    goto fail;
  }
  if (n > 0) {
    ck->A.p = ps_calloc((size_t)n + 1, sizeof *ck->A.p, ctx);
    ck->A.i = ps_calloc((size_t)nz + 1, sizeof *ck->A.i, ctx);
    ck->A.x = ps_calloc((size_t)nz + 1, sizeof *ck->A.x, ctx);
    if (!ck->A.p || !ck->A.i || !ck->A.x) {
      status = PS_ERR_NOMEM;
      goto fail;
    }
    get(&r, ck->A.p, ((size_t)n + 1) * sizeof *ck->A.p);
    get(&r, ck->A.i, (size_t)nz * sizeof *ck->A.i);
    get(&r, ck->A.x, (size_t)nz * sizeof *ck->A.x);
    ck->A.n = n;
    int ok = !r.short_read && ck->A.p[0] == 0 && ck->A.p[n] == nz;
    for (int64_t j = 0; ok && j < n; j++) ok = ck->A.p[j] <= ck->A.p[j + 1];
    for (int64_t k = 0; ok && k < nz; k++) ok = ck->A.i[k] >= 0 && ck->A.i[k] < n;
    if (!ok) {
      status = corrupt(ck, "its factor matrix is not a matrix", ctx);
      goto fail;
    }
  }
  ck->items = r.at;
  /* walk the items once: each must fit */
  int64_t count = get_i64(&r);
  for (int64_t k = 0; k < count && !r.short_read; k++) {
    uint32_t len = get_u32(&r);
    if (len >= PS_STATE_NAME || len > r.size - r.at) {
      r.short_read = 1;
      break;
    }
    r.at += len;
    uint64_t bytes = get_u64(&r);
    if (bytes > r.size - r.at) r.short_read = 1;
    else r.at += (size_t)bytes;
  }
  if (r.short_read || count < 0 || r.at != r.size) {
    status = corrupt(ck, "its items do not fit the file", ctx);
    goto fail;
  }
  return PS_OK;
fail:
  ps_checkpoint_free(ck);
  return status;
}

int ps_checkpoint_check(const ps_checkpoint *ck, const ps_checkpoint_head *want,
                        const char *case_file, ps_ctx *ctx) {
  const ps_checkpoint_head *h = &ck->head;
  if (h->algorithm != want->algorithm)
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s was written by algorithm version %d, this peristatic computes version "
                    "%d (doc/algorithm-versions.md): a restart would not repeat that run; run "
                    "%s afresh",
                    ck->path, h->algorithm, want->algorithm, case_file);
  if (h->fingerprint != want->fingerprint) {
    char parts[160] = "";
    int n = 0, m = 0;
    for (int k = 0; k < PS_RESTART_PARTS; k++) n += h->parts[k] != want->parts[k];
    for (int k = 0; k < PS_RESTART_PARTS; k++)
      if (h->parts[k] != want->parts[k]) {
        m++;
        snprintf(parts + strlen(parts), sizeof parts - strlen(parts), "%s%s",
                 m == 1 ? "" : m == n ? " and " : ", ", ps_case_restart_parts[k]);
      }
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s was written for another case: its %s settings differ from %s's "
                    "(restart fingerprint %016llx, %s's %016llx). Every setting that "
                    "determines the result must be the same to restart (path.max_increments "
                    "may differ); run %s afresh or restart from its own output folder",
                    ck->path, n ? parts : "geometry, material, loading, solver or path",
                    case_file, (unsigned long long)h->fingerprint, case_file,
                    (unsigned long long)want->fingerprint, case_file);
  }
  if (h->processes != want->processes || h->rank != want->rank) {
    char had[64], has[64];
    if (h->processes > 0)
      snprintf(had, sizeof had, "process %d of a distributed run on %d", h->rank,
               h->processes);
    else
      snprintf(had, sizeof had, "a run holding the whole model");
    if (want->processes > 0)
      snprintf(has, sizeof has, "is distributed over %d processes", want->processes);
    else
      snprintf(has, sizeof has, "holds the whole model");
    return ps_error(ctx, PS_ERR_INPUT, "%s is the checkpoint of %s, and this run %s: restart "
                    "it with as many processes and the same solver.layout", ck->path, had,
                    has);
  }
  const char *what = NULL;
  long long a = 0, b = 0;
  if (h->particles != want->particles) what = "particles", a = h->particles, b = want->particles;
  else if (h->arms != want->arms) what = "arms", a = h->arms, b = want->arms;
  else if (h->dofs != want->dofs) what = "dofs", a = h->dofs, b = want->dofs;
  else if (h->free_dofs != want->free_dofs)
    what = "free dofs", a = h->free_dofs, b = want->free_dofs;
  if (what)
    return ps_error(ctx, PS_ERR_INPUT, "%s holds %lld %s, %s has %lld: not this case's "
                    "checkpoint", ck->path, a, what, case_file, b);
  if (!(h->delta == want->delta || (isinf(h->delta) && isinf(want->delta))))
    return ps_error(ctx, PS_ERR_INPUT, "%s was written with delta %.17g m, %s has %.17g m: not "
                    "this case's checkpoint", ck->path, h->delta, case_file, want->delta);
  return PS_OK;
}

int ps_checkpoint_load_items(const ps_checkpoint *ck, const ps_state_list *l, ps_ctx *ctx) {
  reader r = {ck->data, ck->size - sizeof(uint64_t), ck->items, 0};
  int64_t count = get_i64(&r);
  unsigned char *seen = ps_calloc((size_t)l->n + 1, 1, ctx);
  if (!seen) return PS_ERR_NOMEM;
  int status = PS_OK;
  for (int64_t k = 0; k < count && status == PS_OK; k++) {
    char name[PS_STATE_NAME] = "";
    uint32_t len = get_u32(&r);
    get(&r, name, len); /* checked by ps_checkpoint_read: len < PS_STATE_NAME */
    uint64_t bytes = get_u64(&r);
    int at = -1;
    for (int j = 0; j < l->n && at < 0; j++)
      if (!strcmp(l->item[j].name, name)) at = j;
    if (at < 0 || seen[at]) {
      status = ps_error(ctx, PS_ERR_INPUT, "%s holds state '%s' that this run %s: written by "
                        "another build or for other settings", ck->path, name,
                        at < 0 ? "does not have" : "has only once");
      break;
    }
    if (bytes != l->item[at].bytes) {
      status = ps_error(ctx, PS_ERR_INPUT, "%s holds %llu bytes of state '%s', this run has "
                        "%zu: written by another build or for other settings", ck->path,
                        (unsigned long long)bytes, name, l->item[at].bytes);
      break;
    }
    get(&r, l->item[at].data, (size_t)bytes);
    seen[at] = 1;
  }
  for (int j = 0; j < l->n && status == PS_OK; j++)
    if (!seen[j])
      status = ps_error(ctx, PS_ERR_INPUT, "%s lacks state '%s' of this run: written by "
                        "another build or for other settings", ck->path, l->item[j].name);
  free(seen);
  return status;
}
