/* fuzz_stl.c — fuzzes the STL reader (esf_stl_read, formats/stl.c), ASCII and binary.
 * How: the input is written to a scratch file and read as a scene's `mesh: {file: F}`
 * wall reads it.
 * What holds: ESF_OK with every triangle finite and not degenerate
 * (esf_stl_check_triangle), the binary flag matching the size rule (84 + 50 N bytes), and
 * an ASCII triangle's line within the file; or an error with a message and an empty
 * result. Nothing leaks. */
#include <stdlib.h>
#include <string.h>

#include "formats/stl.h"
#include "fuzz.h"

const char esf_fuzz_name[] = "stl";

int esf_fuzz_one(const uint8_t *data, size_t size, esf_error *err) {
  const char *path = esf_fuzz_write("input.stl", data, size);
  esf_stl m;
  int rc = esf_stl_read(path, &m, err);
  if (rc && (m.n || m.v || m.line)) abort(); /* a failed read leaves nothing */
  size_t lines = 1;
  for (size_t i = 0; i < size; i++) lines += data[i] == '\n';
  for (size_t t = 0; !rc && t < m.n; t++) {
    esf_error e2;
    if (esf_stl_check_triangle((const double(*)[3])m.v[t], &e2)) abort();
    if (m.binary ? m.line[t] != 0 : m.line[t] < 1 || (size_t)m.line[t] > lines) abort();
  }
  if (!rc && m.binary && (size < 84 || (size - 84) % 50 || (size - 84) / 50 != m.n))
    abort();
  esf_stl_release(&m);
  return rc;
}
