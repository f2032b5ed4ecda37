/* esf_error.h — status codes and the one error-reporting path of esfera.
 *
 * Every library function that can fail returns an int status: ESF_OK (0) on success,
 * a negative ESF_E* code on failure, and writes a human-readable message into the
 * esf_error it was handed (which may be NULL when the caller does not care).
 * The program maps codes to exit statuses with esf_error_exit_status(). */
#ifndef ESF_ERROR_H
#define ESF_ERROR_H

#include <stdarg.h>

enum {
  ESF_OK = 0,
  ESF_EINPUT = -1,   /* bad input: scene, option, file contents (exit 2) */
  ESF_EIO = -2,      /* a file could not be read or written (exit 2) */
  ESF_ENOMEM = -3,   /* out of memory (exit 1) */
  ESF_ENUMERIC = -4, /* the simulation failed: instability, non-finite state (exit 1) */
  ESF_EINTERNAL = -5 /* a bug: an invariant of esfera itself broke (exit 1) */
};

#define ESF_ERROR_MSG_MAX 2048

typedef struct esf_error {
  int code;                    /* the last status set, ESF_OK when none */
  char msg[ESF_ERROR_MSG_MAX]; /* the message, "" when none */
} esf_error;

/* Clears err (no-op for NULL). */
void esf_error_clear(esf_error *err);

/* Sets err's code and message (printf format) and returns code, so that callers can
 * write `return esf_fail(err, ESF_EINPUT, "...", ...);`. err may be NULL. */
int esf_fail(esf_error *err, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
int esf_failv(esf_error *err, int code, const char *fmt, va_list ap);

/* Prepends context ("while reading X: ") to an existing message; returns err->code. */
int esf_error_prefix(esf_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* The process exit status for a code: 0 ok, 2 bad input or file, 1 otherwise. */
int esf_error_exit_status(int code);

/* A short name for a code ("bad input", "numerical failure", ...). */
const char *esf_error_name(int code);

#endif
