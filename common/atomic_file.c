/* Whole-or-nothing file writes (atomic_file.h). */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "atomic_file.h"

static void keep(c5_afile *a, int e)
{
    if (!a->err_no)
        a->err_no = e ? e : EIO;
}

void c5_afile_tmp_path(const char *path, const char *ext, char *out, size_t len)
{
    static unsigned seq;
    const char *slash = strrchr(path, '/');
    int dirlen = slash ? (int)(slash - path + 1) : 0;
    snprintf(out, len, "%.*s.%s.tmp-%ld-%u%s", dirlen, path, path + dirlen, (long)getpid(), seq++, ext ? ext : "");
}

int c5_output_target(const char *path, char *out, size_t len)
{
    char cur[PATH_MAX], next[PATH_MAX];
    snprintf(cur, sizeof cur, "%s", path);
    for (int depth = 0; depth < 16; depth++) {
        struct stat st;
        if (lstat(cur, &st) != 0 || !S_ISLNK(st.st_mode)) {
            snprintf(out, len, "%s", cur);
            return 0;
        }
        ssize_t n = readlink(cur, next, sizeof next - 1);
        if (n < 0)
            return -1;
        next[n] = 0;
        if (next[0] == '/') {
            snprintf(cur, sizeof cur, "%s", next);
        } else { /* relative to the link's folder */
            const char *slash = strrchr(cur, '/');
            int dirlen = slash ? (int)(slash - cur + 1) : 0;
            if ((size_t)dirlen + strlen(next) >= sizeof cur) {
                errno = ENAMETOOLONG;
                return -1;
            }
            memmove(cur + dirlen, next, strlen(next) + 1);
        }
    }
    errno = ELOOP;
    return -1;
}

int c5_output_check(const char *path, c5_err *err)
{
    if (!path || !*path)
        return c5_fail(err, "no output path given");
    char t[PATH_MAX], dir[PATH_MAX];
    if (c5_output_target(path, t, sizeof t) != 0)
        return c5_fail(err, "%s: cannot write: the link's target: %s", path, strerror(errno));
    struct stat st;
    if (stat(t, &st) == 0 && S_ISDIR(st.st_mode))
        return c5_fail(err, "%s: cannot write: %s", path, strerror(EISDIR));
    const char *slash = strrchr(t, '/');
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - t) + 1 : 2, slash ? t : "./");
    int e = 0;
    if (stat(dir, &st) != 0)
        e = errno;
    else if (!S_ISDIR(st.st_mode))
        e = ENOTDIR;
    else if (access(dir, W_OK | X_OK) != 0)
        e = errno;
    return e ? c5_fail(err, "%s: cannot write: folder %s: %s", path, dir, strerror(e)) : 0;
}

int c5_output_dir(const char *dir, c5_err *err)
{
    if (!dir || !*dir)
        return c5_fail(err, "no output folder given");
    char buf[PATH_MAX];
    if (strlen(dir) >= sizeof buf)
        return c5_fail(err, "%.200s...: output path too long", dir);
    strcpy(buf, dir);
    for (char *p = buf + 1;; p++) /* each missing level, as mkdir -p */
        if (*p == '/' || !*p) {
            char c = *p;
            *p = 0;
            if (mkdir(buf, 0777) != 0 && errno != EEXIST)
                return c5_fail(err, "%s: cannot create the folder %s: %s", dir, buf, strerror(errno));
            if (!(*p = c))
                break;
        }
    struct stat st;
    if (stat(dir, &st) != 0)
        return c5_fail(err, "%s: cannot write: %s", dir, strerror(errno));
    if (!S_ISDIR(st.st_mode))
        return c5_fail(err, "%s: cannot write: %s", dir, strerror(ENOTDIR));
    return 0;
}

int c5_afile_open(c5_afile *a, const char *path, c5_err *err)
{
    memset(a, 0, sizeof *a);
    a->mode = -1;
    if (!path || !*path)
        return c5_fail(err, "no output path given");
    if (strlen(path) >= sizeof a->shown)
        return c5_fail(err, "%.200s...: output path too long", path);
    snprintf(a->shown, sizeof a->shown, "%s", path);
    snprintf(a->path, sizeof a->path, "%s", path);
    if (c5_output_target(path, a->path, sizeof a->path) != 0) {
        a->err_no = errno;
        return c5_fail(err, "%s: cannot write: the link's target: %s", path, strerror(errno));
    }
    struct stat st;
    if (stat(a->path, &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            a->err_no = EISDIR;
            return c5_fail(err, "%s: cannot write: %s", path, strerror(EISDIR));
        }
        a->mode = (int)(st.st_mode & 07777);
    }
    c5_afile_tmp_path(a->path, NULL, a->tmp, sizeof a->tmp);
    int fd = open(a->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
        a->err_no = errno;
        a->tmp[0] = 0;
        return c5_fail(err, "%s: cannot write: %s", path, strerror(errno));
    }
    if ((a->mode >= 0 && fchmod(fd, (mode_t)a->mode) != 0) || !(a->f = fdopen(fd, "wb"))) {
        a->err_no = errno;
        close(fd);
        unlink(a->tmp);
        a->tmp[0] = 0;
        return c5_fail(err, "%s: cannot write: %s", path, strerror(a->err_no));
    }
    return 0;
}

void c5_afile_write(c5_afile *a, const void *buf, size_t n)
{
    if (a->err_no || !a->f || n == 0)
        return;
    errno = 0;
    if (fwrite(buf, 1, n, a->f) != n)
        keep(a, errno);
}

void c5_afile_printf(c5_afile *a, const char *fmt, ...)
{
    if (a->err_no || !a->f)
        return;
    va_list ap;
    va_start(ap, fmt);
    errno = 0;
    if (vfprintf(a->f, fmt, ap) < 0)
        keep(a, errno);
    va_end(ap);
}

void c5_afile_abort(c5_afile *a)
{
    if (a->f)
        fclose(a->f);
    a->f = NULL;
    if (a->tmp[0])
        unlink(a->tmp);
    a->tmp[0] = 0;
}

int c5_afile_commit(c5_afile *a, c5_err *err)
{
    if (!a->f)
        return c5_fail(err, "%s: cannot write: not open", a->shown);
    errno = 0;
    if (!a->err_no && fflush(a->f) != 0)
        keep(a, errno);
    if (!a->err_no && fsync(fileno(a->f)) != 0)
        keep(a, errno);
    errno = 0;
    if (fclose(a->f) != 0)
        keep(a, errno);
    a->f = NULL;
    if (!a->err_no && rename(a->tmp, a->path) != 0)
        keep(a, errno);
    if (a->err_no) {
        int e = a->err_no;
        c5_afile_abort(a);
        return c5_fail(err, "%s: cannot write: %s", a->shown, strerror(e));
    }
    a->tmp[0] = 0;
    return 0;
}

int c5_afile_put(const char *path, const void *buf, size_t n, c5_err *err)
{
    c5_afile a;
    if (c5_afile_open(&a, path, err) != 0)
        return -1;
    c5_afile_write(&a, buf, n);
    return c5_afile_commit(&a, err);
}
