/* vtu_read.h: a minimal reader of the VTK XML files peristatic writes,
 * written from the file format alone (not from src/io/vtu.c), for the
 * tests: an UnstructuredGrid .vtu with every DataArray in one raw
 * appended block (little-endian, UInt64 byte counts), checked strictly,
 * and the DataSet entries of a .pvd collection. */
#ifndef VTU_READ_H
#define VTU_READ_H

#include <stddef.h>
#include <stdint.h>

typedef struct vtu_array {
  char section[16];      /* FieldData, PointData, CellData, Points or Cells */
  char name[64];
  char type[16];         /* Float64, Int64 or UInt8 */
  int n_comp;            /* NumberOfComponents (1 when absent) */
  uint64_t offset;       /* the offset attribute */
  uint64_t n_bytes;      /* the byte count at offset in the block */
  const unsigned char *data; /* the n_bytes values, inside the file's bytes */
} vtu_array;

typedef struct vtu_file {
  unsigned char *bytes;  /* the whole file */
  size_t len;
  size_t head_len;       /* bytes before <AppendedData */
  long long n_point, n_cell;
  int n_array;
  vtu_array a[64];
} vtu_file;

/* Read path into f and check it: the header's attributes
 * (UnstructuredGrid, version, LittleEndian, UInt64), balanced tags, one
 * Piece, every DataArray appended with a known type, a byte count that
 * fits its section's size (points, cells or NumberOfTuples) x components,
 * the entries back to back from offset 0 in the order of the header, and
 * nothing after the last one but the closing tags. Returns 0, or -1 with
 * the reason in why. */
int vtu_read(const char *path, vtu_file *f, char *why, size_t len);
void vtu_free(vtu_file *f);

/* The array of that section and name, or NULL. */
const vtu_array *vtu_find(const vtu_file *f, const char *section, const char *name);
/* Entry i of an array (little-endian bytes to the host's numbers). */
double vtu_f64(const vtu_array *a, size_t i);
int64_t vtu_i64(const vtu_array *a, size_t i);
/* the number of entries (values, not tuples) */
size_t vtu_count(const vtu_array *a);

/* The entries of a .pvd: at most max (timestep, file) pairs in order.
 * Returns their number, or -1 with the reason in why (unreadable, not a
 * Collection, unbalanced tags, an entry without timestep or file). */
int pvd_read(const char *path, double *time, char (*file)[256], int max, char *why,
             size_t len);

#endif
