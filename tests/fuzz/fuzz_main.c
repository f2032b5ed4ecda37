/* fuzz_main.c — libFuzzer's entry for every harness of the fuzz build (meson option
 * fuzz, clang): each input goes to the harness's esf_fuzz_one (fuzz.h); its status is
 * not a finding (bad input is what the readers must refuse), only a crash, a leak, a
 * sanitizer report or a timeout is.
 * Sanitizer defaults built into the harnesses: UBSan halts on its first report; ASan
 * detects leaks and lets an allocation above 64 MB fail (malloc returns NULL) instead
 * of aborting, as a machine short of memory would, so that a scene asking for millions
 * of particles meets the readers' out-of-memory paths (ESF_ENOMEM) within the
 * fuzzer's time and memory limits rather than counting as a crash. ASAN_OPTIONS and
 * UBSAN_OPTIONS still override them. */
#include "fuzz.h"

const char *__asan_default_options(void);
const char *__ubsan_default_options(void);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

const char *__asan_default_options(void) {
  return "detect_leaks=1:allocator_may_return_null=1:max_allocation_size_mb=64";
}

const char *__ubsan_default_options(void) { return "halt_on_error=1:print_stacktrace=1"; }

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  esf_error err;
  esf_error_clear(&err);
  esf_fuzz_one(data, size, &err);
  return 0;
}
