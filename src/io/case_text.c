/* case_text.c: a case file's text before libyaml loads it. It is read
 * whole, at most PS_CASE_MAX_BYTES, and its nesting is bounded by
 * PS_CASE_MAX_DEPTH and anchors refused, measured on libyaml's events
 * (its document loader's work grows with the square of the nesting and
 * of the anchors in Debian's 0.2.5), so that a hostile file is refused in
 * milliseconds. */
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

/* The nesting of a case file, measured by libyaml's own event parser
 * before its document loader runs: +1 for each sequence or mapping start,
 * -1 for each end, stopping as soon as the depth passes
 * PS_CASE_MAX_DEPTH (the event parser holds no more than the open levels,
 * so it stops early and cheaply; the loader is what grows with the square
 * of the nesting in Debian's 0.2.5). The same pass refuses anchors and
 * aliases: 0.2.5's loader registers anchors in quadratic time, and case
 * files need neither. A syntax or encoding error ends the pass quietly:
 * the loader reports it, with its line, having parsed no deeper. Reading
 * the events with libyaml's grammar (not a hand-written scan) leaves no
 * byte-order mark, line break (CR, NEL, LS, PS), encoding (UTF-16) or
 * scalar form that counts differently here and there. */
int ps_case_check_nesting(const char *path, const char *text, size_t len, ps_ctx *ctx) {
  yaml_parser_t pa;
  if (!yaml_parser_initialize(&pa))
    return ps_error(ctx, PS_ERR_NOMEM, "%s: cannot initialise the YAML parser", path);
  yaml_parser_set_input_string(&pa, (const unsigned char *)text, len);
  int depth = 0, status = PS_OK;
  for (;;) {
    yaml_event_t e;
    if (!yaml_parser_parse(&pa, &e)) {
      if (pa.error == YAML_MEMORY_ERROR)
        status = ps_error(ctx, PS_ERR_NOMEM, "%s: out of memory while parsing YAML", path);
      break; /* a syntax or encoding error: ps_yaml_open reports it */
    }
    yaml_event_type_t type = e.type;
    int line = (int)e.start_mark.line + 1;
    const yaml_char_t *anchor =
        type == YAML_SCALAR_EVENT           ? e.data.scalar.anchor
        : type == YAML_SEQUENCE_START_EVENT ? e.data.sequence_start.anchor
        : type == YAML_MAPPING_START_EVENT  ? e.data.mapping_start.anchor
                                            : NULL;
    yaml_event_delete(&e);
    if (anchor || type == YAML_ALIAS_EVENT) {
      status = ps_error(ctx, PS_ERR_INPUT,
                        "%s:%d: case files use no YAML anchors (&) or aliases (*)", path,
                        line);
      break;
    }
    if (type == YAML_SEQUENCE_START_EVENT || type == YAML_MAPPING_START_EVENT) {
      if (++depth > PS_CASE_MAX_DEPTH) {
        status = ps_error(ctx, PS_ERR_INPUT,
                          "%s:%d: nesting deeper than %d levels (lists and mappings); case "
                          "files nest a few",
                          path, line, PS_CASE_MAX_DEPTH);
        break;
      }
    } else if (type == YAML_SEQUENCE_END_EVENT || type == YAML_MAPPING_END_EVENT) {
      depth--;
    } else if (type == YAML_STREAM_END_EVENT) {
      break;
    }
  }
  yaml_parser_delete(&pa);
  return status;
}
