/* fuzz_util.c — the fuzz harnesses' scratch files (fuzz.h): one directory per process
 * under $TMPDIR (default /tmp), made on first use and emptied and removed at exit, so
 * that readers that take a path get the fuzzer's bytes as a file. Not thread-safe (a
 * harness runs one input at a time). */
#define _GNU_SOURCE
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz.h"

static char scratch[512];
static char path_buf[8][1024]; /* a few paths may be live at once */
static int path_next;

static void remove_scratch(void) {
  DIR *d = scratch[0] ? opendir(scratch) : NULL;
  if (!d) return;
  struct dirent *e;
  char p[1024];
  while ((e = readdir(d))) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    snprintf(p, sizeof p, "%s/%s", scratch, e->d_name);
    unlink(p);
  }
  closedir(d);
  rmdir(scratch);
}

const char *esf_fuzz_path(const char *name) {
  if (!scratch[0]) {
    const char *tmp = getenv("TMPDIR");
    snprintf(scratch, sizeof scratch, "%s/esf-fuzz-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(scratch)) {
      perror("esf-fuzz: mkdtemp");
      abort();
    }
    atexit(remove_scratch);
  }
  char *p = path_buf[path_next++ % 8];
  snprintf(p, sizeof path_buf[0], "%s/%s", scratch, name);
  return p;
}

const char *esf_fuzz_write(const char *name, const uint8_t *data, size_t size) {
  const char *p = esf_fuzz_path(name);
  FILE *f = fopen(p, "wb");
  if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f) != 0) {
    perror(p);
    abort(); /* the harness itself failed: never a finding of the reader */
  }
  return p;
}

char *esf_fuzz_read(const char *path, size_t *size) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  size_t cap = 4096, n = 0, got;
  char *buf = malloc(cap + 1);
  while (buf && (got = fread(buf + n, 1, cap - n, f)) > 0) {
    n += got;
    if (n == cap) {
      char *nb = realloc(buf, 2 * cap + 1);
      if (!nb) {
        free(buf);
        buf = NULL;
        break;
      }
      buf = nb;
      cap *= 2;
    }
  }
  fclose(f);
  if (buf) buf[n] = '\0';
  *size = n;
  return buf;
}
