/* ps_checkpoint.h: checkpoint.bin, the state of a run after a complete
 * increment, from which `peristatic run --restart` continues as if the
 * run had never stopped (doc/peristatic.md RESTART). The format is in
 * checkpoint.c alone; what goes in is the layers' own lists of their
 * state (ps_state_list, ps_util.h: ps_solver_state_list,
 * ps_path_state_list) and the matrix of the solver's last factor
 * (ps_solver_factor_matrix), so this file knows no layer's struct.
 *
 * The file, in the byte order of the machine that wrote it (refused on
 * another):
 *   "PSCHKPT\n"                       magic (8 bytes)
 *   u32 format version (PS_CHECKPOINT_FORMAT), u32 0x01020304 (byte
 *   order), u32 algorithm version, u32 processes of a distributed run
 *   (0: one process, the whole model)
 *   u64 restart fingerprint (ps_case_restart_fingerprint), u64 those of
 *   its PS_RESTART_PARTS parts (ps_case_restart_part_fingerprints)
 *   f64 delta, i64 particles, arms, dofs, free dofs
 *   i64 increment, f64 wall seconds of the run up to it
 *   i32 factor (0 none, 1..4: ps_solver_factor_matrix), i32 rank (the
 *   process of a distributed run whose share it holds; 0 for one),
 *   i64 order n, i64 nonzeros nz, i64 p[n + 1], i64 i[nz], f64 x[nz]
 *   i64 number of items, then per item: u32 name length, the name, u64
 *   bytes, the bytes
 *   u64 FNV-1a hash of every byte before it (a truncated or damaged file
 *   is refused). */
#ifndef PS_CHECKPOINT_H
#define PS_CHECKPOINT_H

#include <stdint.h>

#include "ps_io.h"

/* the file's name inside a run's output folder: one process's; a
 * distributed run writes one file per process, checkpoint_pR.bin for
 * rank R (ps_checkpoint_name) */
#define PS_CHECKPOINT_FILE "checkpoint.bin"
/* the version of the layout above */
#define PS_CHECKPOINT_FORMAT 1

/* What identifies the run a checkpoint belongs to, and where it is. */
typedef struct ps_checkpoint_head {
  int algorithm;           /* ps_algorithm_version */
  uint64_t fingerprint;    /* ps_case_restart_fingerprint */
  uint64_t parts[PS_RESTART_PARTS]; /* ps_case_restart_part_fingerprints */
  double delta;            /* the run's elongation limit, m (inf: none) */
  int64_t particles, arms, dofs, free_dofs;
  int64_t increment;       /* the increments done (history.csv's rows) */
  double wall;             /* wall seconds of the run up to it */
  int processes;           /* a distributed run's processes, each of which
                              writes its share's state (0: one process,
                              the whole model) */
  int rank;                /* the process whose share it holds (0) */
} ps_checkpoint_head;

/* The file name of the checkpoint of process `rank` of a distributed run
 * on `processes` (checkpoint_pR.bin), or of a one-process run
 * (processes 0: PS_CHECKPOINT_FILE), into buf[len]. */
void ps_checkpoint_name(int processes, int rank, char *buf, size_t len);

/* Write dir/checkpoint.bin (the name of head's processes and rank:
 * ps_checkpoint_name) atomically (NAME.tmp, fsync, renamed, the folder
 * synced): head, the factor matrix A (which = its number, 0 and A NULL
 * for none) and the bytes of every item of l. Returns PS_OK or PS_ERR_IO
 * (nothing replaced). */
int ps_checkpoint_write(const char *dir, const ps_checkpoint_head *head, int which,
                        const ps_csc *A, const ps_state_list *l, ps_ctx *ctx);

/* A checkpoint read into memory. */
typedef struct ps_checkpoint {
  char path[1100];
  ps_checkpoint_head head;
  int which;               /* the factor's number (0: none) */
  ps_csc A;                /* its matrix (owned; n = 0 when none) */
  unsigned char *data;     /* the whole file (owned) */
  size_t size;
  size_t items;            /* offset of the item count */
} ps_checkpoint;

/* Read and check the file at path (magic, format, byte order, the hash:
 * a truncated or damaged file is refused) into *ck. Returns PS_OK,
 * PS_ERR_INPUT (no such file, not a checkpoint of this format, truncated
 * or corrupt; the message names the file), PS_ERR_IO (cannot read), or
 * PS_ERR_NOMEM. ck is freed on failure. */
int ps_checkpoint_read(const char *path, ps_checkpoint *ck, ps_ctx *ctx);

/* Compare ck's head with want's (algorithm version, fingerprint, delta,
 * processes and rank, sizes; not increment and wall). Returns PS_OK, or
 * PS_ERR_INPUT with a
 * message that names the file (and case) and says what differs. */
int ps_checkpoint_check(const ps_checkpoint *ck, const ps_checkpoint_head *want,
                        const char *case_file, ps_ctx *ctx);

/* Copy the items of ck into those of l: every name of l must be in the
 * file with the same size and every item of the file in l (else
 * PS_ERR_INPUT naming the item: the checkpoint is not of this build's
 * layout). Returns PS_OK or PS_ERR_INPUT. */
int ps_checkpoint_load_items(const ps_checkpoint *ck, const ps_state_list *l, ps_ctx *ctx);

void ps_checkpoint_free(ps_checkpoint *ck);

#endif
