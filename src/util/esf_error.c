/* esf_error.c — the single error-reporting path: a status code plus a message buffer
 * owned by the caller. No global state; nothing here prints or exits. Messages quote
 * input (a CSV field, an STL token, a YAML key), so control characters other than
 * newline and tab are shown as '?': a message never drives the terminal it is printed
 * on. */
#include "util/esf_error.h"

#include <stdio.h>
#include <string.h>

static void printable(char *s) {
  for (; *s; s++)
    if ((unsigned char)*s < 0x20 ? *s != '\n' && *s != '\t' : *s == 0x7f) *s = '?';
}

void esf_error_clear(esf_error *err) {
  if (!err) return;
  err->code = ESF_OK;
  err->msg[0] = '\0';
}

int esf_failv(esf_error *err, int code, const char *fmt, va_list ap) {
  if (err) {
    err->code = code;
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    printable(err->msg);
  }
  return code;
}

int esf_fail(esf_error *err, int code, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  esf_failv(err, code, fmt, ap);
  va_end(ap);
  return code;
}

int esf_error_prefix(esf_error *err, const char *fmt, ...) {
  if (!err) return ESF_EINTERNAL;
  char head[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(head, sizeof head, fmt, ap);
  va_end(ap);
  printable(head);
  size_t h = strlen(head), m = strlen(err->msg);
  if (h >= sizeof err->msg) h = sizeof err->msg - 1;
  if (h + m >= sizeof err->msg) m = sizeof err->msg - 1 - h;
  memmove(err->msg + h, err->msg, m);
  memcpy(err->msg, head, h);
  err->msg[h + m] = '\0';
  return err->code;
}

int esf_error_exit_status(int code) {
  switch (code) {
  case ESF_OK:
    return 0;
  case ESF_EINPUT:
  case ESF_EIO:
    return 2;
  default:
    return 1;
  }
}

const char *esf_error_name(int code) {
  switch (code) {
  case ESF_OK:
    return "ok";
  case ESF_EINPUT:
    return "bad input";
  case ESF_EIO:
    return "file error";
  case ESF_ENOMEM:
    return "out of memory";
  case ESF_ENUMERIC:
    return "numerical failure";
  default:
    return "internal error";
  }
}
