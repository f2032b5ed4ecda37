/* replay.c — a fuzz harness without libFuzzer, for every build: runs each file given
 * through the harness's esf_fuzz_one (fuzz.h) and prints the exit status the esfera
 * program would give for it (esf_error_exit_status) with the message.
 *   replay_NAME [--expect STATUS] [--ascii] FILE...
 * With --expect, exits 1 unless every file gives STATUS and, for a non-zero STATUS, a
 * message; with --ascii, also unless every message is printable ASCII (and newlines).
 * The regression tests (tests/fuzz/meson.build) replay the inputs the fuzzers found
 * this way. A crash or a sanitizer report ends the program as it would the fuzzer. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"

int main(int argc, char **argv) {
  int expect = -1, ascii = 0, k = 1, bad = 0, files = 0;
  if (k + 1 < argc && strcmp(argv[k], "--expect") == 0) {
    expect = atoi(argv[k + 1]);
    k += 2;
  }
  if (k < argc && strcmp(argv[k], "--ascii") == 0) ascii = 1, k++;
  for (; k < argc; k++) {
    size_t n = 0;
    char *buf = esf_fuzz_read(argv[k], &n);
    if (!buf) {
      fprintf(stderr, "replay_%s: cannot read %s\n", esf_fuzz_name, argv[k]);
      return 2;
    }
    esf_error err;
    esf_error_clear(&err);
    int rc = esf_fuzz_one((const uint8_t *)buf, n, &err);
    free(buf);
    int status = esf_error_exit_status(rc);
    int ok = expect < 0 || (status == expect && (status == 0 || err.msg[0]));
    for (const char *c = err.msg; ascii && *c; c++)
      ok = ok && ((*c >= 0x20 && *c < 0x7f) || *c == '\n');
    printf("%s %s: exit %d%s%s\n", ok ? "ok" : "FAIL", argv[k], status, rc ? ": " : "",
           rc ? err.msg : "");
    bad += !ok;
    files++;
  }
  printf("replay_%s: %d files, %d failed\n", esf_fuzz_name, files, bad);
  return bad ? 1 : 0;
}
