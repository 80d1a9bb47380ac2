#define _GNU_SOURCE
#include "harness.h"

#include <ftw.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_TESTS 1024

static struct {
    const char *name;
    c5t_fn fn;
} tests[MAX_TESTS];
static int n_tests;
static int failed_now;
static char tmpdir[512];
static char paths[8][1024];

void c5t_register(const char *name, c5t_fn fn)
{
    if (n_tests == MAX_TESTS) {
        fprintf(stderr, "harness: too many tests\n");
        exit(2);
    }
    tests[n_tests].name = name;
    tests[n_tests].fn = fn;
    n_tests++;
}

void c5t_failf(const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    printf("    %s:%d: ", file, line);
    vprintf(fmt, ap);
    printf("\n");
    va_end(ap);
    failed_now = 1;
}

int c5t_failed_now(void) { return failed_now; }

static int rm_entry(const char *p, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb, (void)flag, (void)ftw;
    return remove(p);
}

static void clean_tmpdir(void)
{
    if (tmpdir[0])
        nftw(tmpdir, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
    tmpdir[0] = 0;
}

const char *c5t_tmpdir(void)
{
    if (!tmpdir[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(tmpdir, sizeof tmpdir, "%s/c5t-XXXXXX", base && *base ? base : "/tmp");
        if (!mkdtemp(tmpdir)) {
            perror("mkdtemp");
            exit(2);
        }
    }
    return tmpdir;
}

const char *c5t_path(int slot, const char *name)
{
    snprintf(paths[slot & 7], sizeof paths[0], "%s/%s", c5t_tmpdir(), name);
    return paths[slot & 7];
}

/* Usage: unit [SUBSTRING...]: run the cases whose names contain any of the substrings. */
int main(int argc, char **argv)
{
    int passed = 0, failed = 0;
    setvbuf(stdout, NULL, _IOLBF, 0);
    for (int i = 0; i < n_tests; i++) {
        int want = argc < 2;
        for (int a = 1; a < argc && !want; a++)
            want = strstr(tests[i].name, argv[a]) != NULL;
        if (!want)
            continue;
        failed_now = 0;
        tests[i].fn();
        clean_tmpdir();
        printf("%s %s\n", failed_now ? "FAIL" : "ok  ", tests[i].name);
        if (failed_now)
            failed++;
        else
            passed++;
    }
    printf("SUMMARY passed=%d failed=%d\n", passed, failed);
    return failed ? 1 : 0;
}

const char *c5t_json(const char *s)
{
    static char buf[8192];
    size_t i;
    for (i = 0; s[i] && i < sizeof buf - 1; i++)
        buf[i] = s[i] == '\'' ? '"' : s[i];
    buf[i] = 0;
    return buf;
}

int c5t_write_file(const char *path, const char *header, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    int ok = (!header || fputs(header, f) >= 0) && (n == 0 || fwrite(data, 1, n, f) == n);
    return (fclose(f) == 0 && ok) ? 0 : -1;
}
