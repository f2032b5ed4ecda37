/* atomic_file.c — durable whole-file replacement (atomic_file.h).
 *
 * Algorithm: open PATH.tmp (O_CREAT | O_TRUNC), write everything (short writes
 * resumed, EINTR retried), fsync, close (a close error counts: NFS reports there),
 * rename(PATH.tmp, PATH), fsync the directory. rename(2) within one directory is atomic
 * on POSIX file systems, so readers and a later resume see the old or the new file.
 * Errors remove PATH.tmp (best effort) and keep errno's text in the message. EFBIG
 * from RLIMIT_FSIZE needs SIGXFSZ ignored to be seen as an error here; the program
 * ignores it (main.c). */
#include "util/atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int write_all(int fd, const unsigned char *p, size_t len) {
  while (len > 0) {
    ssize_t w = write(fd, p, len);
    if (w < 0) {
      if (errno == EINTR) continue;
      return -1;
    }
    if (w == 0) {
      errno = ENOSPC;
      return -1;
    }
    p += w;
    len -= (size_t)w;
  }
  return 0;
}

int esf_fsync_parent(const char *path, esf_error *err) {
  char dir[1200];
  const char *slash = strrchr(path, '/');
  if (!slash)
    snprintf(dir, sizeof dir, ".");
  else if (slash == path)
    snprintf(dir, sizeof dir, "/");
  else
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
  int fd = open(dir, O_RDONLY | O_DIRECTORY);
  if (fd < 0)
    return esf_fail(err, ESF_EIO, "cannot open directory '%s': %s", dir, strerror(errno));
  int rc = fsync(fd) == 0 || errno == EINVAL ? ESF_OK : -1;
  int e = errno;
  close(fd);
  if (rc)
    return esf_fail(err, ESF_EIO, "cannot sync directory '%s': %s", dir, strerror(e));
  return ESF_OK;
}

int esf_fsync_path(const char *path, esf_error *err) {
  int fd = open(path, O_RDONLY);
  if (fd < 0)
    return esf_fail(err, ESF_EIO, "cannot open '%s': %s", path, strerror(errno));
  int bad = fsync(fd) != 0;
  int e = errno;
  close(fd);
  if (bad) return esf_fail(err, ESF_EIO, "cannot sync '%s': %s", path, strerror(e));
  return ESF_OK;
}

int esf_atomic_write(const char *path, const void *data, size_t len, esf_error *err) {
  char tmp[1200];
  if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
    return esf_fail(err, ESF_EIO, "path too long: %s", path);
  int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (fd < 0)
    return esf_fail(err, ESF_EIO, "cannot write '%s': %s", tmp, strerror(errno));
  int bad = write_all(fd, data, len) != 0 || fsync(fd) != 0;
  int e = errno;
  if (close(fd) != 0 && !bad) {
    bad = 1;
    e = errno;
  }
  if (!bad && rename(tmp, path) != 0) {
    bad = 1;
    e = errno;
  }
  if (bad) {
    unlink(tmp);
    return esf_fail(err, ESF_EIO, "cannot write '%s': %s (the previous file is intact)",
                    path, strerror(e));
  }
  return esf_fsync_parent(path, err);
}

int esf_read_file(const char *path, char **data, size_t *len, esf_error *err) {
  *data = NULL;
  *len = 0;
  int fd = open(path, O_RDONLY);
  if (fd < 0)
    return esf_fail(err, ESF_EIO, "cannot open '%s': %s", path, strerror(errno));
  struct stat sb;
  if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
    close(fd);
    return esf_fail(err, ESF_EIO, "'%s' is not a regular file", path);
  }
  size_t n = (size_t)sb.st_size, got = 0;
  char *buf = malloc(n + 1);
  if (!buf) {
    close(fd);
    return esf_fail(err, ESF_ENOMEM, "out of memory reading '%s'", path);
  }
  while (got < n) {
    ssize_t r = read(fd, buf + got, n - got);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    got += (size_t)r;
  }
  int e = errno;
  close(fd);
  if (got != n) {
    free(buf);
    return esf_fail(err, ESF_EIO, "cannot read '%s': %s", path,
                    got < n ? "file shrank while reading" : strerror(e));
  }
  buf[n] = '\0';
  *data = buf;
  *len = n;
  return ESF_OK;
}
