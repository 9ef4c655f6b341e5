/* case_text.c: a case file's text before libyaml sees it. It is read
 * whole, at most PS_CASE_MAX_BYTES, and its nesting is bounded by
 * PS_CASE_MAX_DEPTH (libyaml's work grows with the square of the nesting
 * in Debian's 0.2.5), so that a hostile file is refused in milliseconds. */
#include "case_impl.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* case_impl.h */
int ps_case_read_text(const char *path, char **text, size_t *len, ps_ctx *ctx) {
  const size_t max = PS_CASE_MAX_BYTES;
  *text = NULL;
  *len = 0;
  FILE *f = fopen(path, "rb");
  if (!f) return ps_error(ctx, PS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  struct stat st;
  int regular = fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode);
  if (!regular && fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
    fclose(f);
    return ps_error(ctx, PS_ERR_IO, "%s: cannot open: %s", path, strerror(EISDIR));
  }
  if (regular && (uintmax_t)st.st_size > max) {
    fclose(f);
    return ps_error(ctx, PS_ERR_INPUT,
                    "%s: larger than 1 MiB (%jd bytes); case files are small YAML texts",
                    path, (intmax_t)st.st_size);
  }
  /* a regular file's size is known; pipes and devices grow the buffer
   * (to one byte past the limit, to tell "too large") */
  size_t cap = regular ? (size_t)st.st_size + 1 : 4096, n = 0;
  void *buf = ps_calloc(cap + 1, 1, ctx);
  int status = buf ? PS_OK : PS_ERR_NOMEM;
  while (status == PS_OK) {
    n += fread((char *)buf + n, 1, cap - n, f);
    if (n < cap || cap > max) break; /* end of file, an error, or too large */
    size_t grown = 2 * cap > max + 1 ? max + 1 : 2 * cap;
    status = ps_realloc(&buf, grown + 1, 1, ctx);
    cap = grown;
  }
  if (status == PS_OK && ferror(f))
    status = ps_error(ctx, PS_ERR_IO, "%s: read error: %s", path, strerror(errno));
  else if (status == PS_OK && n > max)
    status = ps_error(ctx, PS_ERR_INPUT,
                      "%s: larger than 1 MiB (more than %zu bytes); case files are small "
                      "YAML texts", path, max);
  fclose(f);
  if (status != PS_OK) {
    free(buf);
    return status;
  }
  ((char *)buf)[n] = '\0';
  *text = buf;
  *len = n;
  return PS_OK;
}

/* The nesting of a case file's text, measured before libyaml parses it:
 * block levels (a stack of indentation columns, with a sequence at its
 * parent key's column and each compact "- " on a line one more) plus
 * flow levels ('[' and '{' where a node may start, outside quoted
 * scalars, comments and block scalars). An approximation of YAML's
 * grammar, close enough to bound libyaml's work: it can count a level
 * more than libyaml builds (a plain scalar continued on a line that
 * starts with '['), never many fewer. */
typedef struct nest_scan {
  int flow;         /* open flow collections */
  char quote;       /* '\'' or '"' inside a quoted scalar, else 0 */
  int node_start;   /* a node may start at the next character */
  int block_scalar; /* >= 0: inside a block scalar ('|', '>') whose
                       header line is indented this much; -1: not */
  int n_level;      /* block levels: columns and kinds (1: sequence) */
  int col[PS_CASE_MAX_DEPTH + 2];
  char seq[PS_CASE_MAX_DEPTH + 2];
} nest_scan;

/* Push a block level; 0 when that makes the nesting too deep. */
static int nest_push(nest_scan *S, int col, int seq) {
  if (S->n_level + S->flow >= PS_CASE_MAX_DEPTH) return 0;
  S->col[S->n_level] = col;
  S->seq[S->n_level++] = (char)seq;
  return 1;
}

/* Is s[i] an indicator followed by a blank or the end of the line? */
static int indicator(const char *s, size_t i, size_t len, char c) {
  return s[i] == c && (i + 1 == len || s[i + 1] == ' ' || s[i + 1] == '\t');
}

/* Scan the characters s[i..len) of one line for quotes, comments and flow
 * brackets. Returns 0 when the nesting gets too deep. */
static int nest_chars(nest_scan *S, const char *s, size_t i, size_t len, int indent) {
  for (; i < len; i++) {
    char c = s[i];
    if (S->quote) {
      if (S->quote == '"' && c == '\\')
        i++;
      else if (c == '\'' && S->quote == '\'' && i + 1 < len && s[i + 1] == '\'')
        i++;
      else if (c == S->quote)
        S->quote = 0;
      continue;
    }
    if (c == ' ' || c == '\t') continue;
    if (c == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t')) break;
    if (S->node_start && (c == '\'' || c == '"')) {
      S->quote = c;
      S->node_start = 0;
    } else if ((c == '[' || c == '{') && (S->node_start || S->flow > 0)) {
      if (S->n_level + ++S->flow > PS_CASE_MAX_DEPTH) return 0;
      S->node_start = 1;
    } else if ((c == ']' || c == '}') && S->flow > 0) {
      S->flow--;
      S->node_start = 0;
    } else if (c == ',' && S->flow > 0) {
      S->node_start = 1;
    } else if (c == ':' && (indicator(s, i, len, ':') ||
                            (S->flow > 0 && i + 1 < len && strchr(",[]{}", s[i + 1])))) {
      S->node_start = 1;
    } else if (S->node_start && (indicator(s, i, len, '-') || indicator(s, i, len, '?'))) {
      /* a node may still start after "- " or "? " */
    } else if (S->node_start && (c == '&' || c == '!')) {
      while (i + 1 < len && s[i + 1] != ' ' && s[i + 1] != '\t') i++; /* anchor, tag */
    } else if (S->node_start && S->flow == 0 && (c == '|' || c == '>')) {
      S->block_scalar = indent; /* the rest of the line: indicators, comment */
      break;
    } else {
      S->node_start = 0;
    }
  }
  return 1;
}

/* One line (without its line break) of block context: the levels its
 * indentation closes and opens, then its characters. Returns 0 when the
 * nesting gets too deep. */
static int nest_block_line(nest_scan *S, const char *s, size_t len) {
  size_t i = 0;
  while (i < len && s[i] == ' ') i++;
  int indent = (int)i;
  if (i == len || s[i] == '#' || (i == 0 && s[0] == '%')) return 1; /* blank, comment,
                                                                   directive */
  if (i == 0 && len >= 3 && (!strncmp(s, "---", 3) || !strncmp(s, "...", 3)) &&
      (len == 3 || s[3] == ' ' || s[3] == '\t')) { /* a document starts or ends */
    S->n_level = 0;
    S->node_start = 1;
    return nest_chars(S, s, 3, len, 0);
  }
  int seq_line = indicator(s, i, len, '-');
  while (S->n_level > 0 && S->col[S->n_level - 1] > indent) S->n_level--;
  if (S->n_level > 0 && S->col[S->n_level - 1] == indent && S->seq[S->n_level - 1] &&
      !seq_line)
    S->n_level--; /* a sequence at its key's column ended */
  int top = S->n_level > 0 ? S->col[S->n_level - 1] : -1;
  if (top < indent || (top == indent && seq_line && !S->seq[S->n_level - 1]))
    if (!nest_push(S, indent, seq_line)) return 0;
  /* compact nesting on the line: "- - key: [..." */
  while (indicator(s, i, len, '-') || indicator(s, i, len, '?')) {
    i++;
    while (i < len && (s[i] == ' ' || s[i] == '\t')) i++;
    if (i == len || s[i] == '#') break;
    if (!nest_push(S, (int)i, indicator(s, i, len, '-'))) return 0;
  }
  S->node_start = 1;
  return nest_chars(S, s, i, len, indent);
}

/* case_impl.h */
int ps_case_check_nesting(const char *path, const char *text, size_t len, ps_ctx *ctx) {
  nest_scan S = {.block_scalar = -1};
  int line = 1;
  for (size_t at = 0; at < len; line++) {
    const char *nl = memchr(text + at, '\n', len - at);
    size_t end = nl ? (size_t)(nl - text) : len, n = end - at;
    const char *s = text + at;
    at = end + 1;
    if (n > 0 && s[n - 1] == '\r') n--;
    if (S.block_scalar >= 0) {
      size_t i = 0;
      while (i < n && s[i] == ' ') i++;
      if (i == n || (int)i > S.block_scalar) continue; /* the scalar's text */
      S.block_scalar = -1;
    }
    int ok = S.quote || S.flow > 0 ? nest_chars(&S, s, 0, n, 0) : nest_block_line(&S, s, n);
    if (!ok)
      return ps_error(ctx, PS_ERR_INPUT,
                      "%s:%d: nesting deeper than %d levels (lists and mappings); case "
                      "files nest a few", path, line, PS_CASE_MAX_DEPTH);
  }
  return PS_OK;
}
