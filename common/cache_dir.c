/* cube5's cache folder (cache_dir.h). */
#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include "atomic_file.h"
#include "cache_dir.h"
#include "supervol.h"

#define FREE_MARGIN ((size_t)1 << 30)

int c5_cache_dir(char *out, size_t n)
{
    const char *d = getenv("C5_CACHE_DIR"), *x = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    if (d && (!*d || !strcmp(d, "off")))
        return -1;
    if (d)
        snprintf(out, n, "%s", d);
    else if (x && *x)
        snprintf(out, n, "%s/cube5", x);
    else if (home && *home)
        snprintf(out, n, "%s/.cache/cube5", home);
    else
        return -1;
    c5_err e;
    return c5_output_dir(out, &e);
}

uint64_t c5_cache_hash(const char *s)
{
    uint64_t h = 0xcbf29ce484222325u; /* FNV-1a */
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 0x100000001b3u;
    return h;
}

int c5_cache_max(size_t *out, c5_err *err) { return c5_env_bytes("C5_CACHE_MAX", C5_CACHE_MAX_DEFAULT, out, err); }

typedef struct {
    char name[256];
    size_t bytes;
    struct timespec used;
} entry;

static int older(const void *a, const void *b)
{
    const entry *x = a, *y = b;
    if (x->used.tv_sec != y->used.tv_sec)
        return x->used.tv_sec < y->used.tv_sec ? -1 : 1;
    return (x->used.tv_nsec > y->used.tv_nsec) - (x->used.tv_nsec < y->used.tv_nsec);
}

/* cube5's own files in the folder: ranges-*.bin and cells-*.bin (nothing else is touched) */
static int ours(const char *n)
{
    size_t l = strlen(n);
    return l > 4 && !strcmp(n + l - 4, ".bin") && (!strncmp(n, "ranges-", 7) || !strncmp(n, "cells-", 6));
}

int c5_cache_make_room(const char *dir, size_t bytes)
{
    size_t max;
    c5_err e;
    struct statvfs fs;
    if (c5_cache_max(&max, &e) != 0 || bytes > max)
        return -1;
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    entry *list = NULL;
    size_t n = 0, cap = 0, total = 0;
    struct dirent *de;
    while ((de = readdir(d)) != NULL) {
        struct stat st;
        if (!ours(de->d_name) || fstatat(dirfd(d), de->d_name, &st, 0) != 0 || !S_ISREG(st.st_mode))
            continue;
        if (n == cap) {
            entry *p = realloc(list, (cap = cap ? 2 * cap : 16) * sizeof *list);
            if (!p)
                break;
            list = p;
        }
        snprintf(list[n].name, sizeof list[n].name, "%s", de->d_name);
        list[n].bytes = (size_t)st.st_size;
        list[n].used = st.st_mtim;
        total += list[n++].bytes;
    }
    if (n > 1)
        qsort(list, n, sizeof *list, older);
    for (size_t i = 0; i < n && total + bytes > max; i++)
        if (unlinkat(dirfd(d), list[i].name, 0) == 0)
            total -= list[i].bytes;
    int rc = total + bytes <= max ? 0 : -1;
    if (rc == 0 && statvfs(dir, &fs) == 0 && (size_t)fs.f_bavail * fs.f_frsize < bytes + FREE_MARGIN)
        rc = -1;
    free(list);
    closedir(d);
    return rc;
}

void c5_cache_touch(const char *path)
{
    utimensat(AT_FDCWD, path, NULL, 0);
}
