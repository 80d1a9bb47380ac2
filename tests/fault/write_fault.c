/* A write shim for tests/write_fault_test.sh (LD_PRELOAD): makes the k-th write of a tool to
 * a regular file fail, as a full disk or a failing device would, where the machine does not
 * allow mounting a small file system. The tools write files through stdio (atomic_file.h):
 * the shim counts fwrite and vfprintf calls on streams of regular files (not the terminal,
 * pipes or standard output) and fails call number C5_FAULT_AT (1, 2, ...) with errno
 * C5_FAULT_ERRNO (ENOSPC or EIO; default ENOSPC), and every later one; C5_FAULT_AT=fsync
 * fails every fsync instead. Only the process named C5_FAULT_PROG (default cube5) is faulted
 * and counted, not the programs it starts (gnuplot). Each call's number goes to stderr when
 * C5_FAULT_COUNT is set, so a test can size its loop. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static long calls;

static int fault_errno(void)
{
    const char *e = getenv("C5_FAULT_ERRNO");
    return e && !strcmp(e, "EIO") ? EIO : ENOSPC;
}

/* 1 when this write to stream f must fail. */
static int fails(FILE *f)
{
    const char *at = getenv("C5_FAULT_AT"), *prog = getenv("C5_FAULT_PROG");
    if (strcmp(program_invocation_short_name, prog ? prog : "cube5"))
        return 0;
    int fd = f ? fileno(f) : -1;
    struct stat st;
    if (fd <= 2 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))
        return 0;
    calls++;
    if (getenv("C5_FAULT_COUNT"))
        fprintf(stderr, "write_fault: call %ld\n", calls);
    if (!at || !strcmp(at, "fsync"))
        return 0;
    return calls >= atol(at);
}

size_t fwrite(const void *p, size_t size, size_t n, FILE *f)
{
    static size_t (*real)(const void *, size_t, size_t, FILE *);
    if (!real)
        real = (size_t (*)(const void *, size_t, size_t, FILE *))dlsym(RTLD_NEXT, "fwrite");
    if (fails(f)) {
        errno = fault_errno();
        return 0;
    }
    return real(p, size, n, f);
}

int vfprintf(FILE *f, const char *fmt, va_list ap)
{
    static int (*real)(FILE *, const char *, va_list);
    if (!real)
        real = (int (*)(FILE *, const char *, va_list))dlsym(RTLD_NEXT, "vfprintf");
    if (fails(f)) {
        errno = fault_errno();
        return -1;
    }
    return real(f, fmt, ap);
}

int fsync(int fd)
{
    static int (*real)(int);
    if (!real)
        real = (int (*)(int))dlsym(RTLD_NEXT, "fsync");
    const char *at = getenv("C5_FAULT_AT"), *prog = getenv("C5_FAULT_PROG");
    if (at && !strcmp(at, "fsync") && !strcmp(program_invocation_short_name, prog ? prog : "cube5")) {
        errno = fault_errno();
        return -1;
    }
    return real(fd);
}
