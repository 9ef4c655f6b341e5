/* vtu_read.c: the tests' reader of .vtu and .pvd files (vtu_read.h). */
#include "vtu_read.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail(char *why, size_t len, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(why, len, fmt, ap);
  va_end(ap);
  return -1;
}

/* the whole file, NUL-terminated (NULL when unreadable) */
static unsigned char *read_all(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  size_t cap = 1 << 16, n = 0, got;
  unsigned char *b = malloc(cap + 1);
  while (b && (got = fread(b + n, 1, cap - n, f)) > 0) {
    n += got;
    if (n == cap) {
      unsigned char *nb = realloc(b, 2 * cap + 1);
      if (!nb) {
        free(b);
        b = NULL;
      } else {
        b = nb;
        cap *= 2;
      }
    }
  }
  fclose(f);
  if (b) b[n] = '\0';
  *len = n;
  return b;
}

/* One XML tag: <name attrs>, <name attrs/> or </name>. */
typedef struct tag {
  char name[32];
  int closing, empty;
  const char *attr, *attr_end; /* the text between the name and '>' or "/>" */
} tag;

/* The next tag in [*p, end), *p moved past it; <?...?> and comments are
 * skipped, text between tags must be white space. 1: a tag, 0: none
 * left, -1: malformed. */
static int next_tag(const char **p, const char *end, tag *t) {
  const char *s = *p;
  for (;;) {
    while (s < end && isspace((unsigned char)*s)) s++;
    if (s == end) {
      *p = s;
      return 0;
    }
    if (*s != '<') return -1;
    if (end - s >= 2 && s[1] == '?') {
      const char *q = strstr(s, "?>");
      if (!q || q >= end) return -1;
      s = q + 2;
      continue;
    }
    if (end - s >= 4 && !strncmp(s, "<!--", 4)) {
      const char *q = strstr(s, "-->");
      if (!q || q >= end) return -1;
      s = q + 3;
      continue;
    }
    break;
  }
  s++;
  t->closing = *s == '/';
  if (t->closing) s++;
  size_t n = 0;
  while (s < end && (isalnum((unsigned char)*s) || *s == '_') && n + 1 < sizeof t->name)
    t->name[n++] = *s++;
  t->name[n] = '\0';
  if (n == 0) return -1;
  t->attr = s;
  int quote = 0;
  while (s < end && (quote || *s != '>')) {
    if (*s == '"') quote = !quote;
    s++;
  }
  if (s == end) return -1;
  t->empty = s[-1] == '/';
  t->attr_end = t->empty ? s - 1 : s;
  if (t->closing && (t->empty || t->attr_end != t->attr)) return -1;
  *p = s + 1;
  return 1;
}

/* The value of attribute name="..." of t into out; 1 found, 0 not. */
static int attr(const tag *t, const char *name, char *out, size_t len) {
  size_t nl = strlen(name);
  for (const char *s = t->attr; s + nl + 2 <= t->attr_end; s++) {
    if ((s == t->attr || isspace((unsigned char)s[-1])) && !strncmp(s, name, nl) &&
        s[nl] == '=' && s[nl + 1] == '"') {
      const char *v = s + nl + 2, *q = memchr(v, '"', (size_t)(t->attr_end - v));
      if (!q || (size_t)(q - v) >= len) return 0;
      memcpy(out, v, (size_t)(q - v));
      out[q - v] = '\0';
      return 1;
    }
  }
  return 0;
}

/* tags balanced: the open ones on stack (depth *n) */
static int push_pop(const tag *t, char (*stack)[32], int *n, char *why, size_t len) {
  if (t->closing) {
    if (*n == 0 || strcmp(stack[*n - 1], t->name))
      return fail(why, len, "</%s> closes <%s>", t->name, *n ? stack[*n - 1] : "nothing");
    (*n)--;
  } else if (!t->empty) {
    if (*n == 16) return fail(why, len, "tags nested too deep");
    snprintf(stack[(*n)++], 32, "%s", t->name);
  }
  return 0;
}

static uint64_t le64(const unsigned char *b) {
  uint64_t v = 0;
  for (int k = 7; k >= 0; k--) v = v << 8 | b[k];
  return v;
}

static int type_width(const char *type) {
  return !strcmp(type, "Float64") || !strcmp(type, "Int64") ? 8 : !strcmp(type, "UInt8") ? 1 : 0;
}

static const char *const sections[] = {"FieldData", "PointData", "CellData", "Points",
                                       "Cells", NULL};

/* The <DataArray/> tag t in section sec into f's next array. */
static int data_array(vtu_file *f, const tag *t, const char *sec, char *why, size_t len) {
  char v[64];
  if (!sec[0] || !t->empty) return fail(why, len, "DataArray outside a section or not empty");
  if (f->n_array == 64) return fail(why, len, "more than 64 arrays");
  vtu_array *a = &f->a[f->n_array++];
  memset(a, 0, sizeof *a);
  snprintf(a->section, sizeof a->section, "%s", sec);
  if (!attr(t, "Name", a->name, sizeof a->name) || !attr(t, "type", a->type, sizeof a->type) ||
      !type_width(a->type))
    return fail(why, len, "DataArray without Name or a known type");
  if (!attr(t, "format", v, sizeof v) || strcmp(v, "appended"))
    return fail(why, len, "%s: format is not appended", a->name);
  a->n_comp = attr(t, "NumberOfComponents", v, sizeof v) ? atoi(v) : 1;
  if (a->n_comp < 1) return fail(why, len, "%s: NumberOfComponents %s", a->name, v);
  if (!attr(t, "offset", v, sizeof v)) return fail(why, len, "%s: no offset", a->name);
  a->offset = strtoull(v, NULL, 10);
  /* tuples: NumberOfTuples in FieldData, else the section's size */
  long long tuples = -1;
  if (!strcmp(sec, "FieldData")) {
    if (!attr(t, "NumberOfTuples", v, sizeof v))
      return fail(why, len, "%s: FieldData without NumberOfTuples", a->name);
    tuples = atoll(v);
  } else if (!strcmp(sec, "PointData") || !strcmp(sec, "Points")) {
    tuples = f->n_point;
  } else if (!strcmp(sec, "CellData") || strcmp(a->name, "connectivity")) {
    tuples = f->n_cell;
  }
  a->n_bytes = (uint64_t)(tuples < 0 ? 0 : tuples) * (uint64_t)a->n_comp *
               (uint64_t)type_width(a->type); /* checked against the block later */
  if (tuples < 0) a->n_bytes = UINT64_MAX;   /* connectivity: any length */
  return 0;
}

/* The header: tags balanced up to <AppendedData, one Piece, the arrays. */
static int read_head(vtu_file *f, const char *s, const char *end, char *why, size_t len) {
  char stack[16][32], v[64], sec[32] = "";
  int depth = 0, pieces = 0, root = 0, r;
  tag t;
  while ((r = next_tag(&s, end, &t)) == 1) {
    if (push_pop(&t, stack, &depth, why, len)) return -1;
    if (!strcmp(t.name, "VTKFile") && !t.closing) {
      root = 1;
      if (!attr(&t, "type", v, sizeof v) || strcmp(v, "UnstructuredGrid"))
        return fail(why, len, "not type=\"UnstructuredGrid\"");
      if (!attr(&t, "byte_order", v, sizeof v) || strcmp(v, "LittleEndian"))
        return fail(why, len, "not byte_order=\"LittleEndian\"");
      if (!attr(&t, "header_type", v, sizeof v) || strcmp(v, "UInt64"))
        return fail(why, len, "not header_type=\"UInt64\"");
      if (!attr(&t, "version", v, sizeof v)) return fail(why, len, "no version");
    } else if (!strcmp(t.name, "Piece") && !t.closing) {
      pieces++;
      if (!attr(&t, "NumberOfPoints", v, sizeof v)) return fail(why, len, "no NumberOfPoints");
      f->n_point = atoll(v);
      if (!attr(&t, "NumberOfCells", v, sizeof v)) return fail(why, len, "no NumberOfCells");
      f->n_cell = atoll(v);
    } else if (!strcmp(t.name, "DataArray")) {
      if (data_array(f, &t, sec, why, len)) return -1;
    } else {
      for (int k = 0; sections[k]; k++)
        if (!strcmp(t.name, sections[k])) snprintf(sec, sizeof sec, "%s", t.closing ? "" : t.name);
    }
  }
  if (r < 0) return fail(why, len, "malformed XML before AppendedData");
  if (!root || depth != 1 || strcmp(stack[0], "VTKFile"))
    return fail(why, len, "tags before AppendedData do not leave just <VTKFile> open");
  if (pieces != 1) return fail(why, len, "%d Pieces", pieces);
  return 0;
}

int vtu_read(const char *path, vtu_file *f, char *why, size_t len) {
  memset(f, 0, sizeof *f);
  f->bytes = read_all(path, &f->len);
  if (!f->bytes) return fail(why, len, "%s: cannot read", path);
  const char *text = (const char *)f->bytes, *tag_s = "<AppendedData encoding=\"raw\">";
  const char *app = strstr(text, tag_s); /* the header has no NUL before it */
  if (!app) return fail(why, len, "no %s", tag_s);
  f->head_len = (size_t)(app - text);
  if (read_head(f, text, app, why, len)) return -1;
  const unsigned char *p = (const unsigned char *)app + strlen(tag_s), *end = f->bytes + f->len;
  while (p < end && isspace(*p)) p++;
  if (p == end || *p != '_') return fail(why, len, "no '_' opens the appended block");
  const unsigned char *base = p + 1;
  uint64_t at = 0;
  for (int k = 0; k < f->n_array; k++) {
    vtu_array *a = &f->a[k];
    if (a->offset != at) return fail(why, len, "%s: offset %llu, want %llu", a->name,
                                     (unsigned long long)a->offset, (unsigned long long)at);
    if ((uint64_t)(end - base) < at + 8) return fail(why, len, "%s: past the end", a->name);
    uint64_t n = le64(base + at);
    if ((uint64_t)(end - base) - at - 8 < n) return fail(why, len, "%s: data past the end", a->name);
    if (a->n_bytes != UINT64_MAX && n != a->n_bytes)
      return fail(why, len, "%s: %llu bytes, want %llu", a->name, (unsigned long long)n,
                  (unsigned long long)a->n_bytes);
    if (n % (uint64_t)(type_width(a->type) * a->n_comp))
      return fail(why, len, "%s: %llu bytes is not whole tuples", a->name, (unsigned long long)n);
    a->n_bytes = n;
    a->data = base + at + 8;
    at += 8 + n;
  }
  /* the closing tags, and nothing else */
  const char *s = (const char *)base + at, *e = (const char *)end;
  static const char *const closing[2] = {"AppendedData", "VTKFile"};
  tag t;
  for (int k = 0; k < 2; k++)
    if (next_tag(&s, e, &t) != 1 || !t.closing || strcmp(t.name, closing[k]))
      return fail(why, len, "the block is not followed by </%s>", closing[k]);
  if (next_tag(&s, e, &t) != 0) return fail(why, len, "more after </VTKFile>");
  return 0;
}

void vtu_free(vtu_file *f) {
  free(f->bytes);
  f->bytes = NULL;
}

const vtu_array *vtu_find(const vtu_file *f, const char *section, const char *name) {
  for (int k = 0; k < f->n_array; k++)
    if (!strcmp(f->a[k].section, section) && !strcmp(f->a[k].name, name)) return &f->a[k];
  return NULL;
}

size_t vtu_count(const vtu_array *a) { return (size_t)(a->n_bytes / (uint64_t)type_width(a->type)); }

double vtu_f64(const vtu_array *a, size_t i) {
  uint64_t w = le64(a->data + 8 * i);
  double v;
  memcpy(&v, &w, sizeof v);
  return v;
}

int64_t vtu_i64(const vtu_array *a, size_t i) {
  if (type_width(a->type) == 1) return a->data[i];
  return (int64_t)le64(a->data + 8 * i);
}

int pvd_read(const char *path, double *time, char (*file)[256], int max, char *why,
             size_t len) {
  size_t n_bytes;
  unsigned char *b = read_all(path, &n_bytes);
  if (!b) return fail(why, len, "%s: cannot read", path);
  const char *s = (const char *)b, *end = s + n_bytes;
  char stack[16][32], v[64];
  int depth = 0, n = 0, r, root = 0, bad = 0;
  tag t;
  while (!bad && (r = next_tag(&s, end, &t)) == 1) {
    if (push_pop(&t, stack, &depth, why, len)) bad = 1;
    else if (!strcmp(t.name, "VTKFile") && !t.closing)
      root = attr(&t, "type", v, sizeof v) && !strcmp(v, "Collection");
    else if (!strcmp(t.name, "DataSet") && depth == 2 && !strcmp(stack[1], "Collection")) {
      if (n == max || !attr(&t, "timestep", v, sizeof v) || !attr(&t, "file", file[n], 256))
        bad = fail(why, len, "DataSet %d without timestep or file (or more than %d)", n, max);
      else
        time[n++] = strtod(v, NULL);
    }
  }
  free(b);
  if (bad) return -1;
  if (r < 0 || depth != 0) return fail(why, len, "malformed XML");
  if (!root) return fail(why, len, "not a VTKFile of type Collection");
  return n;
}
